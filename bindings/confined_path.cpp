#include "confined_path.h"

#include <algorithm>
#include <system_error>

#include "lua_reader.h"
#include "system/regular_file.h"

namespace quantum::lua {
namespace fs = std::filesystem;
namespace {

bool below(const fs::path& file, const fs::path& folder) {
  const fs::path inside = file.lexically_relative(folder);
  return !inside.empty() && *inside.begin() != "..";
}

// Where `file` really is, every symlink on the way followed; empty when that cannot be told.
fs::path real_place(const fs::path& file) {
  std::error_code error;
  fs::path real = fs::weakly_canonical(file, error);
  return error ? fs::path() : real;
}

}  // namespace

fs::path confined_path(const std::vector<fs::path>& folders, const std::string& name, const std::string& key,
                       std::string& looked) {
  const fs::path relative(name);
  const std::string quoted = "'" + name + "'";
  if (name.empty()) throw ReadError(key, "'' is not a file name");
  if (relative.has_root_path())
    throw ReadError(key, quoted + ": an absolute path is refused: a sport names its files relative to its folder");
  if (std::find(relative.begin(), relative.end(), "..") != relative.end())
    throw ReadError(key, quoted + ": '..' is refused: a sport names files inside its folder");
  for (const fs::path& folder : folders) {
    const fs::path file = folder / relative;
    looked += (looked.empty() ? "" : ", ") + file.string();
    if (const std::string why = system::not_a_regular_file(file); !why.empty()) throw ReadError(key, why);
    std::error_code error;
    if (!fs::exists(file, error)) continue;
    const fs::path real = real_place(file);
    const bool confined = std::any_of(folders.begin(), folders.end(), [&](const fs::path& allowed) {
      const fs::path real_folder = real_place(allowed);
      return !real.empty() && !real_folder.empty() && below(real, real_folder);
    });
    if (!confined)
      throw ReadError(key, file.string() + " leads out of the folders a sport may read (to " + real.string() + ")");
    return file;
  }
  return {};
}

}  // namespace quantum::lua
