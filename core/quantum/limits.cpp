#include "quantum/limits.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace quantum::limits {

namespace {

// A bound as people write it: 1000, 0.1, 1.6, and a million or more in powers of ten as 1e6.
std::string bound_text(double v) {
  const double power = std::log10(std::abs(v));
  if (std::abs(v) >= 1e6 && power == std::round(power)) return (v < 0 ? "-1e" : "1e") + std::to_string(int(power));
  return number_text(v);
}

}  // namespace

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string interval(const Range& r) {
  return (r.lo_open ? "(" : "[") + bound_text(r.lo) + ", " + bound_text(r.hi) + (r.hi_open ? ")" : "]");
}

std::string stated(const Range& r) { return *r.unit ? interval(r) + " " + r.unit : interval(r); }

std::string must_be_in(const Range& r, double got) { return "must be in " + stated(r) + ", got " + number_text(got); }

void check(const Range& r, double v, std::string_view what) {
  if (!r.contains(v)) throw std::invalid_argument(std::string(what) + " " + must_be_in(r, v));
}

}  // namespace quantum::limits
