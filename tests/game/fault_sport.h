// What the Fault* tests of scripts share: a folder of their own (no fixed /tmp path), a shipped
// sport with a piece of hostile Lua before its `return sport`, the line of that Lua a test names,
// and a session played with it.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hostile_support.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum::fault {

namespace fs = std::filesystem;

// A folder made for one test (mkdtemp), removed with what it holds when the test is done.
struct TempFolder {
  fs::path path;
  TempFolder() {
    std::string name = (fs::temp_directory_path() / "quantum_fault_XXXXXX").string();
    if (!mkdtemp(name.data())) ADD_FAILURE() << "mkdtemp: " << name;
    path = name;
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
};

// rules/<sport> with `lua` run before its `return sport`, in `folder`; returns sport.lua's path.
inline std::string sport_with(const fs::path& folder, const std::string& sport, const std::string& lua) {
  const fs::path rules = fs::path(QUANTUM_SOURCE_DIR) / "rules" / sport;
  fs::copy_file(rules / "field.lua", folder / "field.lua");
  hostile::write_with_before_return(rules / "sport.lua", folder / "sport.lua", lua);
  return (folder / "sport.lua").string();
}

// "file:N: ", N the line of `file` that holds `text` (0 when none does).
inline std::string place_of(const std::string& file, const std::string& text) {
  std::ifstream in(file);
  int n = 0;
  for (std::string line; std::getline(in, line);)
    if (++n, line.find(text) != std::string::npos) return file + ":" + std::to_string(n) + ": ";
  return file + ":0: ";
}

// A session of the sport in `folder`, its players simulated, `seconds` long.
struct Played {
  std::string errors;  // what the session told on its error stream
  int rule_errors = 0;
};

inline Played play(const fs::path& folder, double seconds = 4) {
  runtime::SessionOptions o;
  o.sport = folder.string();
  o.seconds = seconds;
  o.particles = 300;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
  return {errors.str(), session.rule_errors()};
}

// The lines of `text` that start with `prefix`.
inline std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with(prefix)) out.push_back(line);
  return out;
}

}  // namespace quantum::fault
