// A log file's lines, read and written whole: the tests that audit logs tamper with them.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace quantum::test {

inline std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

inline void write_lines(const std::filesystem::path& file, const std::vector<std::string>& lines) {
  std::ofstream out(file);
  for (const std::string& line : lines) out << line << '\n';
}

}  // namespace quantum::test
