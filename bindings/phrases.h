// Announcer phrases: a sport's templates ("{team} shoots", "{speed:%.1f} metres a second") by
// key, checked when the sport loads and filled when said.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace quantum::lua {

// A value for a placeholder: text, or a number (formatted by the placeholder's %-format, or as
// Lua prints it).
struct PhraseValue {
  std::string_view text;
  std::optional<double> number;
};

// One parsed template: literal pieces and placeholders in order.
class PhraseTemplate {
 public:
  // Throws std::invalid_argument naming what is wrong: text longer than limits::kMaxPhraseBytes,
  // an unclosed "{", an empty name, a format other than %[flags][width][.precision] followed by
  // d, i, f, e or g.
  explicit PhraseTemplate(std::string_view text);

  // The names of its placeholders, in order.
  std::vector<std::string> placeholders() const;
  // Whether placeholder `name` carries a number format ({speed:%.1f}).
  bool numeric(const std::string& name) const;

  // Appends the filled text to `out`. lookup(name) gives a placeholder's value, or nothing when
  // it has none (then this throws std::invalid_argument naming the placeholder). A phrase longer
  // than limits::kMaxPhraseBytes throws std::invalid_argument before the value that would make it
  // so is copied.
  template <class Lookup>
  void fill(std::string& out, Lookup&& lookup) const {
    for (const Piece& p : pieces_) {
      if (p.name.empty()) {
        append_within_limit(out, p.text, p);
        continue;
      }
      const std::optional<PhraseValue> v = lookup(std::string_view(p.name));
      if (!v) missing(p.name);
      append(out, p, *v);
    }
  }

 private:
  struct Piece {
    std::string text;    // literal text (name empty), or the placeholder's %-format ("" for none)
    std::string name;    // the placeholder's name
  };
  [[noreturn]] static void missing(const std::string& name);
  static void append(std::string& out, const Piece& p, const PhraseValue& v);
  static void append_within_limit(std::string& out, std::string_view text, const Piece& p);
  std::vector<Piece> pieces_;
};

class Phrases {
 public:
  // Adds phrase `key`; throws std::invalid_argument (see PhraseTemplate) for a malformed one.
  void add(const std::string& key, std::string_view text);
  const PhraseTemplate* find(std::string_view key) const;
  std::vector<std::string> keys() const;

  // Whether `text` given to game.say must be a phrase key: a lower-case name such as "goal" or
  // "match_end". Anything else (capitals, spaces, punctuation) is literal text to speak.
  static bool looks_like_key(std::string_view text);

 private:
  std::map<std::string, PhraseTemplate, std::less<>> phrases_;
};

}  // namespace quantum::lua
