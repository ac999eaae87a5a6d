#include "audit.h"

#include <algorithm>
#include <array>
#include <boost/math/distributions/chi_squared.hpp>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "output_files.h"

namespace quantum::tools {
namespace {

using nlohmann::json;

constexpr double kTolerance = 1e-9;    // relative (docs/decisions.md)
constexpr double kFloor = 1e-12;       // absolute: below it a relative difference is rounding, not a doctored figure
constexpr double kTie = 1e-12;         // u this near a running sum may take either neighbour
constexpr double kEventTime = 2e-6;    // s: an events log rounds its times to microseconds
constexpr double kMostFactor = 1e6;    // a factor's product stops here, before the handicap
constexpr double kThreshold = 0.001;   // a statistical test fails below this p
constexpr size_t kFewestDraws = 100;   // fewer, and no statistical test says anything
constexpr double kFewestExpected = 5;  // per category: fewer, and the chi-square's approximation fails
constexpr size_t kProgressEvery = 50'000;
// Bounds on what a hostile file can make the parser hold: a draw's line is kilobytes and nests 5 deep.
constexpr size_t kLongestLine = size_t(16) << 20;
constexpr int kDeepest = 16;
constexpr uint64_t kShareSeed = 20240611;  // the PIT's uniform shares: a run repeats

// The file cannot be audited: it is not a log, or a line is not what the format says (exit 2).
struct Unreadable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string num(double x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

std::string printed(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

// A p-value readable at both ends: 0.50, 0.0032, 3.2e-09.
std::string chance(double p) { return printed(p >= 0.01 ? "%.2f" : "%.2g", p); }

std::string in_quotes(std::string_view s) { return '"' + std::string(s) + '"'; }

// Within the spec's tolerance; `scale` is the size of the figures a sum was made of, whose
// rounding a small result inherits. Nothing is close to NaN or infinity, nor within an overflowed scale.
bool close(double a, double b, double scale = 0) {
  const double bound = kTolerance * std::max({std::abs(a), std::abs(b), scale}) + kFloor;
  return std::abs(a - b) <= bound && std::isfinite(bound);
}

// A log's lines, plain or gzip-compressed; a last line cut short by a killed match is left out,
// with a warning.
using Lines = runtime::LineReader;

void warn_if_torn(const Lines& lines, std::ostream& err) {
  if (const std::string torn = lines.torn(); !torn.empty()) err << "audit: warning: " << torn << '\n';
}

bool blank(std::string_view line) { return line.find_first_not_of(" \t\r") == std::string_view::npos; }

// A line as JSON, refused before parsing when it nests deeper than any log's ("[[[[...": the
// parser would hold a node for every bracket).
json parsed(std::string_view line) {
  int depth = 0;
  bool quote = false, escape = false;
  for (char c : line) {
    if (quote) {
      if (escape) escape = false;
      else if (c == '\\') escape = true;
      else if (c == '"') quote = false;
    } else if (c == '"') {
      quote = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kDeepest) throw Unreadable("nested deeper than " + std::to_string(kDeepest) + ": not a log line");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  try {
    json j = json::parse(line);
    if (!j.is_object()) throw Unreadable("not a JSON object");
    return j;
  } catch (const json::exception& e) {  // not JSON, or a number past a double's range
    throw Unreadable(std::string("not JSON (") + e.what() + ")");
  }
}

const json& field(const json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end()) throw Unreadable(std::string("no \"") + key + "\"");
  return *it;
}

double number(const json& value, const char* what) {
  if (!value.is_number()) throw Unreadable(std::string("\"") + what + "\" is not a number");
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw Unreadable(std::string("\"") + what + "\" is not a finite number");
  return x;
}

double number_at(const json& object, const char* key) { return number(field(object, key), key); }

const std::string& text_at(const json& object, const char* key) {
  const json& value = field(object, key);
  if (!value.is_string()) throw Unreadable(std::string("\"") + key + "\" is not a string");
  return value.get_ref<const std::string&>();
}

const json& list_at(const json& object, const char* key) {
  const json& value = field(object, key);
  if (!value.is_array()) throw Unreadable(std::string("\"") + key + "\" is not a list");
  return value;
}

const json& as_object(const json& value) {
  if (!value.is_object()) throw Unreadable("not an object");
  return value;
}

// Rethrows what `read` refuses with the place it was reading.
template <class Read>
auto within(const std::string& place, Read read) {
  try {
    return read();
  } catch (const Unreadable& e) {
    throw Unreadable(place + ": " + e.what());
  } catch (const json::exception& e) {
    throw Unreadable(place + ": " + e.what());
  }
}

enum class Kind : uint8_t { Body, Goal, Wall, Out, Landing, Tackle, None };
constexpr size_t kKinds = size_t(Kind::None) + 1;
constexpr std::array<const char*, kKinds> kKindNames = {"body", "goal", "wall", "out", "landing", "tackle", "none"};

Kind kind_named(const std::string& name) {
  for (size_t k = 0; k < kKinds - 1; ++k)
    if (name == kKindNames[k]) return Kind(k);
  throw Unreadable("\"kind\" " + in_quotes(name) + " is none of body, goal, wall, out, landing, tackle");
}

// The kind of draw whose outcome an event of `type` is, for the types draws make.
std::optional<Kind> drawn_kind(std::string_view type) {
  for (const char* body : {"shot", "intercept", "retouch", "catch", "pass", "pickup", "hit"})
    if (type == body) return Kind::Body;
  if (type == "goal" || type == "own_goal") return Kind::Goal;
  if (type == "bounce") return Kind::Wall;
  if (type == "out") return Kind::Out;
  if (type == "landing") return Kind::Landing;
  if (type == "tackle") return Kind::Tackle;
  return std::nullopt;
}

const char* events_of(Kind kind) {
  switch (kind) {
    case Kind::Body: return "a shot, intercept, retouch, catch, pass, pickup or hit";
    case Kind::Goal: return "a goal or own goal";
    case Kind::Wall: return "a bounce";
    case Kind::Out: return "an out";
    case Kind::Landing: return "a landing";
    case Kind::Tackle: return "a tackle";
    case Kind::None: break;
  }
  return "no event";
}

// Whether an event's actor names a draw's: an out's has none, and the floor's landing is "".
bool same_actor(Kind kind, std::string_view draw, std::string_view event) {
  if (kind == Kind::Out) return true;
  if (kind == Kind::Landing && draw == "floor") return event.empty();
  return draw == event;
}

// A factor's terms multiplied as docs/decisions.md says: capped after each, the handicap last.
struct Terms {
  double product = 1;
  bool handicap_early = false;  // a handicap term with another after it
};

Terms terms_of(const json& holder) {
  Terms t;
  const auto it = holder.find("factors");
  if (it == holder.end()) return t;
  if (!it->is_array()) throw Unreadable("\"factors\" is not a list");
  bool handicap = false;
  for (size_t k = 0; k < it->size(); ++k) {
    t.handicap_early = t.handicap_early || handicap;
    within("factors[" + std::to_string(k) + "]", [&] {
      const json& term = as_object((*it)[k]);
      handicap = text_at(term, "source") == "handicap";
      t.product *= number_at(term, "value");
    });
    if (!handicap) t.product = std::min(t.product, kMostFactor);
  }
  return t;
}

struct Group {
  int fate;  // -1: no factor was given
  double mass;
};

struct Option {
  Kind kind = Kind::None;
  std::string actor;
  double p = 0, p_newtonian = 0, mass = 0, factor = 1, weight = 0;
  Terms terms;
  size_t first_group = 0, groups = 0;
};

struct FateFactor {
  double mass, factor;
  Terms terms;
};

// A draw's line, as far as the checks need it. Kept from line to line: its lists keep their room.
struct Draw {
  double t = 0, u = 0;
  std::vector<Option> options;
  std::vector<Group> groups;
  std::vector<FateFactor> fates;
  double rest_mass = 0, rest_weight = 0;
  bool all_met = false, skipped = false, tackles = false;
  std::string outcome;
};

void read_option(const json& o, Draw& d, Option& option) {
  option.kind = kind_named(text_at(o, "kind"));
  option.actor = text_at(o, "actor");
  option.p = number_at(o, "p");
  option.p_newtonian = number_at(o, "p_newtonian");
  option.terms = terms_of(o);
  option.first_group = d.groups.size(), option.groups = 0;
  if (option.kind != Kind::Wall) option.factor = number_at(o, "factor");
  if (option.kind == Kind::Tackle) return;
  option.mass = number_at(o, "mass");
  option.weight = number_at(o, "weight");
  const json& groups = list_at(o, "groups");
  for (size_t g = 0; g < groups.size(); ++g) {
    const json& group = groups[g];
    if (!group.is_array() || group.size() < 2)
      throw Unreadable("groups[" + std::to_string(g) + "] is not [fate, mass, particles]");
    const double fate = number(group[0], "fate");
    if (fate != std::floor(fate) || fate < -1 || fate > 1e9)
      throw Unreadable("groups[" + std::to_string(g) + "]: no fate index");
    d.groups.push_back({int(fate), number(group[1], "mass")});
    ++option.groups;
  }
}

void read_draw(const json& line, Draw& d) {
  if (line.contains("format")) throw Unreadable("a second header: give each log as a file of its own");
  d.t = number_at(line, "t");
  d.u = number_at(line, "u");
  d.outcome = text_at(line, "outcome");
  const auto skipped = line.find("factors_skipped");
  d.skipped = skipped != line.end() && *skipped != false && !skipped->is_null();
  const json& draw = list_at(line, "draw");
  d.options.resize(draw.size());
  d.groups.clear();
  for (size_t k = 0; k < draw.size(); ++k)
    within("draw[" + std::to_string(k) + "]", [&] { read_option(as_object(draw[k]), d, d.options[k]); });
  d.tackles = !d.options.empty() && d.options.front().kind == Kind::Tackle;
  const auto fates = line.find("fates");
  d.fates.clear();
  if (fates != line.end()) {
    if (!fates->is_array()) throw Unreadable("\"fates\" is not a list");
    for (size_t g = 0; g < fates->size(); ++g)
      within("fates[" + std::to_string(g) + "]", [&] {
        const json& f = as_object((*fates)[g]);
        d.fates.push_back({number_at(f, "mass"), number_at(f, "factor"), terms_of(f)});
      });
  }
  // A tackle has no cloud behind it: no rest.
  d.rest_mass = d.rest_weight = 0, d.all_met = false;
  if (d.tackles && !line.contains("rest")) return;
  const json& rest = field(line, "rest");
  if (!rest.is_object()) throw Unreadable("\"rest\" is not an object");
  within("rest", [&] { d.rest_mass = number_at(rest, "mass"), d.rest_weight = number_at(rest, "weight"); });
  const json& all_met = field(line, "all_met");
  if (!all_met.is_boolean()) throw Unreadable("\"all_met\" is not true or false");
  d.all_met = all_met.get<bool>();
}

std::string named(const Draw& d, size_t k) {
  const Option& o = d.options[k];
  return "draw[" + std::to_string(k) + "] " + kKindNames[size_t(o.kind)] + " " + in_quotes(o.actor);
}

// What is wrong with a factor, after its holder's name; "" for nothing. `skipped`: a fate's on a
// line with factors_skipped, 1 whatever its terms (the contacts keep theirs).
std::string factor_violation(double factor, const Terms& terms, bool skipped = false) {
  if (terms.handicap_early) return ": a handicap term before another (the handicap multiplies last)";
  if (skipped && !close(factor, 1)) return ": factor " + num(factor) + " is not 1 on a line with factors_skipped";
  if (!skipped && !close(factor, terms.product))
    return ": factor " + num(factor) + " is not its terms' product, " + num(terms.product);
  return {};
}

// What a draw checks out as.
struct Verdict {
  std::string violation;  // the first, "" for none
  std::optional<size_t> realized;  // the option of the outcome; none: nullopt
  bool known = true;  // the outcome is an option or none
};

class Checker {
 public:
  Verdict check(const Draw& d) {
    Verdict v;
    if (d.options.empty()) return v.violation = "a draw with no options", v;
    for (const Option& o : d.options)
      if ((o.kind == Kind::Tackle) != d.tackles) return v.violation = "tackles and contacts in one draw", v;
    v.violation = d.tackles ? tackle_arithmetic(d) : contact_arithmetic(d);
    std::string chances = chances_violation(d);
    if (v.violation.empty()) v.violation = std::move(chances);
    std::string drawn = redrawn(d, v);
    if (v.violation.empty()) v.violation = std::move(drawn);
    if (v.violation.empty() && v.realized) {
      const Option& o = d.options[*v.realized];
      if (!(o.p_newtonian > 0) || (!d.tackles && !(o.mass > 0)))
        v.violation = "the realized " + named(d, *v.realized) + " had no Newtonian chance (p_newtonian " +
                      num(o.p_newtonian) + (d.tackles ? "" : ", mass " + num(o.mass)) +
                      "): a factor makes an outcome likelier or rarer, never possible";
    }
    return v;
  }

 private:
  std::string tackle_arithmetic(const Draw& d) {
    double sum = 0;
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      if (std::string bad = factor_violation(o.factor, o.terms); !bad.empty()) return named(d, k) + bad;
      sum += 1 - std::pow(1 - o.p_newtonian, o.factor);
    }
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      const double own = 1 - std::pow(1 - o.p_newtonian, o.factor);
      const double expected = sum > 1 ? own / sum : own;
      if (!close(o.p, expected))
        return named(d, k) + ": p " + num(o.p) + " is not 1 - (1 - p_newtonian)^factor" +
               (sum > 1 ? " over their sum " + num(sum) : "") + ", " + num(expected);
    }
    return {};
  }

  std::string contact_arithmetic(const Draw& d) {
    const size_t fates = d.fates.size();
    for (size_t g = 0; g < fates; ++g) {
      const FateFactor& f = d.fates[g];
      if (std::string bad = factor_violation(f.factor, f.terms, d.skipped); !bad.empty())
        return "fates[" + std::to_string(g) + "]" + bad;
    }
    met_.assign(fates, 0);
    double weights = 0, masses = 0;
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      double expected = 0, size = 0;
      for (size_t i = o.first_group; i < o.first_group + o.groups; ++i) {
        const Group& g = d.groups[i];
        if (g.fate >= int(fates))
          return named(d, k) + ": its groups name fate " + std::to_string(g.fate) + " of " + std::to_string(fates);
        if (g.fate >= 0) met_[size_t(g.fate)] += g.mass;
        const double term = g.mass * (g.fate < 0 ? 1 : d.fates[size_t(g.fate)].factor);
        expected += term, size += std::abs(term);
      }
      if (o.kind == Kind::Wall) {
        if (!close(o.weight, expected, size))
          return named(d, k) + ": weight " + num(o.weight) + " is not its groups' masses times their fates' factors, " +
                 num(expected);
      } else {
        if (std::string bad = factor_violation(o.factor, o.terms); !bad.empty()) return named(d, k) + bad;
        if (!close(o.weight, o.mass * o.factor))
          return named(d, k) + ": weight " + num(o.weight) + " is not mass x factor, " + num(o.mass * o.factor);
      }
      weights += o.weight, masses += o.mass;
    }
    // The rest: each fate's particles that met nothing at its factor; what of rest.mass no fate
    // accounts for is particles of no fate yet, at 1. A fate all met leaves its rounding, times
    // its factor (up to 1e6 and more): the tolerance is the fate's whole weight's.
    double rest = 0, rest_size = 0, of_fates = 0;
    for (size_t g = 0; g < fates; ++g) {
      const FateFactor& f = d.fates[g];
      const double left = f.mass - met_[g];
      rest += left * f.factor, of_fates += left;
      rest_size += (std::abs(f.mass) + std::abs(met_[g])) * std::abs(f.factor);
    }
    rest += d.rest_mass - of_fates;
    rest_size += std::abs(d.rest_mass) + std::abs(of_fates);
    if (!close(d.rest_weight, rest, rest_size))
      return "rest.weight " + num(d.rest_weight) + " is not what the fates leave after the groups, " + num(rest);
    if (!d.all_met) weights += d.rest_weight, masses += d.rest_mass;
    // Past a double's range every p would be 0 over infinity, and look consistent.
    if (!std::isfinite(weights)) return "the weights sum to " + num(weights);
    const char* over = d.all_met ? " over the options' (all_met)" : " over the options' and the rest's";
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      const double p = weights > 0 ? o.weight / weights : 0;
      if (!close(o.p, p))
        return named(d, k) + ": p " + num(o.p) + " is not its weight" + over + ", " + num(p);
      const double p_newtonian = masses > 0 ? o.mass / masses : 0;
      if (!close(o.p_newtonian, p_newtonian))
        return named(d, k) + ": p_newtonian " + num(o.p_newtonian) + " is not its mass" + over + ", " +
               num(p_newtonian);
    }
    return {};
  }

