// Hot reload: scripts edited while a match runs take effect between two frames; a broken edit is
// reported with its file and line and the old version goes on; the match keeps its state.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "reloader.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// A copy of rules/airhockey and rules/powerups in a fresh folder, to edit.
struct Rules {
  fs::path root, sport, powerups;
  explicit Rules(const std::string& name) {
    root = fs::temp_directory_path() / ("quantum_reload_" + name);
    fs::remove_all(root);
    sport = root / "airhockey", powerups = root / "powerups";
    fs::create_directories(root);
    fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", sport, fs::copy_options::recursive);
    fs::copy(QUANTUM_SOURCE_DIR "/rules/powerups", powerups, fs::copy_options::recursive);
  }
  ~Rules() { fs::remove_all(root); }
  // The sport's sport.lua with `lines` run just before it returns its table.
  std::string sport_ending_with(const std::string& lines) const {
    std::ifstream in(sport / "sport.lua");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    s.replace(s.rfind("return sport"), 12, lines + "return sport");
    return s;
  }
  void write(const fs::path& file, const std::string& text) const {
    // As an editor saves: a new file renamed over the old one.
    const fs::path tmp = file.string() + ".tmp";
    std::ofstream(tmp) << text;
    fs::rename(tmp, file);
  }
};

struct Running {
  std::unique_ptr<lua::ScriptedRules> sport;
  std::unique_ptr<game::Match> match;
  std::vector<BodyInput> still;

  explicit Running(const Rules& r) {
    sport = std::make_unique<lua::ScriptedRules>(r.sport.string());
    game::MatchConfig config;
    config.particles = 400;
    match = std::make_unique<game::Match>(sport->spec().field, config, *sport);
    for (const BodySpec& b : sport->spec().field.bodies) still.push_back({b.start, {0, 0}});
    still[1].position = {0.88f, 0.06f};  // Red's mallet half in the way of a shot
    Cloud ball;
    for (int i = 0; i < 200; ++i) {
      const double a = 0.1 * (i / 199.0 - 0.5);
      ball.push(0.5f, 0.0f, float(2.5 * std::cos(a)), float(2.5 * std::sin(a)), 1.0 / 200, 1.0 / 200);
    }
    match->set_scene(still, ball, 0);
  }

  double red_intercept() const {
    double p = 0;
    for (const game::FateView& f : match->fates())
      if (f.fate.kind == FateKind::Body && f.actor == "Red's mallet") p += f.tweaked;
    return p;
  }
};

