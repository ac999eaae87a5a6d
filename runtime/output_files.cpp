#include "output_files.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace quantum::runtime {
namespace fs = std::filesystem;

void check_output_file(const std::string& option, const std::string& path) {
  auto refuse = [&](const std::string& why) { throw std::runtime_error(option + " " + path + ": " + why); };
  if (path.empty()) refuse("no file name");
  std::error_code ec;
  if (fs::is_directory(path, ec)) refuse("is a folder, not a file");
  const fs::path parent = fs::path(path).parent_path();
  const fs::path folder = parent.empty() ? fs::path(".") : parent;
  if (!fs::exists(folder, ec)) refuse("no folder " + folder.string());
  if (!fs::is_directory(folder, ec)) refuse(folder.string() + " is not a folder");
  // An existing file must be writable itself; a new one needs a writable folder.
  const bool exists = fs::exists(path, ec);
  if (access(exists ? path.c_str() : folder.c_str(), W_OK) != 0) refuse(std::string("cannot be written (") + std::strerror(errno) + ")");
}

void make_output_folder(const std::string& option, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(option + " " + dir.string() + ": cannot make the folder (" + ec.message() + ")");
  if (access(dir.c_str(), W_OK) != 0)
    throw std::runtime_error(option + " " + dir.string() + ": cannot be written (" + std::strerror(errno) + ")");
}

void say_lost(std::ostream& errors, const std::string& shown) {
  errors << "quantum: cannot write to " << shown
         << " (a full disk?): what follows is lost; the match goes on, and quantum will exit with 1\n";
}

}  // namespace quantum::runtime
