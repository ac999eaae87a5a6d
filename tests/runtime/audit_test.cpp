// `quantum audit` against logs made here from docs/decisions.md alone: draws made honestly pass;
// each way a log can lie fails and names the draw; what is not a version-2 log is refused; and a
// log whose every draw adds up but whose outcomes follow other chances fails its statistics.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "audit.h"
#include "log_files.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using test::lines_of;
using test::write_lines;
using nlohmann::json;

// A folder of the test's own, gone after it.
struct Folder {
  fs::path path = fs::temp_directory_path() /
                  ("quantum_audit_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                   std::to_string(getpid()));
  Folder() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Folder() { fs::remove_all(path); }
  fs::path operator/(const std::string& name) const { return path / name; }
};

struct Said {
  int code;
  std::string out, err;
};

Said audit(const std::vector<fs::path>& files, bool progress = false) {
  std::vector<std::string> names;
  for (const fs::path& f : files) names.push_back(f.string());
  std::ostringstream out, err;
  const int code = tools::audit(names, out, err, progress);
  return {code, out.str(), err.str()};
}

std::ostream& operator<<(std::ostream& o, const Said& s) { return o << "exit " << s.code << "\n" << s.out << s.err; }

std::string shortest(double x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

struct Target {
  const char* kind;
  const char* actor;
  double sport;  // the sport's factor for it (walls have none: their particles keep their fates')
};

const Target kTargets[] = {{"body", "Red's mallet", 5},  {"body", "Blue's mallet", 5}, {"goal", "Red's goal", 5},
                           {"goal", "Blue's goal", 0.1}, {"wall", "left wall", 0},     {"wall", "right wall", 0},
                           {"out", "out", 1},            {"landing", "floor", 2},      {"landing", "Red's court", 0.5}};

const char* const kBodyEvents[] = {"shot", "intercept", "retouch", "catch", "pass", "pickup", "hit"};

// Draws made the way docs/decisions.md says the engine makes them, with their events. With
// `bias`, outcomes follow chances in which every body weighs `bias` times what the log says,
// and each u is made again inside the logged chance of the outcome: every draw adds up.
class Synthetic {
 public:
  explicit Synthetic(uint64_t seed, double bias = 1) : rng_(seed), bias_(bias) {}

  void write(const fs::path& decisions, const fs::path& events, int draws) {
    std::ofstream d(decisions), e(events);
    d << json{{"format", "quantum decisions"}, {"version", 2}, {"engine", "test"}, {"sport", "synthetic"},
              {"files", json::array()}, {"seed", 1}, {"seconds", 600}, {"fps", 60}, {"particles", 1000},
              {"tackle_rate", 3}, {"balance", {{"per_goal", 0}, {"most", 2}}}, {"params", json::object()},
              {"factor_overrides", json::object()}, {"factors", {{"goal", 5}, {"body", 5}}},
              {"players", {{{"name", "Red's mallet"}, {"team", "Red"}, {"skill", 0.6}, {"handicap", 2}},
                           {{"name", "Blue's mallet"}, {"team", "Blue"}, {"skill", nullptr}, {"handicap", 1}}}}}
             .dump()
      << '\n';
    long frame = 0;
    for (int k = 0; k < draws; ++k) {
      frame += 1 + long(rng_() % 3);
      const double t = frame / 60.0;
      json draw = chance(0.1) ? tackle(t) : contact(t);
      d << draw.dump() << '\n';
      if (draw["outcome"] != "none") e << event_of(draw).dump() << '\n';
      // Events no draw makes, which need none.
      if (k % 40 == 0)
        e << json{{"t", rounded(t + 0.5 / 60)}, {"type", "throw"}, {"actor", "Red's mallet"}}.dump() << '\n';
      if (k % 97 == 0)
        e << json{{"t", rounded(t + 0.5 / 60)}, {"type", "timer"}, {"said", {"One minute"}}}.dump() << '\n';
    }
  }

 private:
  double uniform() { return double(rng_() >> 11) * 0x1.0p-53; }
  bool chance(double p) { return uniform() < p; }
  template <class T>
  T pick(std::initializer_list<T> among) {
    return among.begin()[rng_() % among.size()];
  }
  static double rounded(double t) { return std::round(t * 1e6) / 1e6; }

  // A factor's terms and their product: capped at 1e6 after each, the handicap last.
  std::pair<json, double> terms(double sport) {
    json terms = json::array({{{"source", "sport"}, {"value", sport}}});
    double factor = sport;
    if (chance(0.3)) {
      const double v = pick({0.6, 2.0, 3.0});
      terms.push_back(
          {{"source", "powerup"}, {"name", "attract"}, {"holder", "Red's mallet"}, {"strength", 2}, {"value", v}});
      factor = std::min(factor * v, 1e6);
    }
    if (sport >= 1000) {  // past the cap, which the handicap still multiplies
      terms.push_back({{"source", "modifier"}, {"index", 1}, {"value", 5000}});
      factor = std::min(factor * 5000, 1e6);
    }
    if (chance(0.2)) {
      const double h = pick({2.0, 0.5});
      terms.push_back({{"source", "handicap"}, {"player", "Red's mallet"}, {"value", h}});
      factor *= h;
    }
    return {terms, factor};
  }

  // The options' p from their weights, u, and the outcome.
  void decide(json& draw, const std::vector<double>& weights, const std::vector<double>& truth, double rest,
              bool all_met) {
    json& options = draw["draw"];
    double total = rest, true_total = rest, sum = 0;
    for (size_t k = 0; k < weights.size(); ++k) total += weights[k], true_total += truth[k];
    std::vector<double> sums;
    for (size_t k = 0; k < weights.size(); ++k) {
      const double p = total > 0 ? weights[k] / total : 0;
      options[k]["p"] = p;
      sums.push_back(sum += p);
    }
    // The outcome, by the true chances; then u, inside its logged chance.
    const double drawn = uniform() * true_total;
    double cumulative = 0;
    int realized = -1;
    for (size_t k = 0; k < truth.size() && realized < 0; ++k)
      if (drawn < (cumulative += truth[k])) realized = int(k);
    if (realized < 0 && all_met)
      for (size_t k = truth.size(); k-- > 0 && realized < 0;)
        if (truth[k] > 0) realized = int(k);
    const double below = realized < 0 ? sum : realized == 0 ? 0 : sums[size_t(realized) - 1];
    const double width = realized < 0 ? 1 - sum : options[size_t(realized)]["p"].get<double>();
    double u = below + uniform() * width;
    if (u >= 1) u = std::nextafter(1.0, 0.0);
    draw["u"] = u;
    draw["outcome"] = realized < 0 ? json("none") : options[size_t(realized)]["actor"];
  }

  json contact(double t) {
    const bool all_met = chance(0.05), skipped = chance(0.03);
    // The cloud: fate groups and the particles of none yet (the last).
    const size_t fates = chance(0.1) ? 0 : 1 + rng_() % 3;
    std::vector<double> left(fates + 1), factor(fates);
    double cloud = 0;
    for (double& m : left) cloud += m = -std::log(1 - uniform());
    if (fates > 0 && chance(0.7)) cloud -= left.back(), left.back() = 0;
    for (double& m : left) m /= cloud;
    json draw = {{"t", t}, {"draw", json::array()}, {"fates", json::array()}};
    if (skipped) draw["factors_skipped"] = true;
    for (size_t g = 0; g < fates; ++g) {
      auto [factors, f] = terms(chance(0.02) ? 1000 : pick({5.0, 0.1, 1.0, 2.0, 0.5}));
      if (skipped) factors = json::array({{{"source", "sport"}, {"value", 0}}}), f = 1;
      factor[g] = f;
      draw["fates"].push_back({{"kind", "goal"}, {"actor", "Red's goal"}, {"via", ""}, {"mass", left[g]},
                               {"tweaked", left[g] * f}, {"particles", int(left[g] * 1000)}, {"factor", f},
                               {"factors", factors}});
    }
    // What met something: a few of the targets, each taking a part of some groups (with all_met,
    // the last takes all that is left).
    std::vector<size_t> order(std::size(kTargets));
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng_);
    order.resize(1 + rng_() % 3);
    std::vector<double> weights, truth;
    for (size_t k = 0; k < order.size(); ++k) {
      const Target& target = kTargets[order[k]];
      const bool last = k + 1 == order.size();
      json groups = json::array();
      double mass = 0, carried = 0;
      for (size_t g = 0; g <= fates; ++g) {
        if (left[g] <= 0 || (!all_met && chance(0.5))) continue;
        const double took = all_met ? (last ? left[g] : left[g] * uniform()) : left[g] * 0.05 * uniform();
        left[g] -= took;
        mass += took;
        carried += took * (g < fates ? factor[g] : 1);
        groups.push_back({g < fates ? int(g) : -1, took, int(took * 1000) + 1});
      }
      json option = {
          {"kind", target.kind}, {"actor", target.actor}, {"particles", int(mass * 1000) + 1}, {"mass", mass}};
      double weight = carried;
      if (std::string(target.kind) != "wall") {
        auto [factors, f] = terms(target.sport);
        if (chance(0.03)) {  // a penalized player's: never met
          factors.insert(
              factors.begin() + 1,
              json::object({{"source", "powerup"}, {"name", "penalty"}, {"holder", target.actor}, {"value", 0}}));
          f = 0;
        }
        option["factor"] = f;
        option["factors"] = factors;
        weight = mass * f;
      }
      option["weight"] = weight;
      option["groups"] = groups;
      draw["draw"].push_back(option);
      weights.push_back(weight);
      truth.push_back(std::string(target.kind) == "body" ? weight * bias_ : weight);
    }
    double rest_mass = 0, rest_weight = 0;
    for (size_t g = 0; g <= fates; ++g) rest_mass += left[g], rest_weight += left[g] * (g < fates ? factor[g] : 1);
    double newtonian = all_met ? 0 : rest_mass;
    for (const json& o : draw["draw"]) newtonian += o["mass"].get<double>();
    for (json& o : draw["draw"]) o["p_newtonian"] = newtonian > 0 ? o["mass"].get<double>() / newtonian : 0;
    draw["rest"] = {{"mass", rest_mass}, {"weight", rest_weight}};
    draw["all_met"] = all_met;
    decide(draw, weights, truth, all_met ? 0 : rest_weight, all_met);
    return draw;
  }

  // Opponents' chances to take the held ball: 1 - (1 - p_newtonian)^factor, over their sum past 1.
  json tackle(double t) {
    const double p_newtonian = 1 - std::exp(-3.0 / 60);
    json draw = {{"t", t}, {"draw", json::array()}, {"fates", json::array()}};
    std::vector<double> own;
    double sum = 0;
    const char* const actors[] = {"Red's mallet", "Blue's mallet"};
    for (size_t k = 0, n = 1 + rng_() % 2; k < n; ++k) {
      auto [factors, f] = terms(pick({1.0, 2.0, 100.0}));
      own.push_back(1 - std::pow(1 - p_newtonian, f));
      sum += own.back();
      draw["draw"].push_back({{"kind", "tackle"}, {"actor", actors[k]}, {"p_newtonian", p_newtonian},
                              {"particles", 0}, {"factor", f}, {"factors", factors}});
    }
    std::vector<double> weights;
    for (double p : own) weights.push_back(sum > 1 ? p / sum : p);
    // As weights over a rest of 1 - their sum, their p are themselves.
    decide(draw, weights, weights, 1 - std::min(sum, 1.0), false);
    for (size_t k = 0; k < weights.size(); ++k) draw["draw"][k]["p"] = weights[k];
    return draw;
  }

  json event_of(const json& draw) {
    for (const json& o : draw["draw"]) {
      if (o["actor"] != draw["outcome"]) continue;
      const std::string kind = o["kind"], actor = o["actor"];
      const std::string type = kind == "body"   ? kBodyEvents[rng_() % std::size(kBodyEvents)]
                               : kind == "goal" ? pick<const char*>({"goal", "own_goal"})
                               : kind == "wall" ? "bounce"
                                                : kind;
      return {{"t", rounded(draw["t"].get<double>())}, {"type", type},
              {"actor", kind == "out" || actor == "floor" ? "" : actor}, {"p", o["p"]},
              {"p_newtonian", o["p_newtonian"]}, {"particles", o["particles"]}, {"x", 0.5}, {"y", -0.25}};
    }
    return {};
  }

  std::mt19937_64 rng_;
  double bias_;
};

struct Logs {
  fs::path decisions, events;
};

Logs synthetic(const Folder& folder, const std::string& name, uint64_t seed, int draws = 3000, double bias = 1) {
  Logs logs{folder / (name + ".jsonl"), folder / (name + "_events.jsonl")};
  Synthetic(seed, bias).write(logs.decisions, logs.events, draws);
  return logs;
}

TEST(Audit, HonestDrawsPass) {
  Folder folder;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const Logs logs = synthetic(folder, "honest", seed, 2000);
    const Said said = audit({logs.decisions, logs.events});
    EXPECT_EQ(said.code, 0) << "seed " << seed << ": " << said;
    EXPECT_EQ(said.err, "");
    EXPECT_NE(said.out.find(": 2000 draws of synthetic (seed 1), events from "), std::string::npos) << said;
    EXPECT_NE(
        said.out.find("arithmetic, chances, re-drawn, plausible: 2000 draws, 0 with a violation (fails on any)\n"),
        std::string::npos)
        << said;
    EXPECT_NE(said.out.find(" 0 unmatched (fails on any)\n"), std::string::npos) << said;
    for (const char* test : {"calibration by kind: chi-square ", "calibration by chance: chi-square ",
                             "probability integral transform: Kolmogorov-Smirnov D = "})
      EXPECT_NE(said.out.find(test), std::string::npos) << test << "\n" << said;
    const std::string end = "audit: passed\n";
    EXPECT_EQ(said.out.substr(said.out.size() - std::min(said.out.size(), end.size())), end) << said;
  }
}