  std::string chances_violation(const Draw& d) {
    double sum = 0;
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      if (!(o.p >= 0 && o.p <= 1)) return named(d, k) + ": p " + num(o.p) + " is not in [0, 1]";
      if (!(o.p_newtonian >= 0 && o.p_newtonian <= 1))
        return named(d, k) + ": p_newtonian " + num(o.p_newtonian) + " is not in [0, 1]";
      sum += o.p;
    }
    if (sum > 1 + kTolerance) return "the chances sum to " + num(sum) + ", past 1";
    // Options that all weigh 0 have no chances to sum to 1 (0 over 0 is taken as 0).
    const bool weighed =
        d.tackles || std::any_of(d.options.begin(), d.options.end(), [](const Option& o) { return o.weight > 0; });
    if (d.all_met && std::abs(sum - 1) > kTolerance && weighed)
      return "all_met, and the chances sum to " + num(sum) + ", not 1";
    return {};
  }

  // The outcome against the option u picks; sets the verdict's realized option.
  std::string redrawn(const Draw& d, Verdict& v) {
    const size_t n = d.options.size();
    sums_.resize(n);
    double sum = 0;
    std::optional<size_t> last;  // the last option with a chance
    for (size_t k = 0; k < n; ++k) {
      sum += d.options[k].p, sums_[k] = sum;
      if (d.options[k].p > 0) last = k;
    }
    // With all_met, rounding may leave u a hair above the sum: the engine takes the last option.
    auto could_pick = [&](size_t k) {
      const Option& o = d.options[k];
      const double below = k == 0 ? 0 : sums_[k - 1];
      return o.p > 0 && d.u >= below - kTie && (d.u < sums_[k] + kTie || (d.all_met && last == k));
    };
    const bool none_possible = d.all_met ? !last : d.u >= sum - kTie;
    bool found = d.outcome == "none";
    bool possible = found && none_possible;
    for (size_t k = 0; k < n && !possible; ++k) {
      if (d.options[k].actor != d.outcome) continue;
      if (!found || could_pick(k)) v.realized = k;
      found = true;
      possible = could_pick(k);
    }
    v.known = found;
    if (!(d.u >= 0 && d.u < 1)) return "u " + num(d.u) + " is not in [0, 1)";
    if (!found) return "the outcome " + in_quotes(d.outcome) + " is none of the options";
    if (possible) return {};
    size_t picked = 0;
    while (picked < n && !(d.u < sums_[picked])) ++picked;
    if (picked == n && d.all_met && last) picked = *last;
    const std::string pick = picked == n ? "none (the chances sum to " + num(sum) + ")"
                                         : named(d, picked) + " ([" + num(picked ? sums_[picked - 1] : 0) + ", " +
                                               num(sums_[picked]) + "))";
    return "u " + num(d.u) + " picks " + pick + ", not the outcome " + in_quotes(d.outcome);
  }

  std::vector<double> met_, sums_;  // kept from draw to draw: their room
};