// inotify delivers the rename a moment later: poll until something reloads or fails (or 1 s).
int poll_until_reloaded(lua::Reloader& reloader, Running& m, std::ostringstream& errors) {
  for (int tries = 0; tries < 50; ++tries) {
    if (const int n = reloader.poll(m.sport, *m.match, errors)) return n;
    if (!errors.str().empty()) return 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return 0;
}

TEST(Reload, AnEditedPowerUpActsFromTheNextFrame) {
  const Rules r("powerup");
  Running m(r);
  lua::Reloader reloader(*m.sport);
  m.sport->grant(*m.match, 1, "penalty", {{"strength", 0.5}});
  m.match->step(m.still);
  const double before = m.red_intercept();
  ASSERT_GT(before, 0.1);
  // The designer makes the penalty total while the match runs.
  r.write(r.powerups / "penalty.lua",
          "return { duration = 10, defaults = { strength = 0.3 },\n"
          "  factor = function(fate, holder, game, p)\n"
          "    if fate.kind == 'body' and fate.actor == holder.name then return 0 end\n"
          "  end }\n");
  std::ostringstream errors;
  EXPECT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
  m.match->step(m.still);
  EXPECT_EQ(m.red_intercept(), 0.0) << "the new penalty acts at once";
  EXPECT_EQ(m.match->powerups().size(), 1u);  // still held, with its time
  EXPECT_EQ(errors.str(), "quantum: reloaded power-up penalty\n");  // one line, as a failure has
}

TEST(Reload, ABrokenEditIsReportedAndTheOldVersionGoesOn) {
  const Rules r("broken");
  Running m(r);
  lua::Reloader reloader(*m.sport);
  m.sport->grant(*m.match, 1, "penalty", {{"strength", 0.5}});
  m.match->step(m.still);
  const double before = m.red_intercept();
  const int stack = lua_gettop(m.sport->L());
  r.write(r.powerups / "penalty.lua", "return {\n  duration = 10,\n  factor = function(fate\n}\n");
  std::ostringstream errors;
  poll_until_reloaded(reloader, m, errors);
  EXPECT_EQ(lua_gettop(m.sport->L()), stack);  // a failed load leaves nothing behind
  EXPECT_NE(errors.str().find("reload failed: "), std::string::npos) << errors.str();
  EXPECT_NE(errors.str().find("penalty.lua:4:"), std::string::npos) << errors.str();
  EXPECT_NE(errors.str().find("the previous version goes on"), std::string::npos) << errors.str();
  m.match->step(m.still);
  EXPECT_NEAR(m.red_intercept(), before, 0.05);  // the old penalty still acts
  // Fixed, it loads.
  r.write(r.powerups / "penalty.lua",
          "return { duration = 10, factor = function(fate, holder) if fate.actor == holder.name then return 0 end end }\n");
  std::ostringstream later;
  EXPECT_EQ(poll_until_reloaded(reloader, m, later), 1) << later.str();
  m.match->step(m.still);
  EXPECT_EQ(m.red_intercept(), 0.0);
}

TEST(Reload, ANewVersionKeepsItsOwnStateWhenTheOldHadNone) {
  const Rules r("fresh_state");
  Running m(r);
  lua::Reloader reloader(*m.sport);
  r.write(r.sport / "sport.lua", r.sport_ending_with("sport.state = { greeting = 'Hello there' }\n"
                                                     "sport.on.intercept = function(game, e) game.say(sport.state.greeting) end\n"));
  std::ostringstream errors;
  ASSERT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
  for (int frame = 0; frame < 120 && m.match->said().empty(); ++frame) m.match->step(m.still);
  ASSERT_FALSE(m.match->said().empty()) << (m.match->errors().empty() ? "" : m.match->errors()[0]);
  EXPECT_EQ(m.match->said().back().text, "Hello there");
  EXPECT_TRUE(m.match->errors().empty()) << m.match->errors()[0];
}

// A constant kept in the sport table is code, not state: the new version's value is the one its
// handlers read.
TEST(Reload, AHandlerReadsTheNewVersionsOwnKeys) {
  const Rules r("own_keys");
  const std::string says_cheer = "sport.on.intercept = function(game, e) game.say(sport.cheer .. ' x' .. sport.hp) end\n";
  r.write(r.sport / "sport.lua", r.sport_ending_with("sport.cheer = 'Well held'\nsport.hp = 1\n" + says_cheer));
  Running m(r);
  lua::Reloader reloader(*m.sport);
  r.write(r.sport / "sport.lua", r.sport_ending_with("sport.cheer = 'Held again'\nsport.hp = 2\n" + says_cheer));
  std::ostringstream errors;
  ASSERT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
  for (int frame = 0; frame < 120 && m.match->said().empty(); ++frame) m.match->step(m.still);
  ASSERT_FALSE(m.match->said().empty()) << (m.match->errors().empty() ? "" : m.match->errors()[0]);
  EXPECT_EQ(m.match->said().back().text, "Held again x2");
  EXPECT_TRUE(m.match->errors().empty()) << m.match->errors()[0];
}

// The old state is copied by the engine, in C: a state too deep or too large for it is refused
// whole with the limit named (60,000 entries are 120,000 keys and values), on_reload gets
// nothing, and the match goes on.
TEST(Reload, AStateTooDeepOrTooLargeToCarryIsReportedAndTheMatchGoesOn) {
  const std::vector<std::pair<std::string, std::string>> states = {
      {"local t = {} sport.state = t for i = 1, 1000 do t.next = {} t = t.next end\n", "more than 100 deep"},
      {"sport.state = {} for i = 1, 60000 do sport.state[i] = i end\n", "more than 100000 values"}};
  for (const auto& [state, limit] : states) {
    const Rules r("too_much_state");
    r.write(r.sport / "sport.lua", r.sport_ending_with(state));
    Running m(r);
    lua::Reloader reloader(*m.sport);
    r.write(r.sport / "sport.lua",
            r.sport_ending_with("sport.on_reload = function(game, old) game.say(old and 'carried' or 'nothing carried') end\n"));
    std::ostringstream errors;
    ASSERT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
    ASSERT_EQ(m.match->errors().size(), 1u) << limit;
    EXPECT_NE(m.match->errors()[0].find("could not be carried over"), std::string::npos) << m.match->errors()[0];
    EXPECT_NE(m.match->errors()[0].find(limit), std::string::npos) << m.match->errors()[0];
    ASSERT_FALSE(m.match->said().empty());
    EXPECT_EQ(m.match->said().back().text, "nothing carried");
    for (int frame = 0; frame < 10; ++frame) m.match->step(m.still);
    EXPECT_TRUE(m.match->world().live());
  }
}

// A reload loads between two frames of a running match, so within a frame's budget: a version
// that spends twice a frame's CPU loading is refused, named, and the old one goes on.
TEST(Reload, AVersionThatLoadsLongerThanAFrameIsRefused) {
  const Rules r("slow_load");
  Running m(r);
  lua::Reloader reloader(*m.sport);
  const std::string twice_a_frame = std::to_string(2 * lua::Limits{}.cpu_seconds);
  r.write(r.sport / "sport.lua",
          r.sport_ending_with("local t = os.clock() while os.clock() - t < " + twice_a_frame + " do end\n"));
  std::ostringstream errors;
  EXPECT_EQ(poll_until_reloaded(reloader, m, errors), 0);
  EXPECT_NE(errors.str().find("reload failed"), std::string::npos) << errors.str();
  EXPECT_NE(errors.str().find("script runs too long"), std::string::npos) << errors.str();
  m.match->step(m.still);
  EXPECT_TRUE(m.match->world().live());
}

TEST(Reload, AReloadedSportKeepsTheMatchAndCarriesItsState) {
  const Rules r("sport");
  Running m(r);
  lua::Reloader reloader(*m.sport);
  m.match->award("red", 2);
  m.sport->grant(*m.match, 0, "attract", {});
  // The new version changes a phrase and takes its state over in on_reload.
  const std::string s = r.sport_ending_with(
      "sport.state = { reloads = 0 }\n"
      "sport.on_reload = function(game, old)\n"
      "  sport.state = { reloads = ((old and old.reloads) or 0) + 1 }\n"
      "  sport.state.self = sport.state\n"
      "  game.say('reloaded ' .. sport.state.reloads .. ' times' .. (old and old.self == old and ', cycle kept' or ''))\n"
      "end\n");
  r.write(r.sport / "sport.lua", s);
  std::ostringstream errors;
  ASSERT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
  r.write(r.sport / "sport.lua", s);  // and once more: the state comes along
  ASSERT_EQ(poll_until_reloaded(reloader, m, errors), 1) << errors.str();
  std::vector<std::string> said;
  for (const game::Said& x : m.match->said()) said.push_back(x.text);
  ASSERT_GE(said.size(), 2u);
  EXPECT_EQ(said[said.size() - 2], "reloaded 1 times");
  EXPECT_EQ(said.back(), "reloaded 2 times, cycle kept");  // a table met again is the same table
  EXPECT_EQ(m.match->score().at("red"), 2);          // the score stays
  EXPECT_EQ(m.match->powerups().size(), 1u);         // and the power-up with it
  m.match->step(m.still);                            // the match goes on under the new rules
  EXPECT_TRUE(m.match->world().live());
}

}  // namespace
}  // namespace quantum