TEST(Audit, PoolsLogsWithTheirEventsInOrder) {
  Folder folder;
  const Logs a = synthetic(folder, "a", 11, 400), b = synthetic(folder, "b", 12, 400);
  const Said pooled = audit({a.decisions, b.decisions, a.events, b.events});
  EXPECT_EQ(pooled.code, 0) << pooled;
  EXPECT_NE(pooled.out.find("plausible: 800 draws, 0 with a violation"), std::string::npos) << pooled;
  // The first events log goes with the first decision log: swapped, neither matches.
  const Said swapped = audit({a.decisions, b.events, b.decisions, a.events});
  EXPECT_EQ(swapped.code, 1) << swapped;
  EXPECT_NE(swapped.out.find("audit: FAILED\n" + a.decisions.string() + ":"), std::string::npos) << swapped;
  // Without events logs, the events are not checked.
  const Said alone = audit({a.decisions});
  EXPECT_EQ(alone.code, 0) << alone;
  EXPECT_NE(alone.out.find("no events log: its events not checked"), std::string::npos) << alone;
  // An events log with no decision log to go with it is a mistake.
  const Said extra = audit({a.decisions, a.events, b.events});
  EXPECT_EQ(extra.code, 2) << extra;
  EXPECT_NE(extra.err.find(b.events.string() + ": an events log with no decision log"), std::string::npos) << extra;
}