// The statistical tests' figures, pooled over every draw.
class Pool {
 public:
  void add(const Draw& d, const Verdict& v) {
    if (!v.known) return;
    ++draws_;
    double sum = 0;
    std::optional<double> below;  // the chance of the options before the realized one
    for (size_t k = 0; k < d.options.size(); ++k) {
      const Option& o = d.options[k];
      const bool realized = v.realized == k;
      if (realized) below = sum;
      offered_[size_t(o.kind)] = true;
      expected_[size_t(o.kind)] += o.p;
      bin(o.p, realized);
      sum += o.p;
    }
    const double none = std::clamp(1 - sum, 0.0, 1.0);
    expected_[size_t(Kind::None)] += none;
    bin(none, !v.realized);
    ++realized_[size_t(v.realized ? d.options[*v.realized].kind : Kind::None)];
    const double share = double(shares_() >> 11) * 0x1.0p-53;
    pit_.push_back(v.realized ? *below + share * d.options[*v.realized].p : std::min(sum, 1.0) + share * none);
  }

  // Prints the tests; returns the first that failed, "" for none. Once: it sorts what it tests.
  std::string report(std::ostream& out) {
    std::string failed;
    if (draws_ < kFewestDraws) {
      const std::string skipped = ": skipped: too few draws (" + std::to_string(draws_) + ", needs " +
                                  std::to_string(kFewestDraws) + ")\n";
      out << "calibration by kind" << skipped << "calibration by chance" << skipped << "probability integral transform"
          << skipped;
      return failed;
    }
    by_kind(out, failed);
    by_chance(out, failed);
    integral_transform(out, failed);
    return failed;
  }

