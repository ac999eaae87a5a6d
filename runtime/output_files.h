// The files a match writes (--events, --decisions, --record, --audio wav:, --video, --snapshot,
// --csv, --plot): checked before anything plays, so a typo costs a second and not a match; written
// so that a kill, a crash or a power cut leaves them whole; one wording for a write that fails
// while the match goes on (docs/reliability.md, "Faults"), and one for a file written whole.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <streambuf>
#include <string>

#include <zlib.h>

namespace quantum::runtime {

// Throws std::runtime_error "OPTION PATH: why" when no file can be written at `path`: its folder
// is missing or not writable, `path` is a folder, or it is there and not a regular file (a FIFO
// would hold the match before its start until someone reads it, a device would take what was
// meant for a file). Creates nothing.
void check_output_file(const std::string& option, const std::string& path);

// Creates `dir` and its parents; throws std::runtime_error "OPTION DIR: why" when it cannot.
void make_output_folder(const std::string& option, const std::filesystem::path& dir);

// One output a command writes: the option that names it, and a file, a folder (--record) or "-"
// for standard output.
struct Output {
  std::string option, path;
  bool folder = false;
};

// Throws std::runtime_error naming both options when two outputs are one file (the same path, or
// links to one file), a file lies in an output folder, or both are standard output: each would
// write over or between the other's lines. Outputs with an empty path are left out.
void check_distinct(std::span<const Output> outputs);

// The line a session writes to `errors`, once, when a write to `shown` first fails (a full disk).
void say_lost(std::ostream& errors, const std::string& shown);

// An output a command wrote whole: its path (a file or a folder) and what it holds ("6.0 s, 180
// frames, 1100x880").
struct Written {
  std::string path, what;
};

// The line that confirms an output: "quantum: wrote match.mp4: 6.0 s, 180 frames, 1100x880, 1.2
// MB", its size on the disk added (a folder's being its files'). Nothing for standard output ("-").
void say_written(std::ostream& out, const Written& written);

// "1.2 MB", "45 KB", "312 bytes".
std::string bytes(uintmax_t n);

// A file that a kill, a crash or a power cut leaves whole up to the last write: each write()
// hands its bytes to the file at once, in one system call, and a thread of the engine's makes
// them durable (fdatasync) within kSyncEvery, off the frame's thread (a disk's flush can take
// longer than a frame). A path ending in .gz is written gzip-compressed, each write flushed to a
// byte boundary so that everything written so far can be read back from what is on the disk.
class DurableFile {
 public:
  static constexpr double kSyncEvery = 0.1;  // s: the most of a match a power cut may cost

  // Creates (or empties) `path`; throws std::runtime_error naming `option` when it cannot, or when
  // `path` is not a regular file (checked on what was opened: nothing blocks on a FIFO).
  DurableFile(const std::string& option, const std::string& path);
  ~DurableFile();
  DurableFile(const DurableFile&) = delete;
  DurableFile& operator=(const DurableFile&) = delete;

  // False once a write has failed; what follows is not written.
  bool write(std::string_view bytes);
  bool ok() const { return ok_; }
  // Flushes, syncs and closes; false when anything could not be written.
  bool close();
  const std::string& path() const { return path_; }

 private:
  friend class DiskSyncer;
  std::string path_;
  int fd_ = -1;
  gzFile gz_ = nullptr;
  bool ok_ = true;
  std::atomic<bool> dirty_{false};  // written since the last sync
};

// Where lines go for an option such as --events: nowhere (""), standard output ("-"), or a
// DurableFile created now. Lines written to stream() wait in memory until commit() hands every
// whole one to the file, so that the file ends at a line boundary whenever the process stops;
// a session commits at the end of every frame. Allocates only while a frame writes more than any
// frame before it.
class LineFile {
 public:
  LineFile(const std::string& option, const std::string& path);
  ~LineFile();
  std::ostream* stream() { return path_.empty() ? nullptr : &out_; }
  // Hands the whole lines written since the last commit to the file.
  void commit();
  // Commits everything; throws std::runtime_error naming the file when anything could not be written.
  void close();
  // Once, as soon as a write has failed (a full disk, a closed pipe): a line to `errors` that says so.
  void say_failure(std::ostream& errors);
  // After close(): the file (not standard output), when it got every line, and how many ("312 lines").
  std::optional<Written> written() const;

 private:
  // The lines waiting for commit(): an ostream's buffer that grows instead of flushing.
  class Pending : public std::streambuf {
   public:
    std::string text;

   protected:
    int_type overflow(int_type c) override;
    std::streamsize xsputn(const char* s, std::streamsize n) override;
  };
  bool hand_over(std::string_view bytes);
  std::string shown() const;  // the path, or "stdout" for "-"

  std::string path_;
  Pending pending_;
  std::ostream out_{&pending_};
  std::unique_ptr<DurableFile> file_;
  size_t lines_ = 0;  // handed to the file
  bool ok_ = true, told_ = false, closed_ = false;
};

// Reads a file line by line, plain or gzip-compressed (by its content, whatever its name), in
// blocks. A last line that was cut short (a process killed while writing it, a compressed stream
// that stops) is left out and said by torn(): a log written by a match that was killed is read up
// to its last whole line. Throws std::runtime_error naming the file when it cannot be read, or a
// line is longer than `longest` bytes (no log's is: a file that is no log).
class LineReader {
 public:
  explicit LineReader(const std::string& path, size_t longest = size_t(16) << 20);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  // The next whole line, without its newline; false at the end.
  bool next(std::string& line);
  size_t number() const { return number_; }  // of the line next() gave last
  // After the end: "PATH:N: the last line is cut short (...): left out", or "" when the file ended whole.
  std::string torn() const;

 private:
  bool fill();
  std::string path_;
  size_t longest_;
  gzFile file_ = nullptr;
  std::string block_;
  size_t at_ = 0, end_ = 0, number_ = 0, torn_bytes_ = 0;
  bool stream_cut_ = false;
};

}  // namespace quantum::runtime