// One draw of an honest log changed by `tamper` (false: a draw it cannot use): the audit fails
// and names that draw's file, line and time.
void expect_caught(const std::string& what, const std::function<bool(json&)>& tamper, bool with_events = true) {
  Folder folder;
  const Logs logs = synthetic(folder, "honest", 5, 500);
  std::vector<std::string> lines = lines_of(logs.decisions);
  std::string where;
  for (size_t k = 1; k < lines.size() && where.empty(); ++k) {
    json d = json::parse(lines[k]);
    if (!tamper(d)) continue;
    where = ':' + std::to_string(k + 1) + " (t = " + shortest(d["t"].get<double>()) + "): ";
    lines[k] = d.dump();
  }
  ASSERT_FALSE(where.empty()) << what << ": no draw to tamper with";
  const fs::path tampered = folder / "tampered.jsonl";
  write_lines(tampered, lines);
  const Said said = with_events ? audit({tampered, logs.events}) : audit({tampered});
  EXPECT_EQ(said.code, 1) << what << "\n" << said;
  EXPECT_NE(said.out.find("audit: FAILED\n" + tampered.string() + where), std::string::npos) << what << "\n" << said;
}

json& realized(json& d) {
  for (json& o : d["draw"])
    if (o["actor"] == d["outcome"]) return o;
  throw std::logic_error("no realized option");
}