 private:
  struct Bin {
    double expected = 0, variance = 0, misses = 0;  // misses: the expected count of not realized
    double realized = 0;
    Bin& operator+=(const Bin& b) {
      expected += b.expected, variance += b.variance, misses += b.misses, realized += b.realized;
      return *this;
    }
  };

  void bin(double p, bool realized) {
    if (!(p > 0)) return;  // nothing expected, and a realized chance 0 is a draw's violation
    bins_[std::min(size_t(p * 10), bins_.size() - 1)] += {p, p * (1 - p), 1 - p, double(realized)};
  }

  static void judge(const char* test, double statistic, int freedom, const std::string& detail, std::ostream& out,
                    std::string& failed) {
    const double p = std::isfinite(statistic) && statistic >= 0
                         ? boost::math::cdf(boost::math::complement(boost::math::chi_squared(freedom), statistic))
                         : 0;
    out << test << ": chi-square " << printed("%.2f", statistic) << " on " << freedom << " degree"
        << (freedom == 1 ? "" : "s") << " of freedom, p = " << chance(p) << " (fails below " << kThreshold << ")\n  "
        << detail << " (realized of expected)\n";
    if (p < kThreshold && failed.empty())
      failed = std::string(test) + ": the outcomes do not follow their chances (p = " + chance(p) +
               "; realized of expected: " + detail + ")";
  }

