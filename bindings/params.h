// Settings a user hands a sport's scripts from the command line (`--param length=40`): the field
// and the sport read them with `param(name, default)`, so one set of files serves a school gym
// and a full hall. A parameter that no script reads is an error: a typo, or the wrong sport.
#pragma once

#include <lua.hpp>

#include <map>
#include <string>
#include <vector>

namespace quantum::lua {

class Params {
 public:
  Params() = default;
  // "name=value" pairs; the last of a name counts. Throws std::invalid_argument for a pair
  // without '=' or a name that is not lower-case letters, digits and '_'.
  explicit Params(const std::vector<std::string>& pairs);

  // Sets `param` in the script environment table on top of L's stack. The Params must outlive
  // the state. param(name, default) returns the value given for name, as a number, boolean or
  // string like the default (an error when it does not read as one), or the default.
  void install(lua_State* L);

  // Throws std::invalid_argument naming a given parameter that no script has read, with the
  // ones `sport` did read.
  void check_read(const std::string& sport) const;

  const std::map<std::string, std::string>& given() const { return given_; }
  // "name=value" for each, in name order: what the command line would say.
  std::vector<std::string> pairs() const;

  // For the Lua function: the value of `name` (noted as read, with the default the script gave,
  // as text), or null when none was given.
  const std::string* read(const std::string& name, std::string default_text);
  // Every parameter the scripts read so far, with its default: what `quantum sports` lists.
  const std::map<std::string, std::string>& read() const { return read_; }

 private:
  std::map<std::string, std::string> given_;
  std::map<std::string, std::string> read_;
};

}  // namespace quantum::lua
