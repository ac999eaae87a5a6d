// The rules API that sports written from the docs asked for: strict reading of sport.lua and
// power-ups (a near miss of the engine's keys named with the key it slips from, the script's own
// keys kept for its handlers), phrases checked at load and when said, a factor that zeroes every
// fate named, modules, each event's own phrases in the log, and hints that make simulated players
// take turns and aim where the sport says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "lua_reader.h"
#include "recording.h"
#include "session.h"
#include "scripted_rules.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// A sport folder holding the air hockey table (or the field of `field_of`, a sport's folder),
// the given sport.lua and any other files.
std::string sport_with(const std::string& name, const std::string& sport,
                       const std::map<std::string, std::string>& files = {},
                       const std::string& field_of = QUANTUM_SOURCE_DIR "/rules/airhockey") {
  const fs::path dir = fs::temp_directory_path() / ("quantum_rules_api_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(fs::path(field_of) / "field.lua", dir / "field.lua");
  std::ofstream(dir / "sport.lua") << sport;
  for (const auto& [file, text] : files) {
    fs::create_directories((dir / file).parent_path());
    std::ofstream(dir / file) << text;
  }
  return dir.string();
}

std::string load_error(const std::string& name, const std::string& sport,
                       const std::map<std::string, std::string>& files = {}) {
  try {
    lua::ScriptedRules s(sport_with(name, sport, files));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Plays `seconds` of the sport between simulated players; returns the rule errors reported.
std::string rule_errors(const std::string& folder, double seconds = 3, uint64_t seed = 1) {
  runtime::SessionOptions o;
  o.sport = folder;
  o.seconds = seconds;
  o.seed = seed;
  o.particles = 300;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
  return errors.str();
}

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

TEST(SportFile, UnknownKeysAreNamedWithTheNearestKnownOne) {
  EXPECT_HAS(load_error("top", "return { phrase = {} }"), "sport.lua: unknown key 'phrase' (did you mean 'phrases'?");
  EXPECT_HAS(load_error("factor", "return { factors = { goals = 2 } }"),
             "sport.lua: factors: unknown key 'goals' (did you mean 'goal'?");
  EXPECT_HAS(load_error("handicap", "return { handicaps = { [\"Blue mallet\"] = 2 } }"),
             "handicaps: unknown key 'Blue mallet' (did you mean 'Blue's mallet'?");
  EXPECT_HAS(load_error("sound", "return { audio = { sounds = { gaol = 'goal.wav' } } }"),
             "audio.sounds: unknown key 'gaol' (did you mean 'goal'?");
  EXPECT_HAS(load_error("team", "return { teams = { bleu = 'Blue' } }"), "teams: unknown key 'bleu' (did you mean 'blue'?");
  // The match table may hold the sport's own settings, but not a slip of the engine's.
  EXPECT_HAS(load_error("match", "return { match = { secnds = 10 } }"), "match: unknown key 'secnds' (did you mean 'seconds'?");
  EXPECT_EQ(load_error("own", "return { match = { seconds = 10, first_to = 3 } }"), "");
}

// A near miss is a slip of the keyboard, not any word: Phrases, phrase, modifer and on_relaod are
// slips; hp, id and ok beside on, or turn_factor beside factors, are other words.
TEST(SportFile, ANearMissIsASlipOfTheKeyboard) {
  const std::vector<std::string> sport = {"name", "phrases", "factors", "modifiers", "on", "on_reload"};
  EXPECT_EQ(lua::near_miss("Phrases", sport), "phrases");
  EXPECT_EQ(lua::near_miss("phrase", sport), "phrases");
  EXPECT_EQ(lua::near_miss("factor", sport), "factors");
  EXPECT_EQ(lua::near_miss("on_relaod", sport), "on_reload");  // a swap is one slip
  EXPECT_EQ(lua::near_miss("modifer", sport), "modifiers");    // two in a key of eight letters or more
  EXPECT_EQ(lua::near_miss("ON", sport), "on");
  EXPECT_EQ(lua::near_miss("nmae", sport), "name");
  for (const char* own : {"hp", "id", "ok", "no", "turn_factor", "streak_reward", "names_of", "modify", "phrasebook"})
    EXPECT_EQ(lua::near_miss(own, sport), "") << own;
  EXPECT_EQ(lua::near_miss("moodifer", sport), "");  // three slips
}

TEST(SportFile, ANearMissOfTheEnginesKeysIsRefusedWithTheKeyItSlipsFrom) {
  const std::vector<std::pair<std::string, std::string>> slips = {
      {"phrase", "phrases"},     {"Phrases", "phrases"},   {"factor", "factors"}, {"on_relaod", "on_reload"},
      {"handicap", "handicaps"}, {"modifer", "modifiers"}, {"On", "on"}};
  for (const auto& [key, known] : slips) {
    const std::string e = load_error("slip_" + known, "return { " + key + " = {} }");
    EXPECT_HAS(e, "sport.lua: unknown key '" + key + "' (did you mean '" + known + "'? known: name, field,");
    EXPECT_HAS(e, "keys of your own are welcome here, but this one looks like a typo");
  }
  EXPECT_HAS(load_error("match_case", "return { match = { Seconds = 10 } }"),
             "match: unknown key 'Seconds' (did you mean 'seconds'?");
  EXPECT_HAS(load_error("match_swap", "return { match = { strat = 'blue' } }"), "match: unknown key 'strat' (did you mean 'start'?");
}

TEST(SportFile, ASportsOwnKeysLoad) {
  // Two letters are too few for a slip: hp and id are the sport's own, in its table and its match.
  EXPECT_EQ(load_error("own_short", "return { hp = 3, id = 'x', ok = true, match = { hp = 3, id = 'x', first_to = 5 } }"), "");
  EXPECT_EQ(load_error("own_kinds", "return { turn_factor = 2, streak_reward = { 3, 5 }, bonus = function() end }"), "");
}

TEST(SportFile, AMetatableOnTheSportTableRunsNothing) {
  // Read raw: an __index that errors (or loops) is never called while the engine reads.
  EXPECT_EQ(load_error("meta", "return setmetatable({ name = 'x' }, { __index = function() error('boom') end })"), "");
}

TEST(SportFile, PhrasesAreCheckedWhenTheSportLoads) {
  EXPECT_HAS(load_error("brace", "return { phrases = { shot = '{team shoots' } }"), "phrases.shot: '{' at character 1 is never closed");
  EXPECT_HAS(load_error("format", "return { phrases = { speed = '{speed:%s} m/s' } }"),
             "phrases.speed: {speed:%s}: the format must be like %d, %.1f");
  // Phrases the engine says itself may only use what the engine fills in.
  EXPECT_HAS(load_error("paused", "return { phrases = { paused = 'Where is {who}?' } }"),
             "phrases.paused: unknown placeholder 'who'");
  EXPECT_HAS(load_error("powerup", "return { phrases = { attract_start = '{playr} attracts it' } }"),
             "phrases.attract_start: unknown placeholder 'playr' (did you mean 'player'? known: player, team)");
  // {player} and {team} are always text: a number format there could only fail when said.
  EXPECT_HAS(load_error("text_format", "return { phrases = { attract_over = '{team:%.1f} is free' } }"),
             "phrases.attract_over: {team} is text: it takes no number format");
  EXPECT_HAS(load_error("recorded", "return { phrases = { goal = 'Goal!' }, audio = { recorded = { gaol = 'x.ogg' } } }"),
             "audio.recorded: unknown key 'gaol' (did you mean 'goal'?");
}

TEST(SportFile, PowerUpScriptsAreReadStrictly) {
  const std::string folder = sport_with("strict_powerup", "return { on = { drop = function(game, e) game.grant(\"Red's mallet\", 'spin') end } }",
                                        {{"powerups/spin.lua", "return { duration = 5, factr = function() return 2 end }"}});
  const std::string errors = rule_errors(folder, 0.1);
  EXPECT_HAS(errors, "powerups/spin.lua: unknown key 'factr' (did you mean 'factor'?");
  EXPECT_HAS(errors, "game.grant");
  const std::string formatted = rule_errors(
      sport_with("powerup_format", "return { on = { drop = function(game, e) game.grant(\"Red's mallet\", 'spin') end } }",
                 {{"powerups/spin.lua", "return { duration = 5, factor = function() end, phrases = { over = '{player:%d} is free' } }"}}),
      0.1);
  EXPECT_HAS(formatted, "powerups/spin.lua: phrases.over: {player} is text: it takes no number format");
}

TEST(SportFile, APowerUpKeepsItsOwnKeysButNotANearMiss) {
  const std::string grant = "return { on = { drop = function(game, e) game.grant(\"Red's mallet\", 'spin') end } }";
  for (const auto& [key, known] : std::vector<std::pair<std::string, std::string>>{
           {"Factor = 2", "factor"}, {"durration = 5", "duration"}, {"defualts = {}", "defaults"}, {"stp = 1", "stop"}}) {
    const std::string errors = rule_errors(
        sport_with("powerup_slip_" + known, grant,
                   {{"powerups/spin.lua", "return { duration = 5, factor = function() end, " + key + " }"}}),
        0.1);
    EXPECT_HAS(errors, "powerups/spin.lua: unknown key '" + key.substr(0, key.find(' ')) + "' (did you mean '" + known + "'?");
  }
  EXPECT_EQ(rule_errors(sport_with("powerup_own", grant,
                                   {{"powerups/spin.lua", "return { duration = 5, factor = function() end, hp = 2, "
                                                          "pull = { 1, 2 }, helper = function() end }"}}),
                        0.1),
            "");
}

TEST(SportRules, AGrantTooLongIsRefusedBeforeThePowerUpStarts) {
  lua::ScriptedRules sport(sport_with("long_grant", "return {}"));
  game::MatchConfig config;
  config.particles = 100;
  game::Match match(sport.spec().field, config, sport);
  EXPECT_THROW(sport.grant(match, 0, "wormhole", {{"seconds", 5000}}), std::invalid_argument);
  EXPECT_TRUE(match.world().wormholes().empty());  // its start never ran
  EXPECT_TRUE(match.powerups().empty());
}

TEST(SportRules, AnUnknownPlayerLeavesTheTurnsAsTheyWere) {
  const std::string folder = sport_with("turn", R"(return { on = { drop = function(game, e)
  game.turn("red")
  game.turn("bleu")
end } })");
  runtime::SessionOptions o;
  o.sport = folder;
  o.seconds = 0.1;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
  EXPECT_HAS(errors.str(), "game.turn: unknown player 'bleu'");
  EXPECT_FALSE(session.match().players()[0].turn);  // as game.turn("red") left it
  EXPECT_TRUE(session.match().players()[1].turn);
}

TEST(SportRules, AnUnknownPhraseKeyOrAMissingValueIsAnErrorAtItsLine) {
  const std::string errors = rule_errors(sport_with("say", R"(return {
  phrases = { goal = "Goal for {team}!", drop = "Dropped {spot}" },
  on = {
    drop = function(game, e)
      game.say("drop", { spot = e.actor })
      local key = "gaol"  -- made at run time: checked when said
      game.say(key)
    end,
    shot = function(game, e) game.say("goal", { tema = "Blue" }) end,
  },
})"), 10);
  EXPECT_HAS(errors, "sport.lua:7: game.say: no phrase 'gaol'");
  EXPECT_HAS(errors, "(did you mean 'goal'?");
  EXPECT_HAS(errors, "sport.lua:9: game.say: phrase 'goal': no value for {team}");
}

TEST(SportFile, ALiteralPhraseKeyIsCheckedWhenTheSportLoads) {
  const std::string e = load_error("literal_key", "local names = require 'lib.names'\nreturn { phrases = { goal = 'Goal!' } }",
                                   {{"lib/names.lua", "-- game.say('in a comment') is not code\n"
                                                      "return { f = function(game) game.say('gaol') end }"}});
  EXPECT_HAS(e, "lib/names.lua:2: game.say(\"gaol\"): unknown phrase key 'gaol' (did you mean 'goal'?");
  EXPECT_EQ(load_error("literal_text", "return { on = { drop = function(game) game.say('Well played!') end } }"), "");
}

TEST(SportRules, AFactorThatZeroesEveryFateIsNamed) {
  const std::string errors =
      rule_errors(sport_with("zero", "return { modifiers = { function(fate, game) return 1 end, function(fate, game) return 0 end } }"), 0.5);
  EXPECT_HAS(errors, "sport.lua: modifiers[2] gives every fate a factor of 0");
  EXPECT_EQ(errors.find("modifiers[1]"), std::string::npos) << errors;
  const std::string powerup = rule_errors(
      sport_with("zero_powerup", "return { on = { drop = function(game, e) game.grant(\"Red's mallet\", 'nothing') end } }",
                 {{"powerups/nothing.lua", "return { duration = 5, factor = function() return 0 end }"}}),
      0.5);
  EXPECT_HAS(powerup, "power-up nothing (");
  EXPECT_HAS(powerup, "powerups/nothing.lua) gives every fate a factor of 0");
}

TEST(SportRules, FactorsMayNotActEvenWhileAHandlerActs) {
  // The handler opens a wormhole, which predicts the fates again: the modifier runs inside the
  // handler's action, and still may only compute.
  const std::string errors = rule_errors(sport_with("modifier_acts", R"(return {
  modifiers = { function(fate, game) game.award("red") end },
  on = { drop = function(game, e) game.wormhole(-0.3, 0.3, 0.6, 0) end },
})"), 0.1);
  EXPECT_HAS(errors, "game.award: only event handlers (on.*), timers and a power-up's start and stop may act");
}

TEST(SportRules, ASportSplitsItsLuaIntoModules) {
  const std::string folder = sport_with("modules", R"(
local names = require "lib.names"
local two_teams = require "two_teams"
return { on = { drop = function(game, e) game.say(names.greeting .. " " .. two_teams.other(game, "blue")) end } })",
                                        {{"lib/names.lua", "return { greeting = 'Hello' }"}});
  runtime::SessionOptions o;
  o.sport = folder;
  o.seconds = 0.1;
  std::ostringstream out, errors;
  runtime::Session session(o, tools::lua_sport, &out, errors);
  session.run();
  EXPECT_EQ(errors.str(), "");
  EXPECT_HAS(out.str(), "Hello red");
  EXPECT_HAS(load_error("escape", "return require '..secret'"), "'..secret' is not a module name");
  const std::string missing = load_error("missing", "return require 'socket'");
  EXPECT_HAS(missing, "no module 'socket': the sandbox loads only the sport's own Lua modules");
  EXPECT_HAS(load_error("broken", "return require 'bad'", {{"bad.lua", "return {\n  x = ,\n}"}}), "bad.lua:2:");
}

