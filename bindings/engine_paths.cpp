#include "engine_paths.h"

#include <algorithm>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <system_error>

#include "lua_reader.h"

namespace quantum::lua {
namespace fs = std::filesystem;
namespace {

bool is_data_folder(const fs::path& folder) {
  std::error_code error;
  return fs::is_directory(folder / "rules" / "lib", error);
}

bool is_sport_folder(const fs::path& folder) {
  std::error_code error;
  return fs::is_regular_file(folder / "sport.lua", error);
}

// The sport folders directly inside `folder`, by name: a folder that cannot be read has none.
std::vector<fs::path> sport_folders_in(const fs::path& folder) {
  std::vector<fs::path> found;
  std::error_code error;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error))
    if (is_sport_folder(it->path())) found.push_back(it->path());
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<fs::path> quantum_path() {
  std::vector<fs::path> folders;
  const char* env = std::getenv("QUANTUM_PATH");
  if (!env) return folders;
  const std::string list = env;
  for (size_t start = 0; start <= list.size();) {
    const size_t colon = std::min(list.find(':', start), list.size());
    if (colon > start) folders.emplace_back(list.substr(start, colon - start));
    start = colon + 1;
  }
  return folders;
}

}  // namespace

fs::path engine_data_folder() {
  if (const char* env = std::getenv("QUANTUM_DATA"); env && *env) {
    if (!is_data_folder(env))
      throw std::runtime_error(std::string("QUANTUM_DATA=") + env + ": not the engine's data folder (it has no rules/lib)");
    return env;
  }
  // /proc/self/exe, not argv[0]: the program may have been started through PATH or a link.
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  for (fs::path dir = program.parent_path(); !error && !dir.empty(); dir = dir.parent_path()) {
    if (is_data_folder(dir / "share" / "quantum")) return dir / "share" / "quantum";
    if (dir == dir.root_path()) break;
  }
  throw std::runtime_error("the engine's data (share/quantum: its power-ups, Lua helpers, sports and sounds) is not in any "
                           "folder above " + program.string() + "; install the engine (cmake --install, or its .deb) "
                           "or set QUANTUM_DATA to its share/quantum folder");
}

fs::path engine_rules_folder() { return engine_data_folder() / "rules"; }

fs::path engine_sounds_folder() { return engine_data_folder() / "sounds"; }

std::vector<SportPlace> sports_in_reach() {
  std::vector<fs::path> folders = sport_folders_in(".");
  for (const fs::path& entry : quantum_path()) {
    if (is_sport_folder(entry)) {
      folders.push_back(entry);
      continue;
    }
    const std::vector<fs::path> inside = sport_folders_in(entry);
    folders.insert(folders.end(), inside.begin(), inside.end());
  }
  const std::vector<fs::path> shipped = sport_folders_in(engine_rules_folder());
  folders.insert(folders.end(), shipped.begin(), shipped.end());

  std::vector<SportPlace> places;
  std::set<std::string> seen;
  for (const fs::path& folder : folders) {
    const fs::path normal = folder.lexically_normal();
    std::string name = (normal.filename().empty() ? normal.parent_path() : normal).filename().string();
    const bool shadowed = !seen.insert(name).second;
    places.push_back({std::move(name), normal, shadowed});
  }
  return places;
}

bool is_sport_name(const std::string& given) {
  return given.find('/') == std::string::npos && given != "." && given != "..";
}

fs::path find_sport(const std::string& given) {
  if (given.empty()) throw std::invalid_argument("a sport is named by its folder or its name, not ''");
  std::error_code error;
  if (!is_sport_name(given)) {
    if (fs::is_directory(given, error)) return given;
    throw std::invalid_argument(given + ": no such sport folder");
  }
  const std::vector<SportPlace> places = sports_in_reach();
  for (const SportPlace& p : places)
    if (p.name == given && !p.shadowed) return p.folder;
  // A folder of that name here, without sport.lua: the sport's loader says what is missing.
  if (fs::is_directory(given, error)) return given;
  std::vector<std::string> names;
  for (const SportPlace& p : places)
    if (!p.shadowed) names.push_back(p.name);
  // A folder full of other things (a /tmp) would make the list of every name unreadable.
  const std::string near = nearest(given, names);
  std::string message = "unknown sport '" + given + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)");
  if (names.size() <= 12) {
    message += "; known: ";
    for (size_t k = 0; k < names.size(); ++k) message += (k ? ", " : "") + names[k];
  }
  throw std::invalid_argument(message + "; a sport is a folder here, in QUANTUM_PATH or among the engine's (quantum sports "
                                        "lists them)");
}

}  // namespace quantum::lua
