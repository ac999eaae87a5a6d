// Reads a field file (rules/<sport>/field.lua) into the quantum core's Field.
#pragma once

#include <string>

#include "params.h"
#include "quantum/field.h"

namespace quantum::lua {

// `path` is a field file, or a sport holding field.lua: its folder or its name (engine_paths.h). The file runs as text-only Lua in
// a sandbox (math, string, table; no require) with an instruction and a memory budget, and must return a
// table; `param(name, default)` reads `params` (none when null). Throws FieldError whose message
// names the file and the place, e.g.
// "rules/airhockey/field.lua: walls[2].points[3]: expected a number for y, got string".
Field load_field(const std::string& path, Params* params = nullptr);

// The file load_field reads for `path`.
std::string field_file(const std::string& path);

}  // namespace quantum::lua