TEST(Audit, AChangedChanceFails) {
  expect_caught("a changed probability", [](json& d) {
    json& option = d["draw"][0];
    if (option["p"].get<double>() < 0.01) return false;
    option["p"] = option["p"].get<double>() * 0.9;
    return true;
  });
  expect_caught("a changed Newtonian chance", [](json& d) {
    json& option = d["draw"][0];
    if (option["kind"] == "tackle" || option["p_newtonian"].get<double>() < 0.01) return false;
    option["p_newtonian"] = option["p_newtonian"].get<double>() * 1.01;
    return true;
  });
  expect_caught("a tackle's chance", [](json& d) {
    json& option = d["draw"][0];
    if (option["kind"] != "tackle") return false;
    option["p"] = option["p"].get<double>() * 1.000001;
    return true;
  });
  expect_caught("chances past 1 (all weights scaled alike)", [](json& d) {
    if (d["draw"][0]["kind"] == "tackle" || d["all_met"] == true) return false;
    double sum = 0;
    for (const json& o : d["draw"]) sum += o["p"].get<double>();
    if (sum < 0.2) return false;
    for (json& o : d["draw"]) o["p"] = o["p"].get<double>() * 2 / sum;
    return true;
  });
}

TEST(Audit, ASwappedOutcomeFails) {
  expect_caught("a swapped outcome", [](json& d) {
    if (d["outcome"] == "none" || d["draw"].size() < 2) return false;
    for (const json& option : d["draw"])
      if (option["actor"] != d["outcome"]) {
        d["outcome"] = option["actor"];
        return true;
      }
    return false;
  });
  expect_caught("an outcome made up", [](json& d) {
    d["outcome"] = "Green's mallet";
    return true;
  });
}