TEST(EventLog, EachEventKeepsItsOwnPhrases) {
  // The drop handler ends the match: match_end is told inside it, and says its own phrase.
  const std::string folder = sport_with("own_phrases", R"(return {
  on = {
    drop = function(game, e)
      game.say("Dropped")
      game.finish("blue")
      game.say("After the end")
    end,
    match_end = function(game, e) game.say("Over") end,
  },
})");
  runtime::SessionOptions o;
  o.sport = folder;
  o.events = (fs::temp_directory_path() / "quantum_own_phrases.jsonl").string();
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  session.run();
  std::ifstream log(o.events);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(log, line);) lines.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["type"], "drop");
  EXPECT_EQ(lines[0]["said"], nlohmann::json({"Dropped", "After the end"}));
  EXPECT_EQ(lines[1]["type"], "match_end");
  EXPECT_EQ(lines[1]["said"], nlohmann::json({"Over"}));
}

// A sport of 600 s whose rules say, when the first ball drops, what they read: the match's length
// beside the sport's own match.seconds, and each player's skill and reach height.
const char* const kReader = R"(local sport = { match = { seconds = 600 } }
sport.on = {
  drop = function(game, e)
    game.say(string.format("length %g of %g", game.length(), sport.match.seconds))
    for _, p in ipairs(game.players()) do
      game.say(string.format("%s: skill %s, reach height %s", p.name, tostring(p.skill), tostring(p.reach_height)))
    end
  end,
}
return sport)";

