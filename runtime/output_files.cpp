#include "output_files.h"

#include "system/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace quantum::runtime {
namespace fs = std::filesystem;

namespace {

std::string error_text(int error) { return std::strerror(error); }

const char* const kNotAFile = ", not a regular file: an output is written as a file (- writes to standard output)";

// What a file or a folder's files hold on the disk.
uintmax_t size_of(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    const uintmax_t n = fs::file_size(path, ec);
    return ec ? 0 : n;
  }
  uintmax_t n = 0;
  for (auto it = fs::recursive_directory_iterator(path, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec)) n += it->file_size(ec);
  return n;
}

bool ends_gz(const std::string& path) { return path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0; }

}  // namespace

void check_output_file(const std::string& option, const std::string& path) {
  auto refuse = [&](const std::string& why) { throw std::runtime_error(option + " " + path + ": " + why); };
  if (path.empty()) refuse("no file name");
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) refuse("is a folder, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) refuse(std::string("is ") + system::kind_of(status.type()) + kNotAFile);
  const fs::path parent = fs::path(path).parent_path();
  const fs::path folder = parent.empty() ? fs::path(".") : parent;
  if (!fs::exists(folder, ec)) refuse("no folder " + folder.string());
  if (!fs::is_directory(folder, ec)) refuse(folder.string() + " is not a folder");
  // An existing file must be writable itself; a new one needs a writable folder.
  const bool exists = fs::exists(status);
  if (access(exists ? path.c_str() : folder.c_str(), W_OK) != 0) refuse("cannot be written (" + error_text(errno) + ")");
}

void make_output_folder(const std::string& option, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(option + " " + dir.string() + ": cannot make the folder (" + ec.message() + ")");
  if (access(dir.c_str(), W_OK) != 0)
    throw std::runtime_error(option + " " + dir.string() + ": cannot be written (" + error_text(errno) + ")");
}

void check_distinct(std::span<const Output> outputs) {
  // Files that are there compare by identity (a link, "./x" and "x" are one file); new ones by
  // where they would be.
  struct Seen {
    const Output* output;
    fs::path where;
    std::optional<std::pair<dev_t, ino_t>> id;
  };
  std::vector<Seen> seen;
  for (const Output& o : outputs) {
    if (o.path.empty()) continue;
    Seen s{&o, {}, std::nullopt};
    if (o.path != "-") {
      std::error_code ec;
      s.where = fs::weakly_canonical(fs::absolute(o.path, ec), ec);
      struct stat st {};
      if (!o.folder && stat(o.path.c_str(), &st) == 0) s.id = std::pair{st.st_dev, st.st_ino};
    }
    for (const Seen& other : seen) {
      auto refuse = [&](const std::string& why) {
        throw std::runtime_error(o.option + " " + o.path + ": " + why + " " + other.output->option + " " + other.output->path +
                                 ": each would write over or between the other's lines; name two files");
      };
      if ((o.path == "-") != (other.output->path == "-")) continue;
      if (o.path == "-") {
        throw std::runtime_error(o.option + " - and " + other.output->option +
                                 " - both write to standard output: each would write between the other's lines; name a "
                                 "file for one of them");
      }
      if ((s.id && s.id == other.id) || s.where == other.where) refuse("is the same file as");
      const Seen& folder = other.output->folder ? other : s;
      const Seen& file = other.output->folder ? s : other;
      if (folder.output->folder != file.output->folder) {
        const fs::path inside = file.where.lexically_relative(folder.where);
        if (!inside.empty() && *inside.begin() != "..") refuse(&folder == &s ? "holds" : "is inside the folder of");
      }
    }
    seen.push_back(std::move(s));
  }
}

void say_lost(std::ostream& errors, const std::string& shown) {
  errors << "quantum: cannot write to " << shown
         << " (a full disk, a closed pipe?): what follows is lost; the match goes on, and quantum will exit with 1\n";
}