TEST(Audit, AUniformNumberThatDoesNotGiveItsOutcomeFails) {
  expect_caught("u inside the options of a draw that ended in nothing", [](json& d) {
    if (d["outcome"] != "none") return false;
    double sum = 0;
    for (const json& option : d["draw"]) sum += option["p"].get<double>();
    if (sum < 0.05) return false;
    d["u"] = sum / 2;
    return true;
  }, false);
  expect_caught("u past 1", [](json& d) {
    d["u"] = 1.0;
    return true;
  }, false);
}

TEST(Audit, FactorsThatDoNotMultiplyFail) {
  expect_caught("a term that does not multiply to the factor", [](json& d) {
    for (json& option : d["draw"])
      if (option.contains("factors")) {
        option["factors"][0]["value"] = option["factors"][0]["value"].get<double>() * 2 + 1;
        return true;
      }
    return false;
  }, false);
  expect_caught("a fate's factor", [](json& d) {
    if (d["fates"].empty() || d.contains("factors_skipped")) return false;
    d["fates"][0]["factors"][0]["value"] = d["fates"][0]["factors"][0]["value"].get<double>() + 1;
    return true;
  }, false);
  expect_caught("a handicap before another term", [](json& d) {
    for (json& option : d["draw"]) {
      json& terms = option["factors"];
      if (!terms.is_array() || terms.size() < 2 || terms.back()["source"] != "handicap") continue;
      std::swap(terms[0], terms[terms.size() - 1]);
      return true;
    }
    return false;
  }, false);
  expect_caught("a factor past the cap of 1e6", [](json& d) {
    for (json& fate : d["fates"])
      if (fate["factor"].get<double>() >= 1e6 && !d.contains("factors_skipped")) {
        double uncapped = 1;
        for (const json& term : fate["factors"]) uncapped *= term["value"].get<double>();
        fate["factor"] = uncapped;
        return true;
      }
    return false;
  }, false);
  expect_caught("factors_skipped with a fate's factor not 1", [](json& d) {
    if (!d.contains("factors_skipped") || d["fates"].empty()) return false;
    d["fates"][0]["factor"] = 2;
    return true;
  }, false);
  expect_caught("factors_skipped with a contact's factor 1 that its terms do not make", [](json& d) {
    if (!d.contains("factors_skipped")) return false;
    for (json& option : d["draw"])
      if (option.contains("factor") && option["factor"] != 1.0 && option["factor"] != 0.0) {
        option["factor"] = 1;
        option["weight"] = option["mass"];
        return true;
      }
    return false;
  }, false);
  expect_caught("a weight that is not mass x factor", [](json& d) {
    json& option = d["draw"][0];
    if (option["kind"] == "tackle" || option["kind"] == "wall") return false;
    option["weight"] = option["weight"].get<double>() * 1.5 + 1e-3;
    return true;
  }, false);
  expect_caught("a wall's weight", [](json& d) {
    for (json& option : d["draw"])
      if (option["kind"] == "wall") {
        option["weight"] = option["weight"].get<double>() * 1.5 + 1e-3;
        return true;
      }
    return false;
  }, false);
  expect_caught("the rest's weight", [](json& d) {
    if (!d.contains("rest") || d["all_met"] == true) return false;
    d["rest"]["weight"] = d["rest"]["weight"].get<double>() * 1.01;
    return true;
  }, false);
}

