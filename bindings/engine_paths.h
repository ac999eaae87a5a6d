// Where the engine's own files are and where a sport named on the command line is found. The
// engine's data (rules/ with its power-ups, Lua helpers and shipped sports; sounds/; markers/)
// is the nearest `share/quantum` above the running program: P/share/quantum once installed
// under P (P/bin/quantum), build/share/quantum in a build folder (links into the checkout), so
// a copy or an install works from any folder. QUANTUM_DATA names another.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace quantum::lua {

// The engine's data folder. Throws std::runtime_error saying where it looked when there is none.
std::filesystem::path engine_data_folder();
// Its rules/ (power-ups, lib/, spec_helpers.lua, the shipped sports) and sounds/.
std::filesystem::path engine_rules_folder();
std::filesystem::path engine_sounds_folder();

// A sport as the user can name it: a folder holding sport.lua.
struct SportPlace {
  std::string name;              // the folder's name: what `quantum play NAME` takes
  std::filesystem::path folder;
  bool shadowed = false;         // an earlier place has a sport of the same name
};

// Every sport a name reaches, in the order names are looked up: the current folder, each folder
// of QUANTUM_PATH (colon-separated: folders of sport folders, or sport folders themselves), the
// engine's shipped sports.
std::vector<SportPlace> sports_in_reach();

// Whether `given` is a sport's name rather than a path: no '/', and not "." or "..".
bool is_sport_name(const std::string& given);

// The folder of the sport `given` names. Given a path (anything with a '/', or "."), that folder;
// given a name, the first sport of that name in sports_in_reach(). Throws std::invalid_argument
// for a path that is no folder, or a name no place has, with the nearest name and the ones known.
std::filesystem::path find_sport(const std::string& given);

}  // namespace quantum::lua
