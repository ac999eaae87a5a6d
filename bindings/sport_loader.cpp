#include "sport_loader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "confined_path.h"
#include "engine_paths.h"
#include "field_loader.h"
#include "lua_push.h"
#include "lua_reader.h"
#include "phrases.h"
#include "powerups.h"
#include "quantum/limits.h"
#include "quantum/narrow.h"

namespace quantum::lua {
namespace fs = std::filesystem;
namespace {

const std::vector<std::string> kSportKeys = {"name",  "field",  "particles", "match",     "factors",
                                             "handicaps", "balance", "teams", "phrases", "audio",
                                             "modifiers", "on", "state", "on_reload", "throws", "tackles"};

// "rules/practice/" and "rules/practice" are one folder.
fs::path normal_folder(const std::string& folder) {
  fs::path p = fs::path(folder).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

std::vector<fs::path> powerup_folders_of(const fs::path& sport, const fs::path& engine) {
  std::vector<fs::path> out;
  for (const fs::path& f : {sport / "powerups", sport.parent_path() / "powerups", engine / "powerups"}) {
    const fs::path normal = f.lexically_normal();
    if (std::find(out.begin(), out.end(), normal) == out.end()) out.push_back(normal);
  }
  return out;
}

// The event names a sport may handle: the runtime announces a pause itself.
std::vector<std::string> handler_names() {
  std::vector<std::string> out;
  for (const std::string& name : game::event_names())
    if (name != "paused" && name != "resumed") out.push_back(name);
  return out;
}


// How far beyond the field's bounds the listener may stand (a commentator's box, a gallery).
constexpr float kListenerReach = 10;
// What espeak-ng can say (its espeakRATE_MINIMUM..MAXIMUM words per minute, volume 0..200; Speech
// refuses the rest), checked here so a sport learns it at load, not at the first phrase; and how
// many announcer priorities there are room for.
struct Range { int lo, hi; };
constexpr Range kSpeechRate{80, 450}, kSpeechVolume{0, 200}, kPriority{0, 100};

// Runs `read` (reading sport.lua's table): a ReadError becomes a ScriptError naming the file.
template <class Read>
void or_script_error(const std::string& file, Read&& read) {
  try {
    read();
  } catch (const ReadError& e) {
    throw ScriptError(file + ": " + e.what());
  }
}

std::vector<std::string> keys(const std::map<std::string, std::string, std::less<>>& phrases) {
  std::vector<std::string> out;
  for (const auto& [key, text] : phrases) out.push_back(key);
  return out;
}

void read_match(const Reader& r, int t, game::SportSpec& spec);
void check_phrases(const game::SportSpec& spec, const std::vector<fs::path>& powerup_folders);
void read_audio(const Reader& r, int t, game::SportSpec& spec);

void read_sport(lua_State* L, int t, game::SportSpec& spec, const std::vector<fs::path>& powerup_folders) {
  const Reader r(L);
  r.no_near_misses(t, "", kSportKeys);
  spec.name = r.string(t, "name", "", spec.folder, false);
  spec.match.seconds = 180;  // when sport.lua's match gives none
  const double particles = r.number(t, "particles", "", double(spec.match.particles), false);
  if (!(particles >= 1 && particles <= 10'000'000)) r.fail("particles", "must be between 1 and 10,000,000");
  spec.match.particles = uint32_t(particles);
  read_match(r, t, spec);
  spec.handicaps.assign(spec.field.bodies.size(), 1.0);
  if (r.field(t, "handicaps")) {
    r.expect(LUA_TTABLE, "handicaps");
    std::vector<std::string> bodies;
    for (const BodySpec& b : spec.field.bodies) bodies.push_back(b.name);
    const int h = lua_gettop(L);
    r.only_keys(h, "handicaps", bodies);
    for (size_t k = 0; k < bodies.size(); ++k) {
      spec.handicaps[k] = r.number(h, bodies[k].c_str(), "handicaps", 1.0, false);
      r.within("handicaps." + bodies[k], limits::kHandicap, spec.handicaps[k]);
    }
    lua_pop(L, 1);
  }
  if (r.field(t, "balance")) {
    r.expect(LUA_TTABLE, "balance");
    const int b = lua_gettop(L);
    r.only_keys(b, "balance", {"per_goal", "most"});
    spec.match.balance_per_goal = r.number(b, "per_goal", "balance", spec.match.balance_per_goal, false);
    r.within("balance.per_goal", limits::kBalancePerGoal, spec.match.balance_per_goal);
    spec.match.balance_most = r.number(b, "most", "balance", spec.match.balance_most, false);
    // At most a handicap's own bound, so a handicap and its balance never overflow a fate's factor.
    r.within("balance.most", limits::kBalanceMost, spec.match.balance_most);
    lua_pop(L, 1);
  }
  if (r.field(t, "factors")) {
    r.expect(LUA_TTABLE, "factors");
    const int f = lua_gettop(L);
    const std::vector<std::string> kinds = fate_kind_names();
    r.only_keys(f, "factors", kinds);
    for (size_t k = 0; k < kinds.size(); ++k) {
      spec.factors[k] = r.number(f, kinds[k].c_str(), "factors", 1, false);
      if (game::bounded_factor(spec.factors[k]).problem) r.fail("factors." + kinds[k], "must be a number in [0, 1e6]");
    }
    lua_pop(L, 1);
  }
  if (r.field(t, "throws")) {
    r.expect(LUA_TTABLE, "throws");
    const int w = lua_gettop(L);
    r.only_keys(w, "throws", {"speed", "spread", "speed_spread", "elevation_spread"});
    spec.match.throw_speed = r.number(w, "speed", "throws", spec.match.throw_speed, false);
    r.within("throws.speed", limits::kThrowSpeed, spec.match.throw_speed);
    const double degrees = r.number(w, "spread", "throws", spec.match.throw_spread.direction / kRadiansPerDegree, false);
    r.within("throws.spread", limits::kSpreadDegrees, degrees);
    spec.match.throw_spread.direction = float(degrees * kRadiansPerDegree);
    spec.match.throw_spread.speed = to_float(r.number(w, "speed_spread", "throws", spec.match.throw_spread.speed, false));
    r.within("throws.speed_spread", limits::kSpeedSpread, spec.match.throw_spread.speed);
    const double up = r.number(w, "elevation_spread", "throws", spec.match.throw_spread.elevation / kRadiansPerDegree, false);
    r.within("throws.elevation_spread", limits::kSpreadDegrees, up);
    spec.match.throw_spread.elevation = float(up * kRadiansPerDegree);
    lua_pop(L, 1);
  }
  if (r.field(t, "tackles")) {
    r.expect(LUA_TTABLE, "tackles");
    const int k = lua_gettop(L);
    r.only_keys(k, "tackles", {"rate"});
    spec.match.tackle_rate = r.number(k, "rate", "tackles", spec.match.tackle_rate, true);
    r.within("tackles.rate", limits::kTackleRate, spec.match.tackle_rate);
    if (spec.match.tackle_rate > 0 && !spec.field.catching()) r.fail("tackles", "tackles take a held ball: the field needs players who catch");
    lua_pop(L, 1);
  }
  if (r.field(t, "teams")) {
    r.expect(LUA_TTABLE, "teams");
    r.only_keys(-1, "teams", spec.field.teams());
    r.map(-1, "teams", [&](const std::string& team, const std::string& place) {
      r.expect(LUA_TSTRING, place, "the team's name as the announcer says it");
      spec.team_names[team] = lua_tostring(L, -1);
    });
    lua_pop(L, 1);
  }
  if (r.field(t, "phrases")) {
    r.expect(LUA_TTABLE, "phrases");
    r.at_most(-1, "phrases", limits::kMaxPhrases);
    r.map(-1, "phrases", [&](const std::string& key, const std::string& place) {
      r.expect(LUA_TSTRING, place, "text, e.g. shot = \"{team} shoots\"");
      try {
        PhraseTemplate(lua_tostring(L, -1));  // parsed to be checked: the rules parse their own copy
        spec.phrases[key] = lua_tostring(L, -1);
      } catch (const std::invalid_argument& e) {
        r.fail(place, e.what());
      }
    });
    lua_pop(L, 1);
  }
  check_phrases(spec, powerup_folders);
  read_audio(r, t, spec);
  if (r.field(t, "on")) {
    r.expect(LUA_TTABLE, "on");
    r.only_keys(-1, "on", handler_names(), "event");
    r.map(-1, "on", [&](const std::string&, const std::string& place) { r.expect(LUA_TFUNCTION, place); });
    lua_pop(L, 1);
  }
  if (r.field(t, "modifiers")) {
    r.expect(LUA_TTABLE, "modifiers", "a list of functions");
    for (size_t i = 1; i <= lua_objlen(L, -1); ++i) {
      lua_rawgeti(L, -1, int(i));
      r.expect(LUA_TFUNCTION, "modifiers[" + std::to_string(i) + "]");
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  if (r.field(t, "on_reload")) {
    r.expect(LUA_TFUNCTION, "on_reload");
    lua_pop(L, 1);
  }
}

// match = {seconds, start, stall}, and whatever else the sport keeps there (first_to, ...).
void read_match(const Reader& r, int t, game::SportSpec& spec) {
  lua_State* L = r.L;
  if (!r.field(t, "match")) return;
  r.expect(LUA_TTABLE, "match");
  const int m = lua_gettop(L);
  const std::vector<std::string> known = {"seconds", "start", "stall"};
  r.no_near_misses(m, "match", known);
  spec.match.seconds = r.number(m, "seconds", "match", spec.match.seconds, false);
  r.within("match.seconds", limits::kMatchSeconds, spec.match.seconds);
  spec.match.stall = r.number(m, "stall", "match", spec.match.stall, false);
  if (!limits::kStall.contains(spec.match.stall))
    r.fail("match.stall", "must be a number of seconds in " + limits::interval(limits::kStall) +
                              " (how long a match may go without play), got " +
                              (std::ostringstream() << spec.match.stall).str());
  if (r.field(m, "start")) {
    r.expect(LUA_TSTRING, "match.start");
    const std::string where = lua_tostring(L, -1);
    lua_pop(L, 1);
    spec.match.first_spot = spec.field.spot_of(where);
    // No spot of that name or team: a player who catches, or the team's catcher nearest the centre.
    const Vec2 centre{0.5f * (spec.field.bounds_min.x + spec.field.bounds_max.x), 0.5f * (spec.field.bounds_min.y + spec.field.bounds_max.y)};
    float nearest = 1e30f;
    for (size_t k = 0; k < spec.field.bodies.size() && spec.match.first_spot < 0; ++k) {
      const BodySpec& b = spec.field.bodies[k];
      const float d = std::hypot(b.start.x - centre.x, b.start.y - centre.y);
      if (b.catches && (b.name == where || (b.team == where && d < nearest))) spec.match.first_holder = int(k), nearest = d;
      if (b.catches && b.name == where) break;
    }
    if (spec.match.first_holder < 0 && spec.match.first_spot < 0)
      r.fail("match.start", "no spot, team or player who catches named '" + where + "' in the field");
    spec.match.first_spot = std::max(spec.match.first_spot, 0);
  }
  lua_pop(L, 1);
}

// game.say("gaol") in the sport's own files: a phrase key the sport does not have is an error
// now, not when (if ever) the handler runs. Keys made at run time are checked when said.
void check_said_keys(const Sandbox& sandbox, const game::SportSpec& spec) {
  const std::string engine = spec.engine.lexically_normal().string();
  for (const std::string& file : sandbox.files()) {
    if (fs::path(file).lexically_normal().string().rfind(engine, 0) == 0) continue;  // the engine's helpers
    std::ifstream in(file);
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      ++number;
      const std::string code = line.substr(0, line.find("--"));
      for (size_t at = code.find("game.say("); at != std::string::npos; at = code.find("game.say(", at + 1)) {
        size_t open = code.find_first_not_of(' ', at + 9);
        if (open == std::string::npos || (code[open] != '"' && code[open] != '\'')) continue;
        const size_t close = code.find(code[open], open + 1);
        const std::string key = code.substr(open + 1, close == std::string::npos ? 0 : close - open - 1);
        if (close == std::string::npos || !Phrases::looks_like_key(key) || spec.phrases.count(key)) continue;
        throw ScriptError(file + ":" + std::to_string(number) + ": game.say(\"" + key + "\"): " +
                          unknown_key(key, keys(spec.phrases), "phrase key") +
                          " (text to speak as it is starts with a capital or has a space)");
      }
    }
  }
}

// The engine says some phrases itself: a paused and resumed match, and power-ups starting and
// running out (a sport's `<power-up>_start` and `_over` take the script's place). Their
// placeholders must be ones the engine fills.
void check_phrases(const game::SportSpec& spec, const std::vector<fs::path>& powerup_folders) {
  for (const std::string& key : keys(spec.phrases)) {
    std::vector<std::string> allowed;
    bool engine_said = key == "paused" || key == "resumed";
    for (const char* suffix : {"_start", "_over"}) {
      if (!key.ends_with(suffix)) continue;
      const std::string powerup = key.substr(0, key.size() - std::string(suffix).size());
      std::string looked;
      engine_said |= plain_powerup_name(powerup) && !powerup_file(powerup_folders, powerup, looked).empty();
      if (engine_said) allowed = kPowerupVars;
    }
    if (engine_said) check_engine_phrase("phrases." + key, PhraseTemplate(spec.phrases.find(key)->second), allowed);
  }
}

void read_audio(const Reader& r, int t, game::SportSpec& spec) {
  lua_State* L = r.L;
  // A sound file: in the sport's folder, else among the engine's own (sounds/). One in neither is
  // the engine's name for it: the match warns once that it stays silent.
  const std::vector<fs::path> folders = {fs::path(spec.folder), engine_sounds_folder()};
  auto resolve = [&](const std::string& name, const std::string& key) {
    std::string looked;
    const fs::path found = confined_path(folders, name, key, looked);
    return (found.empty() ? folders.back() / name : found).lexically_normal().string();
  };
  for (const auto& [event, name] : {std::pair{"shot", "hit.wav"}, {"intercept", "hit.wav"}, {"retouch", "hit.wav"},
                                    {"hit", "hit.wav"},     {"kick", "hit.wav"},  {"goal", "goal.wav"}, {"own_goal", "goal.wav"}, {"drop", "whistle.wav"},
                                    {"bounce", "wall.wav"}})
    spec.audio.sounds[event] = resolve(name, std::string("audio.sounds.") + event);
  spec.audio.priorities = {{"goal", 3}, {"own_goal", 3}, {"match_end", 3}, {"time_up", 3}, {"drop", 2}, {"out", 2},
                       {"dead", 2}, {"shot", 1},     {"intercept", 1}, {"timer", 1},   {"retouch", 0}, {"bounce", 0},
                       {"hit", 1},       {"kick", 1}};
  for (const char* e : {"shot", "intercept", "retouch", "hit", "bounce", "catch", "pickup", "tackle", "pass", "throw", "kick", "give"})
    spec.audio.supersede[e] = true;
  if (!r.field(t, "audio")) return;
  r.expect(LUA_TTABLE, "audio");
  const int a = lua_gettop(L);
  r.only_keys(a, "audio", {"voice", "rate", "volume", "listener", "facing", "sounds", "recorded", "priorities",
                           "supersede", "duck", "repeat_gap", "wait_for", "keep"});
  spec.audio.voice = r.string(a, "voice", "audio", spec.audio.voice, false);
  spec.audio.rate = r.whole(a, "rate", "audio", spec.audio.rate, kSpeechRate.lo, kSpeechRate.hi);
  spec.audio.volume = r.whole(a, "volume", "audio", spec.audio.volume, kSpeechVolume.lo, kSpeechVolume.hi);
  if (r.field(a, "listener")) spec.audio.listener = r.point("audio.listener");
  if (r.field(a, "facing")) spec.audio.facing = r.point("audio.facing");
  // Sounds are placed around the listener: it stands on the field or beside it, facing some way.
  const Vec2 lo = spec.field.bounds_min, hi = spec.field.bounds_max, at = spec.audio.listener;
  if (!(at.x >= lo.x - kListenerReach && at.x <= hi.x + kListenerReach && at.y >= lo.y - kListenerReach &&
        at.y <= hi.y + kListenerReach))
    r.fail("audio.listener", "must be within 10 m of the field's bounds");
  const float facing = std::hypot(spec.audio.facing.x, spec.audio.facing.y);
  if (!(facing > 0 && std::isfinite(facing))) r.fail("audio.facing", "must be a direction: finite and not {0, 0}");
  auto within = [&](const char* key, double fallback, double most) {
    const double v = r.number(a, key, "audio", fallback, false);
    if (!(v >= 0 && v <= most)) {
      char message[96];
      std::snprintf(message, sizeof message, "expected a number from 0 to %g, got %g", most, v);
      r.fail(std::string("audio.") + key, message);
    }
    return v;
  };
  spec.audio.duck = float(within("duck", spec.audio.duck, 1));
  spec.audio.repeat_gap = within("repeat_gap", spec.audio.repeat_gap, 60);
  spec.audio.wait_for = within("wait_for", spec.audio.wait_for, 5);
  spec.audio.keep = r.whole(a, "keep", "audio", spec.audio.keep, kPriority.lo, kPriority.hi);
  std::vector<std::string> events = game::event_names();
  if (r.field(a, "sounds")) {
    r.expect(LUA_TTABLE, "audio.sounds");
    r.only_keys(-1, "audio.sounds", events);
    r.map(-1, "audio.sounds", [&](const std::string& event, const std::string& place) {
      r.expect(LUA_TSTRING, place, "a sound file's name");
      spec.audio.sounds[event] = resolve(lua_tostring(L, -1), place);
    });
    lua_pop(L, 1);
  }
  if (r.field(a, "recorded")) {
    r.expect(LUA_TTABLE, "audio.recorded");
    r.only_keys(-1, "audio.recorded", keys(spec.phrases));
    r.map(-1, "audio.recorded", [&](const std::string& key, const std::string& place) {
      r.expect(LUA_TSTRING, place, "a sound file's name");
      spec.audio.recorded[key] = resolve(lua_tostring(L, -1), place);
    });
    lua_pop(L, 1);
  }
  events.push_back("timer");
  if (r.field(a, "supersede")) {
    r.expect(LUA_TTABLE, "audio.supersede");
    r.only_keys(-1, "audio.supersede", events);
    r.map(-1, "audio.supersede", [&](const std::string& event, const std::string& place) {
      r.expect(LUA_TBOOLEAN, place);
      spec.audio.supersede[event] = lua_toboolean(L, -1);
    });
    lua_pop(L, 1);
  }
  if (r.field(a, "priorities")) {
    r.expect(LUA_TTABLE, "audio.priorities");
    r.only_keys(-1, "audio.priorities", events);
    r.map(-1, "audio.priorities", [&](const std::string& event, const std::string& place) {
      spec.audio.priorities[event] = r.whole_at_top(place, kPriority.lo, kPriority.hi);
    });
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

}  // namespace

SportFolders::SportFolders(const std::string& given, const fs::path& engine)
    : folder(normal_folder(find_sport(given).string()).string()),
      engine(engine),
      powerups(powerup_folders_of(folder, engine)),
      modules({fs::path(folder), engine / "lib"}) {}

int load_sport(Sandbox& sandbox, Params& params, const SportFolders& where, const Field* playing, game::SportSpec& spec) {
  lua_State* L = sandbox.L();
  const std::string file = (fs::path(where.folder) / "sport.lua").string();
  spec.folder = where.folder;
  spec.engine = where.engine;
  int sport = LUA_NOREF;
  sandbox.protect([&] {
    sandbox.push_environment();
    params.install(L);
    lua_pop(L, 1);
    sandbox.run_file(file);
    if (!lua_istable(L, -1)) throw ScriptError(file + ": must return a table, returned " + luaL_typename(L, -1));
    or_script_error(file, [&] {
      const std::string name = Reader(L).string(lua_gettop(L), "field", "", "field.lua", false);
      std::string looked;
      const fs::path found = confined_path({fs::path(where.folder)}, name, "field", looked);
      spec.field_file = (found.empty() ? fs::path(where.folder) / name : found).lexically_normal();  // load_field says it is not there
    });
    sport = luaL_ref(L, LUA_REGISTRYINDEX);
  });
  // Outside the sport's budget: the field file runs in a sandbox of its own, with its own. A
  // reload's match plays on its field, which the new version reads (its bodies' handicaps).
  spec.field = playing ? *playing : load_field(spec.field_file.string(), &params);
  sandbox.protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport);
    or_script_error(file, [&] { read_sport(L, lua_gettop(L), spec, where.powerups); });
    lua_pop(L, 1);
    check_said_keys(sandbox, spec);
    params.check_read(where.folder);
  });
  spec.params = params.pairs();
  return sport;
}

}  // namespace quantum::lua
