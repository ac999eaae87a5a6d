// The sports written in Lua, for a session (runtime/sport_source.h): bindings/'s loader and
// scripted rules, with its hot reload, behind the runtime's SportSource. The program layer wires
// the two; neither knows the other.
#pragma once

#include <memory>

#include "scripted_rules.h"
#include "session.h"
#include "sport_source.h"

namespace quantum::tools {

// A runtime::SportLoader: loads request.sport's sport.lua (lua::ScriptedRules), its factors
// overridden, with a lua::Reloader when the request reloads.
std::unique_ptr<runtime::SportSource> lua_sport(const runtime::SportRequest& request);

// The Lua rules a session loaded with lua_sport plays now (a spec's or a benchmark's grant): a
// reload replaces them, so hold no reference across frames.
lua::ScriptedRules& scripted_rules(runtime::Session& session);

}  // namespace quantum::tools
