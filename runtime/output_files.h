// The files a match writes (--events, --decisions, --record, --audio wav:, --video, --snapshot,
// --csv, --plot): checked before anything plays, so a typo costs a second and not a match, and
// one wording for a write that fails while the match goes on.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace quantum::runtime {

// Throws std::runtime_error "OPTION PATH: why" when no file can be written at `path`: its folder
// is missing or not writable, or `path` is a folder. Creates nothing.
void check_output_file(const std::string& option, const std::string& path);

// Creates `dir` and its parents; throws std::runtime_error "OPTION DIR: why" when it cannot.
void make_output_folder(const std::string& option, const std::filesystem::path& dir);

// The line a session writes to `errors`, once, when a write to `shown` first fails (a full disk).
void say_lost(std::ostream& errors, const std::string& shown);

}  // namespace quantum::runtime