std::string bytes(uintmax_t n) {
  char text[32];
  if (n >= 1000 * 1000) std::snprintf(text, sizeof text, "%.1f MB", double(n) / 1e6);
  else if (n >= 1000) std::snprintf(text, sizeof text, "%.0f KB", double(n) / 1e3);
  else std::snprintf(text, sizeof text, "%ju bytes", n);
  return text;
}

void say_written(std::ostream& out, const Written& w) {
  if (w.path.empty() || w.path == "-") return;
  out << "quantum: wrote " << w.path << ": " << (w.what.empty() ? "" : w.what + ", ") << bytes(size_of(w.path)) << '\n';
}

// The one thread that makes every DurableFile's writes durable, each within kSyncEvery of being
// written. A frame only sets its file's dirty flag; the sync, which may wait for the disk, is here.
class DiskSyncer {
 public:
  static DiskSyncer& get() {
    static DiskSyncer syncer;
    return syncer;
  }
  void add(DurableFile* file) {
    std::lock_guard lock(mutex_);
    files_.push_back(file);
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    wake_.notify_one();
  }
  // Holds the lock a sync holds: once this returns, no sync of `file` is under way or to come.
  void remove(DurableFile* file) {
    std::lock_guard lock(mutex_);
    std::erase(files_, file);
  }
  ~DiskSyncer() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, std::chrono::duration<double>(DurableFile::kSyncEvery));
      for (DurableFile* f : files_)
        if (f->dirty_.exchange(false)) fdatasync(f->fd_);
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<DurableFile*> files_;
  std::thread thread_;
  bool stop_ = false;
};

DurableFile::DurableFile(const std::string& option, const std::string& path) : path_(path) {
  check_output_file(option, path);
  // O_NONBLOCK: a FIFO put there since the check opens at once (or fails) instead of waiting for
  // a reader, and fstat then refuses it.
  fd_ = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_CLOEXEC, 0666);
  if (fd_ < 0) throw std::runtime_error(option + " " + path + ": cannot be written (" + error_text(errno) + ")");
  struct stat st {};
  if (fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw std::runtime_error(option + " " + path + ": is not a regular file" + kNotAFile);
  }
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
  if (ends_gz(path)) {
    // gzip's own fd: closing gz_ closes it, and fd_ stays valid for the syncer until then.
    gz_ = gzdopen(dup(fd_), "wb");
    if (!gz_) {
      ::close(fd_);
      throw std::runtime_error(option + " " + path + ": cannot start its gzip stream");
    }
  }
  DiskSyncer::get().add(this);
}

DurableFile::~DurableFile() { close(); }

bool DurableFile::write(std::string_view bytes) {
  if (!ok_ || fd_ < 0 || bytes.empty()) return ok_;
  if (gz_) {
    ok_ = gzwrite(gz_, bytes.data(), unsigned(bytes.size())) == int(bytes.size()) && gzflush(gz_, Z_SYNC_FLUSH) == Z_OK;
  } else {
    while (!bytes.empty()) {
      const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        ok_ = false;
        break;
      }
      bytes.remove_prefix(size_t(n));
    }
  }
  dirty_ = true;
  return ok_;
}

bool DurableFile::close() {
  if (fd_ < 0) return ok_;
  DiskSyncer::get().remove(this);
  if (gz_ && gzclose(gz_) != Z_OK) ok_ = false;
  gz_ = nullptr;
  if (fdatasync(fd_) != 0 && errno != EINVAL) ok_ = false;
  if (::close(fd_) != 0) ok_ = false;
  fd_ = -1;
  return ok_;
}

LineFile::Pending::int_type LineFile::Pending::overflow(int_type c) {
  if (!traits_type::eq_int_type(c, traits_type::eof())) text.push_back(traits_type::to_char_type(c));
  return traits_type::not_eof(c);
}

std::streamsize LineFile::Pending::xsputn(const char* s, std::streamsize n) {
  text.append(s, size_t(n));
  return n;
}

LineFile::LineFile(const std::string& option, const std::string& path) : path_(path) {
  if (path.empty()) return;
  // A frame's lines fit without growing; a decision line of a crowded draw is a few kilobytes.
  pending_.text.reserve(size_t(1) << 16);
  if (path != "-") file_ = std::make_unique<DurableFile>(option, path);
}