  struct Category {
    std::string name;
    double expected, realized;
  };

  // Pearson's chi-square over the kinds offered and none; kinds expected fewer than 5 times pool
  // into one category, itself joined to the smallest other while still short.
  void by_kind(std::ostream& out, std::string& failed) const {
    std::vector<Category> kinds;
    Category rare{"", 0, 0};
    for (size_t k = 0; k < kKinds; ++k) {
      if (!offered_[k] && Kind(k) != Kind::None) continue;
      const Category c{kKindNames[k], expected_[k], double(realized_[k])};
      if (c.expected >= kFewestExpected) {
        kinds.push_back(c);
      } else {
        rare.name += (rare.name.empty() ? "" : "+") + c.name;
        rare.expected += c.expected, rare.realized += c.realized;
      }
    }
    if (!rare.name.empty() && rare.expected >= kFewestExpected) {
      kinds.push_back(rare);
    } else if (!rare.name.empty() && !kinds.empty()) {
      Category& smallest = *std::min_element(
          kinds.begin(), kinds.end(), [](const Category& a, const Category& b) { return a.expected < b.expected; });
      smallest.name += "+" + rare.name, smallest.expected += rare.expected, smallest.realized += rare.realized;
    }
    if (kinds.size() < 2) {
      out << "calibration by kind: skipped: too few draws (fewer than two kinds of outcome expected " << kFewestExpected
          << " times)\n";
      return;
    }
    double statistic = 0;
    std::string detail;
    for (const Category& c : kinds) {
      statistic += (c.realized - c.expected) * (c.realized - c.expected) / c.expected;
      detail += (detail.empty() ? "" : ", ") + c.name + " " + printed("%.0f", c.realized) + " of " +
                printed("%.1f", c.expected);
    }
    judge("calibration by kind", statistic, int(kinds.size()) - 1, detail, out, failed);
  }