TEST(Audit, AnImpossibleOutcomeFails) {
  expect_caught("a realized option with p_newtonian 0", [](json& d) {
    if (d["outcome"] == "none") return false;
    realized(d)["p_newtonian"] = 0;
    return true;
  }, false);
  // A wall's weight is its groups', so a wall of mass 0 can have a chance with every figure
  // adding up: only plausibility catches its outcome.
  Folder folder;
  const fs::path log = folder / "wall.jsonl";
  write_lines(log,
              {R"({"format":"quantum decisions","version":2})",
               R"({"t":1.5,"u":0.1,"draw":[{"kind":"wall","actor":"left wall","p":0.5,"p_newtonian":0,"particles":3,)"
               R"("mass":0,"weight":1,"groups":[[0,0.5,3]]}],"rest":{"mass":0.5,"weight":1},"all_met":false,)"
               R"("outcome":"left wall","fates":[{"kind":"body","actor":"Red's mallet","via":"","mass":1,)"
               R"("tweaked":1,"particles":10,"factor":2,"factors":[{"source":"sport","value":2}]}]})"});
  const Said said = audit({log});
  EXPECT_EQ(said.code, 1) << said;
  EXPECT_NE(
      said.out.find(log.string() + ":2 (t = 1.5): the realized draw[0] wall \"left wall\" had no Newtonian chance"),
      std::string::npos)
      << said;
}

TEST(Audit, EventsMustMatchTheOutcomesBothWays) {
  Folder folder;
  const Logs logs = synthetic(folder, "honest", 6, 500);
  std::vector<std::string> events = lines_of(logs.events);
  // The first realized touch's event gone: its draw is named.
  size_t gone = 0;
  while (json::parse(events[gone])["type"] != "shot") ++gone;
  const double t = json::parse(events[gone])["t"];
  const std::string actor = json::parse(events[gone])["actor"];
  std::vector<std::string> fewer = events;
  fewer.erase(fewer.begin() + long(gone));
  write_lines(folder / "fewer.jsonl", fewer);
  const Said missing = audit({logs.decisions, folder / "fewer.jsonl"});
  EXPECT_EQ(missing.code, 1) << missing;
  EXPECT_NE(missing.out.find("the outcome \"" + actor + "\" (body) has no event in "), std::string::npos) << missing;
  EXPECT_NE(missing.out.find("audit: FAILED\n" + logs.decisions.string() + ":"), std::string::npos) << missing;
  // An event of another player at that time.
  std::vector<std::string> other = events;
  json changed = json::parse(other[gone]);
  changed["actor"] = actor == "Red's mallet" ? "Blue's mallet" : "Red's mallet";
  other[gone] = changed.dump();
  write_lines(folder / "other.jsonl", other);
  EXPECT_EQ(audit({logs.decisions, folder / "other.jsonl"}).code, 1);
  // A goal no draw made: the event is named.
  std::vector<std::string> more = events;
  more.insert(more.begin() + long(gone) + 1,
              json{{"t", t + 0.001}, {"type", "goal"}, {"actor", "Red's goal"}, {"team", "Red"}}.dump());
  write_lines(folder / "more.jsonl", more);
  const Said extra = audit({logs.decisions, folder / "more.jsonl"});
  EXPECT_EQ(extra.code, 1) << extra;
  EXPECT_NE(extra.out.find((folder / "more.jsonl").string() + ":" + std::to_string(gone + 2) + " (t = " +
                           shortest(t + 0.001) + "): an event of \"Red's goal\" that no draw in "),
            std::string::npos) << extra;
}

