// How often a phrase occurs in what a command or a session said: a warning told once, a line
// drawn twice.
#pragma once

#include <string>

namespace quantum::test {

inline int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace quantum::test
