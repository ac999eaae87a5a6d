// `quantum test`: runs Lua rule specs (*_spec.lua, busted's describe/it/assert) inside the
// engine's own LuaJIT, with the scenario API of bindings/wrap_scenario.h.
#pragma once

#include <string>
#include <vector>

namespace quantum::tools {

// Runs the specs under `paths` (files or folders; none: rules/). Returns the process exit code:
// 0 when every spec passed. busted itself exits the process with the failure count otherwise.
int run_specs(const std::vector<std::string>& paths);

}  // namespace quantum::tools