  // Squared z-scores of the ten bins of chance; neighbouring bins pool until each expects 5
  // realized and 5 not (the normal approximation's rule of thumb), what is left joining the last.
  void by_chance(std::ostream& out, std::string& failed) const {
    std::vector<Bin> pooled;
    std::vector<size_t> starts;  // each pooled bin's first of the ten
    Bin run;
    size_t from = 0;
    for (size_t b = 0; b < bins_.size(); ++b) {
      run += bins_[b];
      if (run.expected < kFewestExpected || run.misses < kFewestExpected) continue;
      pooled.push_back(run), starts.push_back(from);
      run = {}, from = b + 1;
    }
    if (pooled.empty()) {
      out << "calibration by chance: skipped: too few draws (no bin of chance expects " << kFewestExpected
          << " realized and " << kFewestExpected << " not)\n";
      return;
    }
    pooled.back() += run;
    starts.push_back(bins_.size());
    double statistic = 0;
    std::string detail;
    for (size_t b = 0; b < pooled.size(); ++b) {
      const Bin& bin = pooled[b];
      statistic += (bin.realized - bin.expected) * (bin.realized - bin.expected) / bin.variance;
      detail += (detail.empty() ? "[" : ", [") + printed("%.1f", starts[b] / 10.0) + ", " +
                printed("%.1f", starts[b + 1] / 10.0) + (starts[b + 1] == bins_.size() ? "] " : ") ") +
                printed("%.0f", bin.realized) + " of " + printed("%.1f", bin.expected);
    }
    judge("calibration by chance", statistic, int(pooled.size()), detail, out, failed);
  }

  void integral_transform(std::ostream& out, std::string& failed) {
    std::sort(pit_.begin(), pit_.end());
    const double n = double(pit_.size());
    double d = 0;
    for (size_t i = 0; i < pit_.size(); ++i) d = std::max({d, (i + 1) / n - pit_[i], pit_[i] - i / n});
    // Boost 1.74 has no Kolmogorov-Smirnov distribution: the asymptotic series
    // Q(l) = 2 sum_{j>=1} (-1)^(j-1) exp(-2 j^2 l^2) with Stephens' l = (sqrt(n) + 0.12 + 0.11 / sqrt(n)) D
    // (Numerical Recipes' probks, which takes Q = 1 where the series has not converged: small l).
    const double lambda = (std::sqrt(n) + 0.12 + 0.11 / std::sqrt(n)) * d;
    double p = 1, sum = 0, sign = 2, previous = 0;
    for (int j = 1; j <= 100; ++j) {
      const double term = sign * std::exp(-2 * j * j * lambda * lambda);
      sum += term;
      if (std::abs(term) <= 1e-3 * previous || std::abs(term) <= 1e-8 * sum) {
        p = std::clamp(sum, 0.0, 1.0);
        break;
      }
      sign = -sign, previous = std::abs(term);
    }
    out << "probability integral transform: Kolmogorov-Smirnov D = " << printed("%.4f", d) << " over " << pit_.size()
        << " draws, p = " << chance(p) << " (fails below " << kThreshold << ")\n";
    if (p < kThreshold && failed.empty())
      failed = "probability integral transform: the outcomes do not follow their chances (p = " + chance(p) + ")";
  }

  size_t draws_ = 0;
  std::array<bool, kKinds> offered_{};
  std::array<double, kKinds> expected_{};
  std::array<size_t, kKinds> realized_{};
  std::array<Bin, 10> bins_{};
  std::vector<double> pit_;  // one per draw
  std::mt19937_64 shares_{kShareSeed};
};

