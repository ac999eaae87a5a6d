// UTF-8, checked: phrases are refused when they are not UTF-8, and text written to JSON (which
// must be UTF-8) has any invalid byte replaced, since run-time values reach it unchecked.
#pragma once

#include <cstddef>
#include <string_view>

namespace quantum::utf8 {

// The length of the well-formed UTF-8 sequence that starts at s[at] (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF), or 0 when the bytes there are not one.
inline std::size_t sequence_at(std::string_view s, std::size_t at) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[at + k]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the allowed range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF)
    length = 2;
  else if (lead >= 0xE0 && lead <= 0xEF)
    length = 3, low = lead == 0xE0 ? 0xA0 : 0x80, high = lead == 0xED ? 0x9F : 0xBF;
  else if (lead >= 0xF0 && lead <= 0xF4)
    length = 4, low = lead == 0xF0 ? 0x90 : 0x80, high = lead == 0xF4 ? 0x8F : 0xBF;
  else
    return 0;
  if (s.size() - at < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t k = 2; k < length; ++k)
    if ((byte(k) & 0xC0) != 0x80) return 0;
  return length;
}

// Where the first byte that is not UTF-8 is, or std::string_view::npos when all of s is.
inline std::size_t first_invalid(std::string_view s) {
  for (std::size_t at = 0; at < s.size();) {
    const std::size_t n = sequence_at(s, at);
    if (n == 0) return at;
    at += n;
  }
  return std::string_view::npos;
}

}  // namespace quantum::utf8