// What the rules said in the first `frames` frames of a session.
std::vector<std::string> said(const runtime::SessionOptions& o, std::unique_ptr<runtime::PlayerSource> players = nullptr,
                              int frames = 2) {
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors, std::move(players));
  std::vector<std::string> out;
  session.watch([&](const runtime::News& news) {
    for (const game::Said& s : news.said) out.push_back(s.text);
  });
  for (int f = 0; f < frames && session.frame(); ++f) {
  }
  session.finish();
  EXPECT_EQ(errors.str(), "");
  return out;
}

#define EXPECT_SAID(list, text) EXPECT_NE(std::find((list).begin(), (list).end(), text), (list).end()) << ::testing::PrintToString(list)

TEST(RulesRead, TheMatchLengthIsTheOneItRuns) {
  runtime::SessionOptions o;
  o.sport = sport_with("length", kReader);
  EXPECT_SAID(said(o), "length 600 of 600");
  // --seconds (play and balance) and a scenario's seconds win; match.seconds stays the sport's.
  o.seconds = 7;
  EXPECT_SAID(said(o), "length 7 of 600");
}

TEST(RulesRead, ASimulatedPlayerHasItsSkillAndAPersonNone) {
  runtime::SessionOptions o;
  o.sport = sport_with("skill", kReader);
  o.skills = {0.25, 0.75};
  std::vector<std::string> text = said(o);
  // A flat table has no heights.
  EXPECT_SAID(text, "Blue's mallet: skill 0.25, reach height nil");
  EXPECT_SAID(text, "Red's mallet: skill 0.75, reach height nil");
  // At the desk, the mouse's player is a person.
  runtime::Hand hand;
  const Field field = lua::ScriptedRules(o.sport).spec().field;
  text = said(o, std::make_unique<runtime::HandPlayers>(field, o.skills, 1, 10.0, 0, hand));
  EXPECT_SAID(text, "Blue's mallet: skill nil, reach height nil");
  EXPECT_SAID(text, "Red's mallet: skill 0.75, reach height nil");
}