class Progress {
 public:
  Progress(std::ostream& err, bool shown) : err_(err), shown_(shown) {}
  void draw() {
    if (++draws_ % kProgressEvery || !shown_) return;
    const std::string line = "audit: " + std::to_string(draws_) + " draws read";
    err_ << '\r' << line << std::flush;
    width_ = line.size();
  }
  void clear() {
    if (width_) err_ << '\r' << std::string(width_, ' ') << '\r' << std::flush;
    width_ = 0;
  }

 private:
  std::ostream& err_;
  bool shown_;
  size_t draws_ = 0, width_ = 0;
};

struct Violation {
  size_t pair = std::numeric_limits<size_t>::max();  // the decision log's place among those given
  double t = 0;
  std::string text;
};

// Keeps the first violation in the order of the logs, then of match time.
struct Violations {
  size_t count = 0;
  Violation first;
  void add(size_t pair, double t, std::string text) {
    ++count;
    if (pair < first.pair || (pair == first.pair && t < first.t)) first = {pair, t, std::move(text)};
  }
};

std::string place(const std::string& file, size_t line, double t) {
  return file + ":" + std::to_string(line) + " (t = " + num(t) + "): ";
}

enum class Content { Decisions, Events };

// Which log a file is, from its first line.
Content content_of(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Unreadable(path + ": a folder, not a log");
  Lines lines(path, kLongestLine);
  std::string line;
  while (lines.next(line) && blank(line)) {
  }
  if (blank(line)) throw Unreadable(path + ": empty, not a log");
  const json first = within(path + ":" + std::to_string(lines.number()), [&] { return parsed(line); });
  const auto format = first.find("format");
  if (format != first.end()) {
    if (*format != "quantum decisions")
      throw Unreadable(path + ": \"format\" is not \"quantum decisions\": not a decision log");
    const auto version = first.find("version");
    if (version == first.end() || *version != 2)
      throw Unreadable(path + ": a decision log of version " +
                       (version != first.end() && version->is_number() ? version->dump() : "?") +
                       "; audit reads version 2");
    return Content::Decisions;
  }
  if (first.contains("draw"))
    throw Unreadable(path + ": a version-1 decision log (no header line: written before 2026-11-29); audit needs "
                            "version 2: play the match again with --decisions (a recorded one: quantum replay DIR "
                            "--decisions FILE)");
  if (first.contains("type")) return Content::Events;
  throw Unreadable(path + ": neither a decision log (its first line has \"format\":\"quantum decisions\") nor an "
                          "events log (lines with \"type\")");
}

struct Event {
  double t;
  Kind kind;
  std::string actor;
  size_t line;
};

// An events log's events of the kinds draws make, by time.
std::vector<Event> read_events(const std::string& path, std::ostream& err) {
  std::vector<Event> events;
  Lines lines(path, kLongestLine);
  for (std::string line; lines.next(line);) {
    if (blank(line)) continue;
    within(path + ":" + std::to_string(lines.number()), [&] {
      const json e = parsed(line);
      const std::optional<Kind> kind = drawn_kind(text_at(e, "type"));
      const double t = number_at(e, "t");
      if (kind) events.push_back({t, *kind, e.contains("actor") ? text_at(e, "actor") : "", lines.number()});
    });
  }
  warn_if_torn(lines, err);
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.t < b.t; });
  return events;
}

// Each realized outcome against its event, and each event against its outcome.
void match_events(const std::vector<Event>& outcomes, const std::vector<Event>& events, size_t pair,
                  const std::string& decisions, const std::string& events_file, Violations& violations) {
  auto window = [](const std::vector<Event>& list, double t) {
    const auto from = std::lower_bound(list.begin(), list.end(), t - kEventTime,
                                       [](const Event& e, double at) { return e.t < at; });
    auto to = from;
    while (to != list.end() && to->t <= t + kEventTime) ++to;
    return std::pair{from, to};
  };
  auto pairs = [](const Event& outcome, const Event& event) {
    return outcome.kind == event.kind && same_actor(outcome.kind, outcome.actor, event.actor);
  };
  for (const Event& o : outcomes) {
    const auto [from, to] = window(events, o.t);
    if (std::none_of(from, to, [&](const Event& e) { return pairs(o, e); }))
      violations.add(pair, o.t,
                     place(decisions, o.line, o.t) + "the outcome " + in_quotes(o.actor) + " (" +
                         kKindNames[size_t(o.kind)] + ") has no event in " + events_file + " (" + events_of(o.kind) +
                         " of it at that time)");
  }
  for (const Event& e : events) {
    const auto [from, to] = window(outcomes, e.t);
    if (std::none_of(from, to, [&](const Event& o) { return pairs(o, e); }))
      violations.add(pair, e.t,
                     place(events_file, e.line, e.t) + "an event of " + in_quotes(e.actor) + " that no draw in " +
                         decisions + " realized (" + events_of(e.kind) + " is a " + kKindNames[size_t(e.kind)] +
                         " draw's outcome)");
  }
}

