// Opening a file others made (a Kinect's recording, a match's recording, a file a recording
// names) only when it is a regular file: opening a FIFO that nobody writes blocks, and reading
// a device (/dev/zero) never ends; opening some devices does something by itself.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

namespace quantum::system {

// What a file of `type` is, for a message: "a FIFO", "a directory", "a symbolic link", ...
inline const char* kind_of(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::directory: return "a directory";
    case std::filesystem::file_type::character: return "a character device";
    case std::filesystem::file_type::block: return "a block device";
    case std::filesystem::file_type::fifo: return "a FIFO";
    case std::filesystem::file_type::socket: return "a socket";
    case std::filesystem::file_type::symlink: return "a symbolic link";
    default: return "a special file";
  }
}

// Why `file` may not be opened for reading: "" when it is a regular file or there is none, else
// e.g. "rules/x/pipe.lua is a FIFO, not a regular file". Looks at its type (symlinks followed)
// without opening it: opening a FIFO that nobody writes, or /dev/stdin, blocks.
inline std::string not_a_regular_file(const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  switch (status.type()) {
    case std::filesystem::file_type::regular:
    case std::filesystem::file_type::not_found: return "";
    case std::filesystem::file_type::none: return file.string() + ": " + error.message();
    default: return file.string() + " is " + kind_of(status.type()) + ", not a regular file";
  }
}


// Whether a symlink at `path` itself is followed (a sport may link a file it shares) or refused
// (a recording holds its own files, so a link there can only lead out of it).
enum class Links { Follow, Refuse };

// A read-only descriptor for `path` if it is a regular file, else -1 and `why`, to follow the
// path in a message: "is a FIFO, not a regular file", "does not exist", "is a symbolic link".
// Its type is looked at before it is opened and again once it is (it may have changed between),
// and it is opened without blocking. `size` gets its size.
inline int open_regular(const std::filesystem::path& path, std::string& why, off_t* size = nullptr,
                        Links links = Links::Follow) {
  std::error_code error;
  const std::filesystem::file_status status =
      links == Links::Follow ? std::filesystem::status(path, error) : std::filesystem::symlink_status(path, error);
  if (status.type() == std::filesystem::file_type::not_found) {
    why = "does not exist";
    return -1;
  }
  if (status.type() != std::filesystem::file_type::regular && !error) {
    why = std::string("is ") + kind_of(status.type()) + ", not a regular file";
    return -1;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | (links == Links::Refuse ? O_NOFOLLOW : 0));
  if (fd < 0) {
    why = errno == ENOENT   ? "does not exist"
          : errno == ELOOP  ? "is a symbolic link, not a regular file"
                            : std::string("cannot be opened (") + std::strerror(errno) + ")";
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    why = "is not a regular file";
    return -1;
  }
  if (size) *size = st.st_size;
  return fd;
}

// Closes a descriptor when it goes.
struct FileDescriptor {
  int fd = -1;
  explicit FileDescriptor(int fd) : fd(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace quantum::system
