#include "json_lines.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "system/utf8.h"

namespace quantum::runtime {

namespace {

double rounded(double v) { return std::round(v * 1e6) / 1e6; }

}  // namespace

JsonLine::JsonLine(std::ostream& out) : out_(out) {
  out_ << '{';
  open_[0] = '}', first_[0] = true, depth_ = 1;
}

void JsonLine::key(const char* name) {
  if (!first_[depth_ - 1]) out_ << ',';
  first_[depth_ - 1] = false;
  if (!name) return;  // an array's item
  text(name);
  out_ << ':';
}

void JsonLine::text(std::string_view s) {
  out_ << '"';
  for (size_t at = 0; at < s.size(); ++at) {
    const char c = s[at];
    // JSON is UTF-8: a byte that is not (a run-time value may hold any) is written as U+FFFD.
    if (const size_t n = utf8::sequence_at(s, at); n != 1) {
      out_ << (n == 0 ? std::string_view("\xEF\xBF\xBD") : s.substr(at, n));
      at += n == 0 ? 0 : n - 1;
      continue;
    }
    switch (c) {
      case '"': out_ << "\\\""; break;
      case '\\': out_ << "\\\\"; break;
      case '\n': out_ << "\\n"; break;
      case '\t': out_ << "\\t"; break;
      case '\r': out_ << "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
          out_ << buf;
        } else {
          out_ << c;
        }
    }
  }
  out_ << '"';
}

JsonLine& JsonLine::field(const char* name, std::string_view s) {
  key(name);
  text(s);
  return *this;
}

JsonLine& JsonLine::field(const char* name, double number) {
  key(name);
  char buf[32];
  const double v = rounded(number);
  // JSON has no NaN or infinity; a value that is not a number is written as null.
  if (std::isfinite(v)) std::snprintf(buf, sizeof buf, "%.15g", v == 0 ? 0.0 : v);
  else std::snprintf(buf, sizeof buf, "null");
  out_ << buf;
  return *this;
}

JsonLine& JsonLine::field(const char* name, bool value) {
  key(name);
  out_ << (value ? "true" : "false");
  return *this;
}

JsonLine& JsonLine::exact(const char* name, double number) {
  key(name);
  char buf[32];
  if (!std::isfinite(number)) {
    out_ << "null";
    return *this;
  }
  const char* end = std::to_chars(buf, buf + sizeof buf, number == 0 ? 0.0 : number).ptr;
  out_ << std::string_view(buf, size_t(end - buf));
  return *this;
}

JsonLine& JsonLine::field(const char* name, uint64_t number) {
  key(name);
  out_ << number;
  return *this;
}

JsonLine& JsonLine::array(const char* name) {
  key(name);
  out_ << '[';
  open_[depth_] = ']', first_[depth_] = true, ++depth_;
  return *this;
}

JsonLine& JsonLine::object(const char* name) {
  key(name);
  out_ << '{';
  open_[depth_] = '}', first_[depth_] = true, ++depth_;
  return *this;
}

JsonLine& JsonLine::item(std::string_view s) {
  key(nullptr);
  text(s);
  return *this;
}

JsonLine& JsonLine::close() {
  if (depth_ > 1) out_ << open_[--depth_];
  return *this;
}

void JsonLine::end() {
  while (depth_ > 0) out_ << open_[--depth_];
  out_ << '\n';
}

}  // namespace quantum::runtime
