// The decision log of real matches against `quantum audit` (docs/decisions.md): every shipped
// sport, played with a handicap, automatic balance and power-ups (one that weighs a player's
// touches, one that disables another player), writes a log that passes; the same log tampered
// with in the ways a doctored log would be fails, naming the draw.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../shipped_sports.h"
#include "audit.h"
#include "log_files.h"
#include "field_loader.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using test::lines_of;
using test::write_lines;

struct Logs {
  fs::path decisions, events;
  bool skipped = false;  // the rules reported a frame whose fates' factors were all 0
};

// A seeded match of `sport` whose first player plays with handicap 2 and the power-up attract
// (strength 2), and whose second (when there is one) is penalized to 0, under automatic balance.
Logs play(const std::string& sport, double seconds, uint64_t seed) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_decision_log_" + sport + "_" + std::to_string(seed));
  fs::remove_all(dir);
  fs::create_directories(dir);
  runtime::SessionOptions o;
  o.sport = std::string(QUANTUM_SOURCE_DIR "/rules/") + sport;
  o.seconds = seconds;
  o.seed = seed;
  o.particles = 500;
  o.auto_balance = 0.5;
  const size_t players = lua::load_field(o.sport).bodies.size();
  o.handicaps.assign(players, 1.0);
  o.handicaps[0] = 2;
  o.decisions = (dir / "decisions.jsonl").string();
  o.events = (dir / "events.jsonl").string();
  std::ostringstream errors;
  {
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    game::Match& m = session.match();
    m.grant(0, "attract", 3600, {{"strength", 2}});
    if (players > 1) m.grant(1, "penalty", 3600, {{"strength", 0}});
    session.run();
  }
  // A ball whose every fate ends at the penalized player skips that frame's fates' factors, which
  // the rules report (and the log marks); nothing else may go wrong.
  std::istringstream lines(errors.str());
  for (std::string line; std::getline(lines, line);)
    EXPECT_NE(line.find("this frame's factors are skipped"), std::string::npos) << sport << ": " << line;
  return {o.decisions, o.events, !errors.str().empty()};
}

int audit(const std::vector<fs::path>& files, std::string& said) {
  std::vector<std::string> names;
  for (const fs::path& f : files) names.push_back(f.string());
  std::ostringstream out, err;
  const int code = tools::audit(names, out, err, false);
  said = out.str() + err.str();
  return code;
}

class EverySport : public testing::TestWithParam<const char*> {};

TEST_P(EverySport, ALogWithHandicapsAndPowerupsPassesTheAudit) {
  const Logs logs = play(GetParam(), 120, 5);
  std::string said;
  EXPECT_EQ(audit({logs.decisions, logs.events}, said), 0) << said;
  EXPECT_NE(said.find("audit: passed"), std::string::npos) << said;
  // The log is what it says: a header, then draws with their terms.
  const std::vector<std::string> lines = lines_of(logs.decisions);
  ASSERT_GT(lines.size(), 100u) << GetParam();
  const nlohmann::json header = nlohmann::json::parse(lines[0]);
  EXPECT_EQ(header.at("format"), "quantum decisions");
  EXPECT_EQ(header.at("version"), 2);
  EXPECT_EQ(header.at("players").at(0).at("handicap"), 2.0);
  bool powerup_term = false;
  for (size_t k = 1; k < lines.size() && !powerup_term; ++k)
    powerup_term = lines[k].find("\"source\":\"powerup\",\"name\":\"attract\"") != std::string::npos;
  EXPECT_TRUE(powerup_term) << GetParam() << ": no draw names the power-up among its factors";
  if (logs.skipped) {  // what stderr said of a frame, its draws say too
    bool marked = false;
    for (size_t k = 1; k < lines.size() && !marked; ++k) marked = lines[k].find("\"factors_skipped\":true") != std::string::npos;
    EXPECT_TRUE(marked) << GetParam() << ": frames with skipped factors, but no draw marked factors_skipped";
  }
}

INSTANTIATE_TEST_SUITE_P(DecisionLog, EverySport, testing::ValuesIn(test::kShippedSports),
                         [](const testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

// One draw of the log changed by `tamper` (which returns false for a draw it cannot use): the
// audit fails and names that draw's time.
template <class Tamper>
void expect_caught(const Logs& logs, const std::string& what, Tamper tamper) {
  std::vector<std::string> lines = lines_of(logs.decisions);
  std::string when;
  for (size_t k = 1; k < lines.size() && when.empty(); ++k) {
    nlohmann::json d = nlohmann::json::parse(lines[k]);
    if (!tamper(d)) continue;
    std::ostringstream t;
    t << d.at("t").get<double>();
    when = t.str();
    lines[k] = d.dump();
  }
  ASSERT_FALSE(when.empty()) << what << ": no draw to tamper with";
  const fs::path tampered = logs.decisions.parent_path() / "tampered.jsonl";
  write_lines(tampered, lines);
  std::string said;
  EXPECT_EQ(audit({tampered, logs.events}, said), 1) << what << "\n" << said;
  EXPECT_NE(said.find("FAILED"), std::string::npos) << what << "\n" << said;
}

TEST(DecisionLog, ATamperedLogFailsTheAudit) {
  const Logs logs = play("airhockey", 120, 7);
  std::string said;
  ASSERT_EQ(audit({logs.decisions, logs.events}, said), 0) << said;
  // A changed chance.
  expect_caught(logs, "a changed probability", [](nlohmann::json& d) {
    nlohmann::json& option = d.at("draw").at(0);
    if (option.at("p").get<double>() < 0.01) return false;
    option["p"] = option.at("p").get<double>() * 0.9;
    return true;
  });
  // A realized outcome swapped for another option of the same draw.
  expect_caught(logs, "a swapped outcome", [](nlohmann::json& d) {
    if (d.at("outcome") == "none" || d.at("draw").size() < 2) return false;
    for (const nlohmann::json& option : d.at("draw"))
      if (option.at("actor") != d.at("outcome")) {
        d["outcome"] = option.at("actor");
        return true;
      }
    return false;
  });
  // A uniform number that does not give the outcome logged.
  expect_caught(logs, "a draw whose u does not give its outcome", [](nlohmann::json& d) {
    if (d.at("outcome") != "none") return false;
    double sum = 0;
    for (const nlohmann::json& option : d.at("draw")) sum += option.at("p").get<double>();
    if (sum < 0.05) return false;
    d["u"] = sum / 2;  // inside the options: something was met
    return true;
  });
  // A missing event: the first realized touch's event line removed.
  std::vector<std::string> events = lines_of(logs.events);
  bool removed = false;
  for (size_t k = 0; k < events.size() && !removed; ++k)
    if (nlohmann::json::parse(events[k]).at("type") == "shot") events.erase(events.begin() + long(k)), removed = true;
  ASSERT_TRUE(removed);
  const fs::path fewer = logs.events.parent_path() / "fewer_events.jsonl";
  write_lines(fewer, events);
  EXPECT_EQ(audit({logs.decisions, fewer}, said), 1) << said;
  EXPECT_NE(said.find("FAILED"), std::string::npos) << said;
}

}  // namespace
}  // namespace quantum
