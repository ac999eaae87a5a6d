// JSON lines, written straight to a stream: one object per line, numbers rounded to micrometres
// and microseconds (plenty for a field, and logs stay diff-able) unless written exact. No allocation, so a match can
// log every event from its frame loop.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>

namespace quantum::runtime {

// One line: JsonLine(out).field("t", 1.5).array("said").item("Goal!").close().end().
class JsonLine {
 public:
  explicit JsonLine(std::ostream& out);
  JsonLine& field(const char* key, std::string_view text);
  JsonLine& field(const char* key, const char* text) { return field(key, std::string_view(text)); }
  JsonLine& field(const char* key, double number);
  JsonLine& field(const char* key, uint64_t number);
  JsonLine& field(const char* key, int number) { return field(key, uint64_t(number)); }
  JsonLine& field(const char* key, bool value);
  // A number in full: the shortest decimal that reads back as the same double (the decision log,
  // which a checker recomputes); with no key, as an array's next item. Not finite: null.
  JsonLine& exact(const char* key, double number);
  JsonLine& exact(double number) { return exact(nullptr, number); }
  // Opens an array or an object as the value of `key` (or, inside an array, as its next item).
  JsonLine& array(const char* key = nullptr);
  JsonLine& object(const char* key = nullptr);
  JsonLine& item(std::string_view text);
  JsonLine& close();  // the innermost open array or object
  void end();         // closes everything and ends the line

 private:
  void key(const char* name);
  void text(std::string_view s);
  std::ostream& out_;
  char open_[8];   // ']' or '}' for each open level
  bool first_[8];  // nothing written in that level yet
  int depth_ = 0;
};

}  // namespace quantum::runtime