TEST(Audit, OutcomesThatFollowOtherChancesFailTheStatistics) {
  Folder folder;
  // Bodies three times likelier than logged: every draw adds up, the outcomes do not follow.
  const Logs logs = synthetic(folder, "biased", 7, 3000, 3);
  const Said said = audit({logs.decisions, logs.events});
  EXPECT_EQ(said.code, 1) << said;
  EXPECT_NE(said.out.find("plausible: 3000 draws, 0 with a violation"), std::string::npos) << said;
  EXPECT_NE(said.out.find(" 0 unmatched "), std::string::npos) << said;
  EXPECT_NE(said.out.find("audit: FAILED\ncalibration by kind: the outcomes do not follow their chances (p = "),
            std::string::npos) << said;
  // Each test alone sees it.
  for (const char* test : {"calibration by kind", "calibration by chance", "probability integral transform"}) {
    const size_t at = said.out.find(std::string(test) + ": ");
    ASSERT_NE(at, std::string::npos) << test;
    const std::string line = said.out.substr(at, said.out.find('\n', at) - at);
    const size_t p = line.find(", p = ");
    ASSERT_NE(p, std::string::npos) << line;
    EXPECT_LT(std::stod(line.substr(p + 6)), 0.001) << line;
  }
}

TEST(Audit, FewDrawsSkipTheStatistics) {
  Folder folder;
  const Logs logs = synthetic(folder, "few", 8, 50);
  const Said said = audit({logs.decisions, logs.events});
  EXPECT_EQ(said.code, 0) << said;
  EXPECT_NE(said.out.find("calibration by kind: skipped: too few draws (50, needs 100)\n"), std::string::npos) << said;
  EXPECT_NE(said.out.find("probability integral transform: skipped: too few draws"), std::string::npos) << said;
}

TEST(Audit, AVersionOneLogIsRefusedWithWhatToDo) {
  Folder folder;
  const Logs logs = synthetic(folder, "honest", 9, 20);
  std::vector<std::string> lines = lines_of(logs.decisions);
  lines.erase(lines.begin());  // no header: as engines before it wrote
  write_lines(folder / "v1.jsonl", lines);
  const Said said = audit({folder / "v1.jsonl", logs.events});
  EXPECT_EQ(said.code, 2) << said;
  EXPECT_EQ(said.out, "");
  EXPECT_NE(said.err.find("a version-1 decision log"), std::string::npos) << said;
  EXPECT_NE(said.err.find("needs version 2: play the match again with --decisions"), std::string::npos) << said;
  lines.insert(lines.begin(), R"({"format":"quantum decisions","version":3})");
  write_lines(folder / "v3.jsonl", lines);
  EXPECT_EQ(audit({folder / "v3.jsonl"}).code, 2);
}