struct LogSummary {
  size_t draws = 0;
  std::string what;  // from the header: sport and seed
};

// Reads and checks one decision log's draws, pooling them; its realized outcomes go to `outcomes`.
LogSummary read_decisions(const std::string& path, size_t pair, Checker& checker, Pool& pool, Violations& violations,
                          size_t& draw_violations, std::vector<Event>* outcomes, Progress& progress, std::ostream& err) {
  LogSummary summary;
  Lines lines(path, kLongestLine);
  Draw d;
  bool header = true;
  for (std::string line; lines.next(line);) {
    if (blank(line)) continue;
    const std::string at = path + ":" + std::to_string(lines.number());
    const json j = within(at, [&] { return parsed(line); });
    if (header) {
      header = false;
      const auto sport = j.find("sport");
      const auto seed = j.find("seed");
      if (sport != j.end() && sport->is_string()) summary.what = " of " + sport->get<std::string>();
      if (seed != j.end() && seed->is_number_unsigned()) summary.what += " (seed " + seed->dump() + ")";
      continue;
    }
    within(at, [&] { read_draw(j, d); });
    const Verdict v = checker.check(d);
    if (!v.violation.empty()) {
      ++draw_violations;
      violations.add(pair, d.t, place(path, lines.number(), d.t) + v.violation);
    }
    pool.add(d, v);
    if (outcomes && v.realized)
      outcomes->push_back({d.t, d.options[*v.realized].kind, d.options[*v.realized].actor, lines.number()});
    ++summary.draws;
    progress.draw();
  }
  warn_if_torn(lines, err);
  return summary;
}

}  // namespace

int audit(const std::vector<std::string>& files, std::ostream& out, std::ostream& err, bool progress) {
  Progress shown(err, progress);
  try {
    std::vector<std::string> decisions, events;
    for (const std::string& f : files) (content_of(f) == Content::Decisions ? decisions : events).push_back(f);
    if (decisions.empty()) throw Unreadable("no decision log among the files (quantum play --decisions FILE)");
    if (events.size() > decisions.size())
      throw Unreadable(events[decisions.size()] + ": an events log with no decision log to go with it (the first "
                                                  "events log goes with the first decision log, and so on)");
    Checker checker;
    Pool pool;
    Violations violations;
    size_t draws = 0, draw_violations = 0, outcomes_matched = 0, events_matched = 0;
    std::vector<std::string> summaries;
    for (size_t i = 0; i < decisions.size(); ++i) {
      const bool with_events = i < events.size();
      std::vector<Event> outcomes;
      const std::vector<Event> logged = with_events ? read_events(events[i], err) : std::vector<Event>{};
      const LogSummary s = read_decisions(decisions[i], i, checker, pool, violations, draw_violations,
                                          with_events ? &outcomes : nullptr, shown, err);
      if (with_events) {
        std::stable_sort(outcomes.begin(), outcomes.end(), [](const Event& a, const Event& b) { return a.t < b.t; });
        match_events(outcomes, logged, i, decisions[i], events[i], violations);
        outcomes_matched += outcomes.size(), events_matched += logged.size();
      }
      draws += s.draws;
      summaries.push_back(decisions[i] + ": " + std::to_string(s.draws) + " draws" + s.what +
                     (with_events ? ", events from " + events[i] : ", no events log: its events not checked"));
    }
    shown.clear();
    for (const std::string& line : summaries) out << line << '\n';
    out << "arithmetic, chances, re-drawn, plausible: " << draws << " draws, " << draw_violations
        << " with a violation (fails on any)\n";
    if (!events.empty())
      out << "events: " << outcomes_matched << " realized outcomes, " << events_matched << " events of their kinds, "
          << violations.count - draw_violations << " unmatched (fails on any)\n";
    const std::string failed_test = pool.report(out);
    if (violations.count == 0 && failed_test.empty()) {
      out << "audit: passed\n";
      return 0;
    }
    out << "audit: FAILED\n" << (violations.count ? violations.first.text : failed_test) << '\n';
    if (violations.count > 1) out << "(and " << violations.count - 1 << " more violations)\n";
    return 1;
  } catch (const std::exception& e) {  // Unreadable, and whatever else stops the reading (memory)
    shown.clear();
    err << "audit: " << e.what() << '\n';
    return 2;
  }
}

}  // namespace quantum::tools
