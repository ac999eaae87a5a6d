#include "params.h"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "lua_reader.h"
#include "lua_wrap.h"

namespace quantum::lua {
namespace {

bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

std::string default_text(lua_State* L, int idx) {
  switch (lua_type(L, idx)) {
    case LUA_TNUMBER: {
      char text[32];
      std::snprintf(text, sizeof text, "%.15g", lua_tonumber(L, idx));
      return text;
    }
    case LUA_TBOOLEAN: return lua_toboolean(L, idx) ? "true" : "false";
    case LUA_TSTRING: return lua_tostring(L, idx);
    default: return "";
  }
}

int param(lua_State* L) {
  const std::string name = check_string(L, 1);
  const std::string* value = upvalue_self<Params>(L).read(name, default_text(L, 2));
  if (!value) {
    lua_settop(L, 2);  // the default, or nil
    return 1;
  }
  switch (lua_type(L, 2)) {
    case LUA_TNUMBER: {
      char* end = nullptr;
      const double v = std::strtod(value->c_str(), &end);
      if (value->empty() || *end != '\0')
        throw ArgError("parameter '" + name + "' must be a number, got '" + *value + "'");
      lua_pushnumber(L, v);
      break;
    }
    case LUA_TBOOLEAN:
      if (*value != "true" && *value != "false")
        throw ArgError("parameter '" + name + "' must be true or false, got '" + *value + "'");
      lua_pushboolean(L, *value == "true");
      break;
    default: lua_pushlstring(L, value->data(), value->size());
  }
  return 1;
}

}  // namespace

Params::Params(const std::vector<std::string>& pairs) {
  for (const std::string& pair : pairs) {
    const size_t eq = pair.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("--param " + pair + ": expected NAME=VALUE");
    const std::string name = pair.substr(0, eq);
    if (!valid_name(name))
      throw std::invalid_argument("--param " + pair + ": a name is lower-case letters, digits and '_'");
    given_[name] = pair.substr(eq + 1);
  }
}

void Params::install(lua_State* L) {
  const int env = lua_gettop(L);
  push_module(L, "", {{"param", guard<param>}}, this);
  lua_getfield(L, -1, "param");
  lua_setfield(L, env, "param");
  lua_pop(L, 1);
}

const std::string* Params::read(const std::string& name, std::string default_text) {
  read_.emplace(name, std::move(default_text));
  const auto it = given_.find(name);
  return it == given_.end() ? nullptr : &it->second;
}

void Params::check_read(const std::string& sport) const {
  std::vector<std::string> known;
  for (const auto& [name, default_text] : read_) known.push_back(name);
  for (const auto& [name, value] : given_) {
    if (read_.count(name)) continue;
    if (known.empty()) throw std::invalid_argument("--param " + name + ": " + sport + " reads no parameters");
    throw std::invalid_argument("--param " + name + ": " + unknown_key(name, known, "parameter") + " in " + sport);
  }
}

std::vector<std::string> Params::pairs() const {
  std::vector<std::string> out;
  for (const auto& [name, value] : given_) out.push_back(name + "=" + value);
  return out;
}

}  // namespace quantum::lua