TEST(Audit, WhatIsNotALogIsRefusedNamingFileAndLine) {
  Folder folder;
  const Logs logs = synthetic(folder, "honest", 10, 20);
  auto refused = [&](const std::string& name, const std::vector<std::string>& lines, const std::string& says) {
    write_lines(folder / name, lines);
    const Said said = audit({folder / name});
    EXPECT_EQ(said.code, 2) << name << ": " << said;
    EXPECT_NE(said.err.find((folder / name).string() + says), std::string::npos) << name << ": " << said;
  };
  refused("garbage.txt", {"hello, world"}, ":1: not JSON");
  refused("binary.bin", {std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10)}, ":1: not JSON");
  refused("empty.jsonl", {}, ": empty, not a log");
  refused("list.jsonl", {"[1, 2, 3]"}, ":1: not a JSON object");
  refused("other.jsonl", {R"({"name":"not a log"})"}, ": neither a decision log");
  refused("deep.jsonl", {std::string(100000, '[')}, ":1: nested deeper than");
  // Draw lines that are not what the format says: a clear word, never a crash.
  std::vector<std::string> lines = lines_of(logs.decisions);
  auto with = [&](size_t at, const std::string& line) {
    std::vector<std::string> changed = lines;
    changed[at] = line;
    return changed;
  };
  json draw = json::parse(lines[3]);
  refused("cut.jsonl", with(3, lines[3].substr(0, lines[3].size() / 2)), ":4: not JSON");
  json text = draw;
  text["draw"][0]["p"] = "0.5";
  refused("text.jsonl", with(3, text.dump()), ":4: draw[0]: \"p\" is not a number");
  json null = draw;
  null["u"] = nullptr;
  refused("null.jsonl", with(3, null.dump()), ":4: \"u\" is not a number");
  json missing = draw;
  missing.erase("draw");
  refused("missing.jsonl", with(3, missing.dump()), ":4: no \"draw\"");
  json overflow = draw;
  overflow["u"] = "U";
  std::string huge = overflow.dump();
  huge.replace(huge.find("\"U\""), 3, "1e999");
  refused("huge.jsonl", with(3, huge), ":4: not JSON ([json.exception.out_of_range.406] number overflow");
  json kind = draw;
  kind["draw"][0]["kind"] = "teleport";
  refused("kind.jsonl", with(3, kind.dump()), ":4: draw[0]: \"kind\" \"teleport\" is none of");
  json groups = draw;
  groups["draw"][0]["groups"] = {{0.5, 1}};
  if (draw["draw"][0]["kind"] != "tackle") refused("groups.jsonl", with(3, groups.dump()), ":4: draw[0]: groups[0]");
  refused("header.jsonl", with(3, lines[0]), ":4: a second header");
  // Files that cannot be read at all.
  const Said none = audit({folder / "nowhere.jsonl"});
  EXPECT_EQ(none.code, 2) << none;
  EXPECT_NE(none.err.find("nowhere.jsonl: does not exist"), std::string::npos) << none;
  const Said dir = audit({folder.path});
  EXPECT_EQ(dir.code, 2) << dir;
  EXPECT_NE(dir.err.find("a folder, not a log"), std::string::npos) << dir;
  const Said events_only = audit({logs.events});
  EXPECT_EQ(events_only.code, 2) << events_only;
  EXPECT_NE(events_only.err.find("no decision log among the files"), std::string::npos) << events_only;
}

// On a terminal the draws read are counted on stderr, and the count is wiped before the report.
TEST(Audit, ProgressIsCountedOnStderrOnlyWhenAsked) {
  Folder folder;
  const fs::path log = folder / "long.jsonl";
  {
    std::ofstream out(log);
    out << R"({"format":"quantum decisions","version":2})" << '\n';
    std::mt19937_64 rng(3);
    for (int k = 0; k < 50'010; ++k) {
      const double u = double(rng() >> 11) * 0x1.0p-53;
      out << R"({"t":)" << shortest(k / 60.0) << R"(,"u":)" << shortest(u)
          << R"(,"draw":[{"kind":"out","actor":"out","p":0.25,"p_newtonian":0.25,"particles":1,"mass":0.25,)"
          << R"("factor":1,"factors":[{"source":"sport","value":1}],"weight":0.25,"groups":[[-1,0.25,1]]}],)"
          << R"("rest":{"mass":0.75,"weight":0.75},"all_met":false,"outcome":")" << (u < 0.25 ? "out" : "none")
          << R"(","fates":[]})" << '\n';
    }
  }
  const Said quiet = audit({log});
  EXPECT_EQ(quiet.code, 0) << quiet;
  EXPECT_EQ(quiet.err, "");
  const Said counted = audit({log}, true);
  EXPECT_EQ(counted.code, 0) << counted;
  const std::string count = "audit: 50000 draws read";
  EXPECT_EQ(counted.err, "\r" + count + "\r" + std::string(count.size(), ' ') + "\r");
  EXPECT_EQ(counted.out, quiet.out);
}

}  // namespace
}  // namespace quantum