TEST(RulesRead, AReplayReadsTheSkillsItsRecordingRead) {
  runtime::SessionOptions o;
  o.sport = sport_with("skill_replay", kReader);
  o.skills = {0.25, 0.75};
  const fs::path recording = fs::temp_directory_path() / "quantum_rules_api_skill_recording";
  fs::remove_all(recording);
  o.record = recording.string();
  const std::vector<std::string> played = said(o);
  EXPECT_SAID(played, "Blue's mallet: skill 0.25, reach height nil");
  runtime::SessionOptions again;
  again.replay = recording.string();
  EXPECT_EQ(said(again), played);
}

// The sport's own keys, in its table, its match and a power-up's, are there for its functions to
// read, in a match and in its replay alike.
TEST(RulesRead, HandlersReadTheSportsOwnKeys) {
  runtime::SessionOptions o;
  o.sport = sport_with("own_keys", R"(local sport = {
  turn_factor = 2,
  hp = 5,
  streak_reward = { goals = 3 },
  cheer = function(team) return "Go " .. team end,
  match = { first_to = 4 },
}
sport.on = {
  drop = function(game, e)
    game.award(e.team, sport.turn_factor)
    local score = game.score()
    game.say(string.format("%s: %d, hp %d, streak %d, first to %d", sport.cheer(e.team), score[e.team], sport.hp,
                           sport.streak_reward.goals, sport.match.first_to))
    game.grant("Red's mallet", "spin")
  end,
}
return sport)",
                       {{"powerups/spin.lua", R"(local spin = { duration = 5, turns = 3 }
spin.factor = function() end
spin.start = function(holder, game, p) game.say(holder.name .. " spins " .. spin.turns .. " times") end
return spin)"}});
  const fs::path recording = fs::temp_directory_path() / "quantum_rules_api_own_keys_recording";
  fs::remove_all(recording);
  o.record = recording.string();
  const std::vector<std::string> played = said(o);
  EXPECT_SAID(played, "Go blue: 2, hp 5, streak 3, first to 4");  // the drop's team has turn_factor points
  EXPECT_SAID(played, "Red's mallet spins 3 times");
  runtime::SessionOptions again;
  again.replay = recording.string();
  EXPECT_EQ(said(again), played);
}