LineFile::~LineFile() {
  try {
    close();
  } catch (const std::exception&) {  // said by say_failure() while the match went on
  }
}

bool LineFile::hand_over(std::string_view bytes) {
  if (file_) return file_->write(bytes);
  // Through std::cout, so that the lines keep their order with whatever else goes there.
  std::cout.write(bytes.data(), std::streamsize(bytes.size()));
  return bool(std::cout.flush());
}

void LineFile::commit() {
  std::string& text = pending_.text;
  const size_t end = text.rfind('\n');
  if (end == std::string::npos) return;
  const std::string_view lines = std::string_view(text).substr(0, end + 1);
  if (ok_) ok_ = hand_over(lines);
  lines_ += size_t(std::count(lines.begin(), lines.end(), '\n'));
  text.erase(0, end + 1);
}

void LineFile::close() {
  if (path_.empty() || closed_) return;
  closed_ = true;
  commit();
  if (!pending_.text.empty() && ok_) ok_ = hand_over(pending_.text), ++lines_;
  pending_.text.clear();
  if (file_ && !file_->close()) ok_ = false;
  if (!ok_) throw std::runtime_error("could not write every line to " + shown());
}

std::string LineFile::shown() const { return path_ == "-" ? "stdout" : path_; }

std::optional<Written> LineFile::written() const {
  if (!file_ || !closed_ || !ok_) return std::nullopt;
  return Written{path_, std::to_string(lines_) + " lines"};
}

void LineFile::say_failure(std::ostream& errors) {
  if (ok_ || told_) return;
  told_ = true;
  say_lost(errors, shown());
}

LineReader::LineReader(const std::string& path, size_t longest) : path_(path), longest_(longest), block_(1 << 16, '\0') {
  std::string why;
  const int fd = system::open_regular(path, why);
  if (fd < 0) throw std::runtime_error(path + ": " + why);
  file_ = gzdopen(fd, "rb");
  if (!file_) {
    ::close(fd);
    throw std::runtime_error(path + ": cannot be read");
  }
}

LineReader::~LineReader() {
  if (file_) gzclose(file_);
}

bool LineReader::fill() {
  const int n = gzread(file_, block_.data(), unsigned(block_.size()));
  int error = Z_OK;
  const char* message = gzerror(file_, &error);
  // A compressed stream that stops short is what a killed match leaves: read up to there.
  if (error == Z_BUF_ERROR) stream_cut_ = true;
  else if (n < 0 || (error != Z_OK && error != Z_STREAM_END))
    throw std::runtime_error(path_ + ": cannot be read (" + (error == Z_ERRNO ? error_text(errno) : message) + ")");
  at_ = 0, end_ = size_t(std::max(n, 0));
  return end_ > 0;
}

bool LineReader::next(std::string& line) {
  line.clear();
  for (;;) {
    if (at_ == end_ && !fill()) {
      torn_bytes_ = line.size();
      line.clear();
      return false;
    }
    const char* from = block_.data() + at_;
    const char* newline = static_cast<const char*>(std::memchr(from, '\n', end_ - at_));
    const size_t n = newline ? size_t(newline - from) : end_ - at_;
    if (line.size() + n > longest_)
      throw std::runtime_error(path_ + ":" + std::to_string(number_ + 1) + ": a line longer than " +
                               std::to_string(longest_ >> 20) + " MB: not a log");
    line.append(from, n);
    at_ += n + (newline ? 1 : 0);
    if (newline) {
      ++number_;
      return true;
    }
  }
}

std::string LineReader::torn() const {
  if (torn_bytes_ == 0 && !stream_cut_) return "";
  const std::string where = path_ + ":" + std::to_string(number_ + 1) + ": ";
  if (torn_bytes_ == 0) return where + "the compressed stream stops short (a match stopped while writing it): read up to there";
  return where + "the last line is cut short after " + std::to_string(torn_bytes_) +
         " bytes (a match stopped while writing it): left out";
}

}  // namespace quantum::runtime
