#include "phrases.h"

#include "quantum/limits.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "system/utf8.h"

namespace quantum::lua {
namespace {

using limits::kMaxPhraseBytes;

std::string longer_than_the_limit(size_t bytes) {
  return "longer than " + std::to_string(kMaxPhraseBytes) + " bytes (" + std::to_string(bytes) + ")";
}

// %[flags][width][.precision]conversion, numbers only: anything else could read past its value.
bool valid_format(std::string_view f) {
  size_t i = 0;
  if (f.empty() || f[i++] != '%') return false;
  while (i < f.size() && std::string_view("-+ 0#").find(f[i]) != std::string_view::npos) ++i;
  for (int digits = 0; i < f.size() && std::isdigit(static_cast<unsigned char>(f[i])); ++i)
    if (++digits > 2) return false;
  if (i < f.size() && f[i] == '.') {
    ++i;
    for (int digits = 0; i < f.size() && std::isdigit(static_cast<unsigned char>(f[i])); ++i)
      if (++digits > 2) return false;
  }
  return i + 1 == f.size() && std::string_view("difeg").find(f[i]) != std::string_view::npos;
}

}  // namespace

PhraseTemplate::PhraseTemplate(std::string_view text) {
  // Checked first, so a hostile template costs one comparison, not a parse.
  if (text.size() > kMaxPhraseBytes) throw std::invalid_argument("the text is " + longer_than_the_limit(text.size()));
  if (const size_t bad = utf8::first_invalid(text); bad != std::string_view::npos)
    throw std::invalid_argument("byte " + std::to_string(bad + 1) + " is not UTF-8 (phrases are UTF-8 text)");
  std::string literal;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') {
      literal += text[i];
      continue;
    }
    const size_t close = text.find('}', i);
    if (close == std::string_view::npos)
      throw std::invalid_argument("'{' at character " + std::to_string(i + 1) + " is never closed");
    const std::string_view inside = text.substr(i + 1, close - i - 1);
    const size_t colon = inside.find(':');
    const std::string name(inside.substr(0, colon));
    std::string format = colon == std::string_view::npos ? "" : std::string(inside.substr(colon + 1));
    if (name.empty() || name.find_first_of(" {") != std::string::npos)
      throw std::invalid_argument("'{" + std::string(inside) + "}' is not a placeholder: write {name} or {name:%.1f}");
    if (colon != std::string_view::npos && !valid_format(format))
      throw std::invalid_argument("{" + std::string(inside) + "}: the format must be like %d, %.1f, %5.2f, %e or %g");
    // Whole numbers are rounded and printed as long longs: "{n:%d}" of 3.0 is "3".
    if (!format.empty() && (format.back() == 'd' || format.back() == 'i')) format = format.substr(0, format.size() - 1) + "lld";
    if (!literal.empty()) pieces_.push_back({std::move(literal), ""}), literal.clear();
    pieces_.push_back({format, name});
    i = close;
  }
  if (!literal.empty()) pieces_.push_back({std::move(literal), ""});
}

std::vector<std::string> PhraseTemplate::placeholders() const {
  std::vector<std::string> out;
  for (const Piece& p : pieces_)
    if (!p.name.empty()) out.push_back(p.name);
  return out;
}

bool PhraseTemplate::numeric(const std::string& name) const {
  for (const Piece& p : pieces_)
    if (p.name == name && !p.text.empty()) return true;
  return false;
}

void PhraseTemplate::missing(const std::string& name) {
  throw std::invalid_argument("no value for {" + name + "}");
}

void PhraseTemplate::append_within_limit(std::string& out, std::string_view text, const Piece& p) {
  if (out.size() + text.size() > kMaxPhraseBytes)
    throw std::invalid_argument((p.name.empty() ? std::string("the text") : "{" + p.name + "}") +
                                " makes the phrase " + longer_than_the_limit(out.size() + text.size()));
  out += text;
}

void PhraseTemplate::append(std::string& out, const Piece& p, const PhraseValue& v) {
  if (!v.number) {
    if (!p.text.empty()) throw std::invalid_argument("{" + p.name + "} has a number format but got text");
    append_within_limit(out, v.text, p);
    return;
  }
  char buf[64];
  const double x = *v.number;
  if (p.text.ends_with("lld")) {
    std::snprintf(buf, sizeof buf, p.text.c_str(), std::isfinite(x) ? std::llround(x) : 0LL);
  } else if (p.text.empty()) {
    std::snprintf(buf, sizeof buf, "%.14g", x);  // as Lua prints numbers
  } else {
    std::snprintf(buf, sizeof buf, p.text.c_str(), x);
  }
  append_within_limit(out, buf, p);
}

void Phrases::add(const std::string& key, std::string_view text) { phrases_.insert_or_assign(key, PhraseTemplate(text)); }

const PhraseTemplate* Phrases::find(std::string_view key) const {
  const auto it = phrases_.find(key);
  return it == phrases_.end() ? nullptr : &it->second;
}

std::vector<std::string> Phrases::keys() const {
  std::vector<std::string> out;
  for (const auto& [key, text] : phrases_) out.push_back(key);
  return out;
}

bool Phrases::looks_like_key(std::string_view text) {
  if (text.empty() || !(text[0] >= 'a' && text[0] <= 'z')) return false;
  for (char c : text)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

}  // namespace quantum::lua
