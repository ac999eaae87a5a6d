// `quantum test`: runs Lua rule specs (*_spec.lua, busted's describe/it/assert) inside the
// engine's own LuaJIT, with the scenario API of tools/wrap_scenario.h.
#pragma once

#include <string>
#include <vector>

namespace quantum::tools {

// Runs the specs under `paths` (files or folders; none: rules/), printing each spec file's name
// and result as it runs, then the total time. Returns the process exit code: 0 when every spec
// passed, 2 when any failed, 1 when busted could not run (or a path does not exist).
int run_specs(const std::vector<std::string>& paths);

}  // namespace quantum::tools