TEST(RulesRead, AJumpRaisesThePlayersReachHeightUntilItLands) {
  // Maya reaches 2.4 m standing (rules/basketball/field.lua); she jumps 0.4 m for half a second.
  const std::string folder = sport_with("reach_height", R"(
local function heights(game, when)
  game.say(string.format("%s: field %g, now %g", when, game.field().players[1].reach_height,
                         game.players()[1].reach_height))
end
return {
  on = {
    drop = function(game, e)
      heights(game, "standing")
      game.jump("Maya", 0.4, 0.5)
      heights(game, "jumping")
      game.after(1, function(game) heights(game, "landed") end)
    end,
  },
})", {}, QUANTUM_SOURCE_DIR "/rules/basketball");
  runtime::SessionOptions o;
  o.sport = folder;
  const std::vector<std::string> text = said(o, nullptr, 70);
  EXPECT_SAID(text, "standing: field 2.4, now 2.4");
  EXPECT_SAID(text, "jumping: field 2.4, now 2.8");
  EXPECT_SAID(text, "landed: field 2.4, now 2.4");
}

// Two proportions differ: z of the difference under the pooled proportion.
double z_score(int a, int n, int b, int m) {
  const double p = double(a + b) / (n + m);
  return (double(a) / n - double(b) / m) / std::sqrt(p * (1 - p) * (1.0 / n + 1.0 / m));
}

struct Faults {
  int out_of_turn = 0, points = 0;
};

// Simulated players in the wall game (tests/sports/wall), with or without its game.turn calls.
Faults wall_games(bool with_turns) {
  std::string folder = QUANTUM_SOURCE_DIR "/tests/sports/wall";
  if (!with_turns) {
    const fs::path copy = fs::temp_directory_path() / "quantum_wall_without_turns";
    fs::remove_all(copy);
    fs::copy(folder, copy, fs::copy_options::recursive);
    std::ifstream in(copy / "sport.lua");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    for (size_t at; (at = s.find("game.turn(turn)")) != std::string::npos;) s.replace(at, 15, "");
    std::ofstream(copy / "sport.lua") << s;
    folder = copy.string();
  }
  Faults f;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    runtime::SessionOptions o;
    o.sport = folder;
    o.seconds = 120;
    o.seed = seed;
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    session.watch([&](const runtime::News& news) {
      for (const game::Said& s : news.said) {
        f.points += s.text.rfind("Point ", 0) == 0;
        f.out_of_turn += s.text.find("out of turn") != std::string::npos;
      }
    });
    session.run();
    EXPECT_EQ(errors.str(), "");
  }
  return f;
}

TEST(Hints, SimulatedPlayersTakeTheirTurns) {
  const Faults with = wall_games(true), without = wall_games(false);
  std::cout << "points lost out of turn: " << with.out_of_turn << " of " << with.points << " with game.turn, "
            << without.out_of_turn << " of " << without.points << " without\n";
  ASSERT_GT(with.points, 20);
  ASSERT_GT(without.points, 20);
  // One-sided two-proportion z-test at p < 0.001: the turns make fewer faults.
  EXPECT_GT(z_score(without.out_of_turn, without.points, with.out_of_turn, with.points), 3.09);
}

// Blue's shots in a minute of air hockey; `aim` a handler line that sets Blue's aim, or none.
std::pair<int, int> blue_shots_leftward(const std::string& aim) {
  std::ifstream in(QUANTUM_SOURCE_DIR "/rules/airhockey/sport.lua");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find("game.say(\"drop\", { team = game.team_name(e.team) })"), 0, aim + "\n    ");
  const fs::path dir = fs::temp_directory_path() / ("quantum_aim_" + std::to_string(aim.size()));
  fs::remove_all(dir);
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", dir, fs::copy_options::recursive);
  std::ofstream(dir / "sport.lua") << s;
  int left = 0, shots = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    runtime::SessionOptions o;
    o.sport = dir.string();
    o.seconds = 60;
    o.seed = seed;
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    session.watch([&](const runtime::News& news) {
      for (const game::GameEvent& e : news.events) {
        if (e.type != game::EventKind::Shot || e.actor != "Blue's mallet") continue;
        ++shots;
        left += e.velocity.y > std::fabs(e.velocity.x);  // toward the left wall more than down the table
      }
    });
    session.run();
    EXPECT_EQ(errors.str(), "");
  }
  return {left, shots};
}

TEST(Hints, SimulatedPlayersAimWhereTheSportSays) {
  const auto [left_aimed, aimed] = blue_shots_leftward("game.aim(\"Blue's mallet\", \"left wall\")");
  const auto [left_free, free] = blue_shots_leftward("");
  std::cout << "Blue's shots toward the left wall: " << left_aimed << " of " << aimed << " aimed there, " << left_free
            << " of " << free << " at the goal\n";
  ASSERT_GT(aimed, 30);
  ASSERT_GT(free, 30);
  EXPECT_GT(z_score(left_aimed, aimed, left_free, free), 3.09);  // one-sided, p < 0.001
}

}  // namespace
}  // namespace quantum
