#include "sport.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "confined_path.h"
#include "field_loader.h"
#include "game/plain_rules.h"
#include "lua_reader.h"
#include "quantum/limits.h"
#include "quantum/narrow.h"

namespace quantum::lua {
namespace fs = std::filesystem;
namespace {


const std::vector<std::string> kSportKeys = {"name",  "field",  "particles", "match",     "factors",
                                             "handicaps", "balance", "teams", "phrases", "audio",
                                             "modifiers", "on", "state", "on_reload", "throws", "tackles"};
const std::vector<std::string> kPowerupKeys = {"name", "duration", "defaults", "phrases", "factor", "start", "stop"};
// The placeholders the engine fills in a power-up's phrases.
const std::vector<std::string> kPowerupVars = {"player", "team"};

// "rules/practice/" and "rules/practice" are one folder.
fs::path normal_folder(const std::string& folder) {
  fs::path p = fs::path(folder).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

// A power-up's name is its script's file name, without the folder: no path reaches out of them.
bool plain_powerup_name(const std::string& name) {
  return !name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
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

// Checks a phrase the engine says itself: every placeholder is one of `allowed` (what the
// engine fills in, always text), none with a number format.
void check_engine_phrase(const std::string& place, const PhraseTemplate& phrase, std::span<const std::string> allowed) {
  for (const std::string& name : phrase.placeholders()) {
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw ReadError(place, unknown_key(name, allowed, "placeholder") + ": the engine says this phrase");
    if (phrase.numeric(name)) throw ReadError(place, "{" + name + "} is text: it takes no number format");
  }
}

// How far beyond the field's bounds the listener may stand (a commentator's box, a gallery).
constexpr float kListenerReach = 10;
// What espeak-ng can say (its espeakRATE_MINIMUM..MAXIMUM words per minute, volume 0..200; Speech
// refuses the rest), checked here so a sport learns it at load, not at the first phrase; and how
// many announcer priorities there are room for.
struct Range { int lo, hi; };
constexpr Range kSpeechRate{80, 450}, kSpeechVolume{0, 200}, kPriority{0, 100};

// "rules/x/sport.lua:12: ", where the Lua function at `index` is defined; `fallback` + ": " when
// that is unknown.
std::string defined_at(lua_State* L, int index, const std::string& fallback) {
  lua_Debug ar;
  lua_pushvalue(L, index);
  lua_getinfo(L, ">S", &ar);
  if (ar.source[0] != '@' || ar.linedefined <= 0) return fallback + ": ";
  return std::string(ar.source + 1) + ":" + std::to_string(ar.linedefined) + ": ";
}

// A factor's term never takes the product past game::kMostFactor, so no number of them
// overflows.
double times(double factor, double term) { return std::min(factor * term, game::kMostFactor); }

// A term of a factor at the top of the stack (a number, not nil), in bounds; what is out of them
// is reported, the error starting with what `culprit()` names (made only then: this runs for
// every fate every frame). The text names no value, so that a term out of bounds every frame is
// one message, shown once.
template <class Culprit>
double checked_term(lua_State* L, game::Match& match, Culprit&& culprit) {
  if (lua_type(L, -1) != LUA_TNUMBER) {
    match.report_error(culprit() + "a " + luaL_typename(L, -1) + ", not a factor in [0, 1e6] (skipped)");
    return 1;
  }
  const game::BoundedFactor f = game::bounded_factor(lua_tonumber(L, -1));
  if (f.problem) match.report_error(culprit() + f.problem);
  return f.value;
}

// Runs `read` (reading sport.lua's table): a ReadError becomes a ScriptError naming the file.
template <class Read>
void or_script_error(const std::string& file, Read&& read) {
  try {
    read();
  } catch (const ReadError& e) {
    throw ScriptError(file + ": " + e.what());
  }
}

}  // namespace

// While a handler, a timer or a power-up's start or stop runs, the rules may act on the match;
// while factors are computed they may only read it. Nested calls restore what was before. The
// scripts' random numbers are the match's (Sandbox::set_seed).
class Sport::Acting {
 public:
  Acting(Sport& sport, game::Match& match, bool may_act)
      : sport_(sport), outer_(sport.match_), outer_reading_(sport.reading_) {
    sport.match_ = may_act ? &match : nullptr;
    sport.reading_ = &match;
    sport.sandbox_->set_seed(match.config().seed);
  }
  ~Acting() { sport_.match_ = outer_, sport_.reading_ = outer_reading_; }
  Acting(const Acting&) = delete;
  Acting& operator=(const Acting&) = delete;

 private:
  Sport& sport_;
  game::Match* outer_;
  const game::Match* outer_reading_;
};

Sport::Sport(const std::string& folder, const fs::path& engine, Params params, const Limits& load)
    : Sport(folder, engine, std::move(params), load, nullptr) {}

std::unique_ptr<Sport> Sport::reload(const Sport& current) {
  return std::unique_ptr<Sport>(new Sport(current.folder_, current.engine_, current.params_, Limits{}, &current.field_));
}

Sport::Sport(const std::string& folder, const fs::path& engine, Params params, const Limits& load, const Field* playing)
    : folder_(normal_folder(find_sport(folder).string()).string()),
      file_((fs::path(folder_) / "sport.lua").string()),
      engine_(engine),
      powerup_folders_(powerup_folders_of(folder_, engine)),
      module_folders_({fs::path(folder_), engine / "lib"}),
      params_(std::move(params)),
      sandbox_(Sandbox::make(Limits{}, true, module_folders_)) {
  std::fill(std::begin(by_kind_), std::end(by_kind_), 1.0);
  lua_State* L = sandbox_->L();
  sandbox_->set_budget(load);
  sandbox_->protect([&] {
    sandbox_->push_environment();
    params_.install(L);
    lua_pop(L, 1);
    sandbox_->run_file(file_);
    if (!lua_istable(L, -1)) throw ScriptError(file_ + ": must return a table, returned " + luaL_typename(L, -1));
    or_script_error(file_, [&] {
      const std::string name = Reader(L).string(lua_gettop(L), "field", "", "field.lua", false);
      std::string looked;
      const fs::path found = confined_path({fs::path(folder_)}, name, "field", looked);
      field_file_ = (found.empty() ? fs::path(folder_) / name : found).lexically_normal();  // load_field says it is not there
    });
    sport_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  });
  // Outside the sport's budget: the field file runs in a sandbox of its own, with its own. A
  // reload's match plays on its field, which the new version reads (its bodies' handicaps).
  field_ = playing ? *playing : load_field(field_file_.string(), &params_);
  sandbox_->protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
    or_script_error(file_, [&] { read_sport(lua_gettop(L)); });
    check_said_keys();
    params_.check_read(folder_);
    push_game_api(L, this);
    game_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  });
  timers_.reserve(16);
  if (playing) return;  // a reload: take_over spends the rest of its frame's budget
  // Loading is not a frame: what it spent must not leave the first frame (or a grant before it)
  // without a budget, as it did on a slow machine.
  sandbox_->set_budget(Limits{});
  sandbox_->new_period();
}

Sport::~Sport() = default;

void Sport::read_sport(int t) {
  lua_State* L = sandbox_->L();
  const Reader r(L);
  r.no_near_misses(t, "", kSportKeys);
  name_ = r.string(t, "name", "", folder_, false);
  const double particles = r.number(t, "particles", "", double(particles_), false);
  if (!(particles >= 1 && particles <= 10'000'000)) r.fail("particles", "must be between 1 and 10,000,000");
  particles_ = uint32_t(particles);
  read_match(r, t);
  handicaps_.assign(field_.bodies.size(), 1.0);
  if (r.field(t, "handicaps")) {
    r.expect(LUA_TTABLE, "handicaps");
    std::vector<std::string> bodies;
    for (const BodySpec& b : field_.bodies) bodies.push_back(b.name);
    const int h = lua_gettop(L);
    r.only_keys(h, "handicaps", bodies);
    for (size_t k = 0; k < bodies.size(); ++k) {
      handicaps_[k] = r.number(h, bodies[k].c_str(), "handicaps", 1.0, false);
      if (!game::handicap_ok(handicaps_[k])) r.fail("handicaps." + bodies[k], "must be in (0, 1000]");
    }
    lua_pop(L, 1);
  }
  if (r.field(t, "balance")) {
    r.expect(LUA_TTABLE, "balance");
    const int b = lua_gettop(L);
    r.only_keys(b, "balance", {"per_goal", "most"});
    balance_per_goal_ = r.number(b, "per_goal", "balance", balance_per_goal_, false);
    if (!(balance_per_goal_ >= 0 && balance_per_goal_ <= 10)) r.fail("balance.per_goal", "must be in [0, 10]");
    balance_most_ = r.number(b, "most", "balance", balance_most_, false);
    // At most a handicap's own bound, so a handicap and its balance never overflow a fate's factor.
    if (!(balance_most_ >= 1 && balance_most_ <= game::kMostHandicap)) r.fail("balance.most", "must be in [1, 1000]");
    lua_pop(L, 1);
  }
  if (r.field(t, "factors")) {
    r.expect(LUA_TTABLE, "factors");
    const int f = lua_gettop(L);
    const std::vector<std::string> kinds = fate_kind_names();
    r.only_keys(f, "factors", kinds);
    for (const std::string& kind : kinds) {
      const double v = r.number(f, kind.c_str(), "factors", 1, false);
      if (game::bounded_factor(v).problem) r.fail("factors." + kind, "must be a number in [0, 1e6]");
    }
    lua_pop(L, 1);
  }
  if (r.field(t, "throws")) {
    r.expect(LUA_TTABLE, "throws");
    const int w = lua_gettop(L);
    r.only_keys(w, "throws", {"speed", "spread", "speed_spread", "elevation_spread"});
    throw_speed_ = r.number(w, "speed", "throws", throw_speed_, false);
    if (!(throw_speed_ > 0 && throw_speed_ <= 1000)) r.fail("throws.speed", "must be in (0, 1000] m/s");
    const double degrees = r.number(w, "spread", "throws", throw_spread_.direction / kRadiansPerDegree, false);
    if (!(degrees >= 0 && degrees <= 90)) r.fail("throws.spread", "must be in [0, 90] degrees");
    throw_spread_.direction = float(degrees * kRadiansPerDegree);
    throw_spread_.speed = to_float(r.number(w, "speed_spread", "throws", throw_spread_.speed, false));
    if (!(throw_spread_.speed >= 0 && throw_spread_.speed <= 1)) r.fail("throws.speed_spread", "must be in [0, 1]");
    const double up = r.number(w, "elevation_spread", "throws", throw_spread_.elevation / kRadiansPerDegree, false);
    if (!(up >= 0 && up <= 90)) r.fail("throws.elevation_spread", "must be in [0, 90] degrees");
    throw_spread_.elevation = float(up * kRadiansPerDegree);
    lua_pop(L, 1);
  }
  if (r.field(t, "tackles")) {
    r.expect(LUA_TTABLE, "tackles");
    const int k = lua_gettop(L);
    r.only_keys(k, "tackles", {"rate"});
    tackle_rate_ = r.number(k, "rate", "tackles", tackle_rate_, true);
    if (!(tackle_rate_ >= 0 && tackle_rate_ <= game::kMostTackleRate)) r.fail("tackles.rate", "must be in [0, 100] per second");
    if (tackle_rate_ > 0 && !field_.catching()) r.fail("tackles", "tackles take a held ball: the field needs players who catch");
    lua_pop(L, 1);
  }
  if (r.field(t, "teams")) {
    r.expect(LUA_TTABLE, "teams");
    r.only_keys(-1, "teams", field_.teams());
    r.map(-1, "teams", [&](const std::string& team, const std::string& place) {
      r.expect(LUA_TSTRING, place, "the team's name as the announcer says it");
      team_names_[team] = lua_tostring(L, -1);
    });
    lua_pop(L, 1);
  }
  if (r.field(t, "phrases")) {
    r.expect(LUA_TTABLE, "phrases");
    r.at_most(-1, "phrases", limits::kMaxPhrases);
    r.map(-1, "phrases", [&](const std::string& key, const std::string& place) {
      r.expect(LUA_TSTRING, place, "text, e.g. shot = \"{team} shoots\"");
      try {
        phrases_.add(key, lua_tostring(L, -1));
      } catch (const std::invalid_argument& e) {
        r.fail(place, e.what());
      }
    });
    lua_pop(L, 1);
  }
  check_phrases();
  read_audio(r, t);
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
void Sport::read_match(const Reader& r, int t) {
  lua_State* L = sandbox_->L();
  if (!r.field(t, "match")) return;
  r.expect(LUA_TTABLE, "match");
  const int m = lua_gettop(L);
  const std::vector<std::string> known = {"seconds", "start", "stall"};
  r.no_near_misses(m, "match", known);
  seconds_ = r.number(m, "seconds", "match", seconds_, false);
  if (!(seconds_ > 0 && seconds_ <= 24 * 3600)) r.fail("match.seconds", "must be in (0, 86400]");
  stall_ = r.number(m, "stall", "match", stall_, false);
  if (!(stall_ >= game::kLeastStall && stall_ <= game::kMostStall))
    r.fail("match.stall", "must be a number of seconds in [1, 3600] (how long a match may go without play), got " +
                              (std::ostringstream() << stall_).str());
  if (r.field(m, "start")) {
    r.expect(LUA_TSTRING, "match.start");
    const std::string where = lua_tostring(L, -1);
    lua_pop(L, 1);
    first_spot_ = field_.spot_of(where);
    // No spot of that name or team: a player who catches, or the team's catcher nearest the centre.
    const Vec2 centre{0.5f * (field_.bounds_min.x + field_.bounds_max.x), 0.5f * (field_.bounds_min.y + field_.bounds_max.y)};
    float nearest = 1e30f;
    for (size_t k = 0; k < field_.bodies.size() && first_spot_ < 0; ++k) {
      const BodySpec& b = field_.bodies[k];
      const float d = std::hypot(b.start.x - centre.x, b.start.y - centre.y);
      if (b.catches && (b.name == where || (b.team == where && d < nearest))) first_holder_ = int(k), nearest = d;
      if (b.catches && b.name == where) break;
    }
    if (first_holder_ < 0 && first_spot_ < 0)
      r.fail("match.start", "no spot, team or player who catches named '" + where + "' in the field");
    first_spot_ = std::max(first_spot_, 0);
  }
  lua_pop(L, 1);
}

// game.say("gaol") in the sport's own files: a phrase key the sport does not have is an error
// now, not when (if ever) the handler runs. Keys made at run time are checked when said.
void Sport::check_said_keys() const {
  const std::string engine = engine_.lexically_normal().string();
  for (const std::string& file : sandbox_->files()) {
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
        if (close == std::string::npos || !Phrases::looks_like_key(key) || phrases_.find(key)) continue;
        throw ScriptError(file + ":" + std::to_string(number) + ": game.say(\"" + key + "\"): " +
                          unknown_key(key, phrases_.keys(), "phrase key") +
                          " (text to speak as it is starts with a capital or has a space)");
      }
    }
  }
}

// The engine says some phrases itself: a paused and resumed match, and power-ups starting and
// running out (a sport's `<power-up>_start` and `_over` take the script's place). Their
// placeholders must be ones the engine fills.
void Sport::check_phrases() const {
  for (const std::string& key : phrases_.keys()) {
    std::vector<std::string> allowed;
    bool engine_said = key == "paused" || key == "resumed";
    for (const char* suffix : {"_start", "_over"}) {
      if (!key.ends_with(suffix)) continue;
      const std::string powerup = key.substr(0, key.size() - std::string(suffix).size());
      std::string looked;
      engine_said |= plain_powerup_name(powerup) && !powerup_file(powerup, looked).empty();
      if (engine_said) allowed = kPowerupVars;
    }
    if (engine_said) check_engine_phrase("phrases." + key, *phrases_.find(key), allowed);
  }
}

void Sport::read_audio(const Reader& r, int t) {
  lua_State* L = sandbox_->L();
  // A sound file: in the sport's folder, else among the engine's own (sounds/). One in neither is
  // the engine's name for it: the match warns once that it stays silent.
  const std::vector<fs::path> folders = {fs::path(folder_), engine_sounds_folder()};
  auto resolve = [&](const std::string& name, const std::string& key) {
    std::string looked;
    const fs::path found = confined_path(folders, name, key, looked);
    return (found.empty() ? folders.back() / name : found).lexically_normal().string();
  };
  for (const auto& [event, name] : {std::pair{"shot", "hit.wav"}, {"intercept", "hit.wav"}, {"retouch", "hit.wav"},
                                    {"hit", "hit.wav"},     {"kick", "hit.wav"},  {"goal", "goal.wav"}, {"own_goal", "goal.wav"}, {"drop", "whistle.wav"},
                                    {"bounce", "wall.wav"}})
    audio_.sounds[event] = resolve(name, std::string("audio.sounds.") + event);
  audio_.priorities = {{"goal", 3}, {"own_goal", 3}, {"match_end", 3}, {"time_up", 3}, {"drop", 2}, {"out", 2},
                       {"dead", 2}, {"shot", 1},     {"intercept", 1}, {"timer", 1},   {"retouch", 0}, {"bounce", 0},
                       {"hit", 1},       {"kick", 1}};
  for (const char* e : {"shot", "intercept", "retouch", "hit", "bounce", "catch", "pickup", "tackle", "pass", "throw", "kick", "give"})
    audio_.supersede[e] = true;
  if (!r.field(t, "audio")) return;
  r.expect(LUA_TTABLE, "audio");
  const int a = lua_gettop(L);
  r.only_keys(a, "audio", {"voice", "rate", "volume", "listener", "facing", "sounds", "recorded", "priorities",
                           "supersede", "duck", "repeat_gap", "wait_for", "keep"});
  audio_.voice = r.string(a, "voice", "audio", audio_.voice, false);
  audio_.rate = r.whole(a, "rate", "audio", audio_.rate, kSpeechRate.lo, kSpeechRate.hi);
  audio_.volume = r.whole(a, "volume", "audio", audio_.volume, kSpeechVolume.lo, kSpeechVolume.hi);
  if (r.field(a, "listener")) audio_.listener = r.point("audio.listener");
  if (r.field(a, "facing")) audio_.facing = r.point("audio.facing");
  // Sounds are placed around the listener: it stands on the field or beside it, facing some way.
  const Vec2 lo = field_.bounds_min, hi = field_.bounds_max, at = audio_.listener;
  if (!(at.x >= lo.x - kListenerReach && at.x <= hi.x + kListenerReach && at.y >= lo.y - kListenerReach &&
        at.y <= hi.y + kListenerReach))
    r.fail("audio.listener", "must be within 10 m of the field's bounds");
  const float facing = std::hypot(audio_.facing.x, audio_.facing.y);
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
  audio_.duck = float(within("duck", audio_.duck, 1));
  audio_.repeat_gap = within("repeat_gap", audio_.repeat_gap, 60);
  audio_.wait_for = within("wait_for", audio_.wait_for, 5);
  audio_.keep = r.whole(a, "keep", "audio", audio_.keep, kPriority.lo, kPriority.hi);
  std::vector<std::string> events = game::event_names();
  if (r.field(a, "sounds")) {
    r.expect(LUA_TTABLE, "audio.sounds");
    r.only_keys(-1, "audio.sounds", events);
    r.map(-1, "audio.sounds", [&](const std::string& event, const std::string& place) {
      r.expect(LUA_TSTRING, place, "a sound file's name");
      audio_.sounds[event] = resolve(lua_tostring(L, -1), place);
    });
    lua_pop(L, 1);
  }
  if (r.field(a, "recorded")) {
    r.expect(LUA_TTABLE, "audio.recorded");
    r.only_keys(-1, "audio.recorded", phrases_.keys());
    r.map(-1, "audio.recorded", [&](const std::string& key, const std::string& place) {
      r.expect(LUA_TSTRING, place, "a sound file's name");
      audio_.recorded[key] = resolve(lua_tostring(L, -1), place);
    });
    lua_pop(L, 1);
  }
  events.push_back("timer");
  if (r.field(a, "supersede")) {
    r.expect(LUA_TTABLE, "audio.supersede");
    r.only_keys(-1, "audio.supersede", events);
    r.map(-1, "audio.supersede", [&](const std::string& event, const std::string& place) {
      r.expect(LUA_TBOOLEAN, place);
      audio_.supersede[event] = lua_toboolean(L, -1);
    });
    lua_pop(L, 1);
  }
  if (r.field(a, "priorities")) {
    r.expect(LUA_TTABLE, "audio.priorities");
    r.only_keys(-1, "audio.priorities", events);
    r.map(-1, "audio.priorities", [&](const std::string& event, const std::string& place) {
      audio_.priorities[event] = r.whole_at_top(place, kPriority.lo, kPriority.hi);
    });
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

std::string Sport::team_name(const std::string& team) const {
  const auto it = team_names_.find(team);
  return it == team_names_.end() ? team : it->second;
}

void Sport::unknown_phrase(std::string_view key) const {
  throw std::invalid_argument("no phrase '" + std::string(key) + "' in " + file_ + ": " +
                              unknown_key(key, phrases_.keys(), "phrase key") +
                              " (text to speak as it is starts with a capital or has a space)");
}

void Sport::say_host(game::Match& match, const std::string& key, const std::string& fallback) {
  auto none = [](std::string_view) { return std::optional<PhraseValue>(); };
  say_or(match, key, fallback, none);
}

double Sport::factor(const std::string& kind) const {
  lua_State* L = sandbox_->L();
  double value = 1;
  sandbox_->protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
    raw_field(L, -1, "factors");
    if (lua_istable(L, -1)) {
      raw_field(L, -1, kind.c_str());
      if (lua_type(L, -1) == LUA_TNUMBER) value = lua_tonumber(L, -1);
    }
  });
  return value;
}

void Sport::set_factor(const std::string& kind, double value) {
  const std::vector<std::string> kinds = fate_kind_names();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
    throw std::invalid_argument(unknown_key(kind, kinds, "fate kind"));
  if (game::bounded_factor(value).problem)
    throw std::invalid_argument("factor for " + kind + " must be a number in [0, 1e6]");
  lua_State* L = sandbox_->L();
  sandbox_->protect([&] {
    lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
    raw_field(L, -1, "factors");
    if (!lua_istable(L, -1)) {
      lua_pop(L, 1);
      lua_newtable(L);
      lua_pushstring(L, "factors");
      lua_pushvalue(L, -2);
      lua_rawset(L, -4);
    }
    lua_pushstring(L, kind.c_str());
    lua_pushnumber(L, value);
    lua_rawset(L, -3);
  });
}

void Sport::factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
                    game::FactorTerms& terms) {
  zeroed_by_.reserve(std::max(kBusyFateGroups, fates.size()));  // as Match's fate buffers: room for a busy moment
  zeroed_by_.assign(fates.size(), kNotZeroed);
  bool scripted = false;
  if (!disabled_ && !sandbox_->spent()) {
    try {
      sandbox_->protect([&] { script_factors(fates, match, out, terms); });
      scripted = true;
    } catch (const ScriptError& e) {
      if (!stuck(match)) match.report_error(std::string(e.what()) + " (this frame's modifiers skipped)");
    }
  }
  if (!scripted) {  // the scripts could not run: the factors by kind as last read
    terms.clear();
    for (size_t k = 0; k < fates.size(); ++k) {
      out[k] = by_kind_[int(fates[k].fate.kind)];
      terms.add(k, {game::FactorTerm::Source::Sport, 0, -1, {}, 0, false, out[k]});
    }
  }
  for (size_t k = 0; k < fates.size(); ++k)
    if (out[k] == 0 && zeroed_by_[k] == kNotZeroed && by_kind_[int(fates[k].fate.kind)] == 0) zeroed_by_[k] = kKindFactor;
  double kept = 0, mass = 0;
  for (size_t k = 0; k < fates.size(); ++k) kept += fates[k].mass * out[k], mass += fates[k].mass;
  // Particles' fates share the ball, which must go somewhere; tackles are chances of their own,
  // and none at all is a frame like any other.
  const bool tackles = !fates.empty() && fates[0].fate.kind == FateKind::Tackle;
  // Contacts (mass 0) keep their factors: a player given 0 never gets the ball, whatever the fates.
  if (mass > 0 && kept == 0 && !tackles) {
    report_zeroing(fates, match);
    for (size_t k = 0; k < fates.size(); ++k)
      if (!fates[k].contact) out[k] = 1;
    terms.skip();
  }
}

void Sport::script_factors(std::span<const game::FateView> fates, game::Match& match, std::span<double> out,
                           game::FactorTerms& terms) {
  lua_State* L = sandbox_->L();
  const Acting reading(*this, match, false);
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int sport = lua_gettop(L);
  raw_field(L, sport, "factors");
  if (lua_istable(L, -1))  // checked when loaded, but a handler may have changed it since
    for (FateKind k : kFateKinds) {
      raw_field(L, -1, to_string(k));
      const auto culprit = [&] { return file_ + ": factors." + to_string(k) + " is "; };
      by_kind_[int(k)] = lua_isnil(L, -1) ? 1.0 : checked_term(L, match, culprit);
      lua_pop(L, 1);
    }
  raw_field(L, sport, "modifiers");
  const int modifiers = lua_gettop(L);
  const size_t n_modifiers = lua_istable(L, modifiers) ? lua_objlen(L, modifiers) : 0;
  // What a script put there since the sport loaded, told once a frame (the same words each
  // frame: told once and counted) naming the function after which it was so.
  const auto not_usable = [&](const std::string& what, int index) {
    match.report_error((modifiers_broken_by_.empty() ? file_ + ": " : modifiers_broken_by_ + "since this function ran, ") +
                       what + " is a " + luaL_typename(L, index) + ", not " +
                       (what == "modifiers" ? "a list of functions" : "a function") + " (skipped)");
  };
  bool told = !lua_isnil(L, modifiers) && !lua_istable(L, modifiers);
  if (told) not_usable("modifiers", modifiers);
  // The players and power-ups a power-up's factor sees, filled once for all fates.
  for (size_t k = 0; k < match.players().size() && !match.powerups().empty(); ++k) {
    player_tables_.push(L, k);
    fill_player(L, match, k);
    lua_pop(L, 1);
  }
  for (size_t j = 0; j < match.powerups().size(); ++j) {
    powerup_tables_.push(L, j);
    fill_powerup(L, match, match.powerups()[j]);
    lua_pop(L, 1);
  }
  for (size_t k = 0; k < fates.size(); ++k) {
    const game::FateView& f = fates[k];
    double factor = by_kind_[int(f.fate.kind)];
    terms.add(k, {game::FactorTerm::Source::Sport, 0, -1, {}, 0, false, factor});
    if (factor == 0) zeroed_by_[k] = kKindFactor;
    if (n_modifiers > 0 || !match.powerups().empty()) {
      fate_tables_.push(L, k);
      fill_fate(L, f, match.field());
      lua_pop(L, 1);
    }
    for (size_t i = 1; i <= n_modifiers && !sandbox_->spent(); ++i) {  // spent: the rest keep their factor
      lua_rawgeti(L, modifiers, int(i));
      if (!lua_isfunction(L, -1)) {
        if (!told) not_usable("modifiers[" + std::to_string(i) + "]", -1), told = true;
        lua_pop(L, 1);
        continue;
      }
      fate_tables_.push(L, k);
      lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
      std::string error;
      if (!call(2, 1, error)) {
        match.report_error(error + " (modifiers[" + std::to_string(i) + "] skipped)");
        continue;
      }
      if (!lua_isnil(L, -1)) {
        const double m = checked_term(L, match, [&] {
          lua_rawgeti(L, modifiers, int(i));
          const std::string at = defined_at(L, -1, file_);
          lua_pop(L, 1);
          return at + "modifiers[" + std::to_string(i) + "] returned ";
        });
        factor = times(factor, m);
        terms.add(k, {game::FactorTerm::Source::Modifier, int(i), -1, {}, 0, false, m});
        if (m == 0 && zeroed_by_[k] == kNotZeroed) zeroed_by_[k] = modifier_code(i);
      }
      lua_pop(L, 1);
    }
    powerup_factors(k, match, factor, terms);
    out[k] = factor;
  }
}

bool Sport::call(int nargs, int nresults, std::string& error) {
  lua_State* L = sandbox_->L();
  lua_pushvalue(L, -nargs - 1);  // the function, kept below it for its place
  lua_insert(L, -nargs - 2);
  const bool ok = sandbox_->call(nargs, nresults, error);
  const int function = lua_gettop(L) - (ok ? nresults : 0);
  if (modifiers_usable(L)) modifiers_broken_by_.clear();
  else if (modifiers_broken_by_.empty()) modifiers_broken_by_ = defined_at(L, function, file_);
  lua_remove(L, function);
  return ok;
}

// Whether the sport's modifiers are none or a list of functions, as loading checked. A list a
// script made as long as memory allows is looked at until the frame's budget is spent (the
// watchdog's flag), not past it; what is not looked at counts as usable.
bool Sport::modifiers_usable(lua_State* L) {
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  raw_field(L, -1, "modifiers");
  bool usable = lua_isnil(L, -1) || lua_istable(L, -1);
  if (lua_istable(L, -1))
    for (size_t i = 1, n = lua_objlen(L, -1); i <= n && usable && !sandbox_->spent(); ++i) {
      lua_rawgeti(L, -1, int(i));
      usable = lua_isfunction(L, -1);
      lua_pop(L, 1);
    }
  lua_pop(L, 2);
  return usable;
}

// Every fate zeroed: the draw would have nothing left to choose from. The match goes on with
// this frame's factors skipped, and the error names what zeroed them.
void Sport::report_zeroing(std::span<const game::FateView> fates, game::Match& match) {
  std::vector<int> culprits;
  for (size_t k = 0; k < fates.size(); ++k)
    if (fates[k].mass > 0 && std::find(culprits.begin(), culprits.end(), zeroed_by_[k]) == culprits.end())
      culprits.push_back(zeroed_by_[k]);
  std::sort(culprits.begin(), culprits.end(), std::greater<>());
  std::string who;
  for (int c : culprits) {
    std::string name;
    if (c == kNotZeroed) {
      name = file_ + ": factors too small to tell from 0 (their product underflows)";
    } else if (c == kKindFactor) {
      name = file_ + ": factors";
      std::string kinds;
      for (const game::FateView& f : fates)
        if (f.mass > 0 && kinds.find(f.kind()) == std::string::npos) kinds += std::string(kinds.empty() ? "" : "/") + f.kind();
      name += " (" + kinds + ")";
    } else if (c > 0) {
      name = file_ + ": modifiers[" + std::to_string(c) + "]";
    } else {
      const std::string& p = match.powerups()[size_t(-2 - c)].name;
      name = "power-up " + p + " (" + powerup_files_[p] + ")";
    }
    who += (who.empty() ? "" : ", ") + name;
  }
  match.report_error(who + (culprits.size() > 1 ? " together give" : " gives") +
                     " every fate a factor of 0, which would leave the ball nowhere to be; this frame's factors are "
                     "skipped");
}

void Sport::on_event(const game::GameEvent& e, game::Match& match) {
  if (disabled_ || sandbox_->spent()) return game::plain_event(e, match);
  try {
    sandbox_->protect([&] { run_handler(e, match); });
  } catch (const ScriptError& x) {
    if (stuck(match)) return game::plain_event(e, match);  // so that no goal goes uncounted
    match.report_error(std::string(x.what()) + " (on." + game::to_string(e.type) + " skipped)");
  }
}

void Sport::run_handler(const game::GameEvent& e, game::Match& match) {
  lua_State* L = sandbox_->L();
  const Acting acting(*this, match, true);
  if (e.type == game::EventKind::Powerup || e.type == game::EventKind::PowerupEnd) {
    const int before = lua_gettop(L);
    try {
      announce_powerup(e, match);
    } catch (const std::exception& x) {
      lua_settop(L, before);
      match.report_error(std::string(x.what()) + " (announcing power-up " + e.powerup + ")");
    }
  }
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  raw_field(L, -1, "on");
  if (!lua_istable(L, -1)) return;
  raw_field(L, -1, game::to_string(e.type));
  if (!lua_isfunction(L, -1)) return;
  lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
  push_event(L, e);
  std::string error;
  if (!call(2, 0, error)) match.report_error(error + " (on." + game::to_string(e.type) + " skipped)");
}

void Sport::begin_frame(game::Match& match) {
  if (stuck(match)) return;
  if (sandbox_->spent()) note_overrun(match);
  sandbox_->new_period();
}

bool Sport::stuck(game::Match& match) {
  if (!sandbox_->abandoned()) return false;
  if (!disabled_) {
    disabled_ = true;
    match.report_error(sandbox_->stuck() + "; " + name_ +
                       " disabled: the match goes on with the engine's plain rules (a goal counts for the other team)");
  }
  return true;
}

// The script that ran when the budget ran out: a power-up's file, else the sport's own.
void Sport::note_overrun(game::Match& match) {
  const std::string& file = sandbox_->spent_in();
  std::string powerup;
  for (const auto& [name, f] : powerup_files_)
    if (f == file) powerup = name;
  if (++overruns_[powerup] < kOverrunsToDisable) return;
  const std::string times = " ran out of a frame's Lua budget " + std::to_string(kOverrunsToDisable) + " times";
  if (!powerup.empty()) {
    if (disabled_powerups_.insert(powerup).second)
      match.report_error(file + ": power-up " + powerup + " disabled: it" + times + "; the match goes on without it");
  } else if (!disabled_) {
    disabled_ = true;
    match.report_error((file.empty() ? file_ : file) + ": " + name_ + " disabled: its scripts" + times +
                       "; the match goes on with the engine's plain rules (a goal counts for the other team)");
  }
}

int Sport::add_timer(game::Match& match, double seconds) {
  lua_State* L = sandbox_->L();
  if (!(std::isfinite(seconds) && seconds > 0 && seconds <= 3600))
    throw std::invalid_argument("seconds must be in (0, 3600], got " + std::to_string(seconds));
  if (timers_.size() >= 1000) throw std::invalid_argument("1000 timers are pending already");
  const int function = luaL_ref(L, LUA_REGISTRYINDEX);
  timers_.push_back({match.time() + seconds, next_timer_, function});
  return next_timer_++;
}

void Sport::cancel_timer(int id) {
  const auto it = std::find_if(timers_.begin(), timers_.end(), [&](const Timer& t) { return t.id == id; });
  if (it == timers_.end()) return;
  luaL_unref(sandbox_->L(), LUA_REGISTRYINDEX, it->function);
  timers_.erase(it);
}

void Sport::tick(game::Match& match) {
  if (disabled_ || sandbox_->spent()) return;  // due timers wait for a frame with budget
  // Most frames have no timer due: the trip to the sandbox's thread is spared them.
  if (std::none_of(timers_.begin(), timers_.end(), [&](const Timer& t) { return t.is_due(match.time()); })) return;
  try {
    sandbox_->protect([&] { run_timers(match); });
  } catch (const ScriptError& x) {
    if (!stuck(match)) match.report_error(std::string(x.what()) + " (timer skipped)");
  }
}

void Sport::run_timers(game::Match& match) {
  lua_State* L = sandbox_->L();
  // Timers set while these run wait for the next frame, however short their delay.
  const int before = next_timer_;
  for (;;) {
    auto next = timers_.end();
    for (auto it = timers_.begin(); it != timers_.end(); ++it)
      if (it->id < before && it->is_due(match.time()) &&
          (next == timers_.end() || it->due < next->due || (it->due == next->due && it->id < next->id)))
        next = it;
    if (next == timers_.end() || sandbox_->spent()) return;
    const Timer timer = *next;
    timers_.erase(next);
    const Acting acting(*this, match, true);
    match.set_cause("timer");
    lua_rawgeti(L, LUA_REGISTRYINDEX, timer.function);
    luaL_unref(L, LUA_REGISTRYINDEX, timer.function);
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    std::string error;
    if (!call(1, 0, error)) match.report_error(error + " (timer skipped)");
  }
}

int Sport::powerup(const std::string& name) {
  if (const auto it = powerups_.find(name); it != powerups_.end()) return it->second;
  if (!plain_powerup_name(name))
    throw std::invalid_argument("power-up '" + name + "': names are lower-case letters, digits and _");
  std::string looked;
  const fs::path file = powerup_file(name, looked);
  if (file.empty()) throw ScriptError("no power-up '" + name + "' (looked for " + looked + ")");
  lua_State* L = sandbox_->L();
  const int base = lua_gettop(L);
  sandbox_->run_file(file.string());
  const std::string where = file.string() + ": ";
  const Reader r(L);
  try {
    r.expect(LUA_TTABLE, "", "a table");
    const int t = lua_gettop(L);
    r.no_near_misses(t, "", kPowerupKeys);
    if (!r.field(t, "factor")) r.fail("", "needs factor = function(fate, holder, game, p)");
    r.expect(LUA_TFUNCTION, "factor");
    lua_pop(L, 1);
    if (!(r.number(t, "duration", "", 0, true) > 0)) r.fail("duration", "must be seconds > 0");
    for (const char* optional : {"start", "stop"}) {
      if (!r.field(t, optional)) continue;
      r.expect(LUA_TFUNCTION, optional);
      lua_pop(L, 1);
    }
    if (r.field(t, "defaults")) {
      r.expect(LUA_TTABLE, "defaults");
      r.map(-1, "defaults", [&](const std::string&, const std::string& place) { r.expect(LUA_TNUMBER, place); });
      lua_pop(L, 1);
    }
    if (r.field(t, "phrases")) {
      r.expect(LUA_TTABLE, "phrases");
      r.only_keys(-1, "phrases", {"start", "over"});
      r.map(-1, "phrases", [&](const std::string&, const std::string& place) {
        r.expect(LUA_TSTRING, place);
        try {
          check_engine_phrase(place, PhraseTemplate(lua_tostring(L, -1)), kPowerupVars);
        } catch (const std::invalid_argument& e) {
          r.fail(place, e.what());
        }
      });
      lua_pop(L, 1);
    }
  } catch (const ReadError& e) {
    lua_settop(L, base);
    throw ScriptError(where + e.what());
  }
  powerup_files_[name] = file.string();
  return powerups_[name] = luaL_ref(L, LUA_REGISTRYINDEX);
}

fs::path Sport::powerup_file(const std::string& name, std::string& looked) const {
  return confined_path(powerup_folders_, name + ".lua", "power-up '" + name + "'", looked);
}

void Sport::grant(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts) {
  if (disabled_ || disabled_powerups_.count(name))
    throw std::invalid_argument("power-up " + name + ": disabled in this match (its scripts overran their budget)");
  sandbox_->protect([&] { grant_protected(match, player, name, std::move(opts)); });
}

void Sport::grant_protected(game::Match& match, int player, const std::string& name, std::map<std::string, double> opts) {
  lua_State* L = sandbox_->L();
  const int script = powerup(name);
  const int top = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, script);
  const int t = lua_gettop(L);
  // The script's defaults, then the grant's own numbers.
  raw_field(L, t, "defaults");
  std::map<std::string, double> params = numbers_of(L, lua_gettop(L));
  lua_pop(L, 1);
  for (const auto& [key, value] : opts) params[key] = value;
  raw_field(L, t, "duration");
  double seconds = lua_tonumber(L, -1);
  lua_pop(L, 1);
  if (const auto it = params.find("seconds"); it != params.end()) seconds = it->second, params.erase(it);
  if (!(seconds > 0 && seconds <= 3600)) {
    lua_settop(L, top);
    throw std::invalid_argument("power-up " + name + ": seconds must be in (0, 3600], got " + std::to_string(seconds));
  }
  // start(holder, game, p) may note what the power-up needs later (black ice: the velocity to keep).
  raw_field(L, t, "start");
  if (lua_isfunction(L, -1)) {
    const Acting acting(*this, match, true);
    lua_newtable(L);
    fill_player(L, match, size_t(player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    lua_createtable(L, 0, int(params.size()));
    for (const auto& [key, value] : params) {
      lua_pushnumber(L, value);
      raw_set(L, key.c_str());
    }
    lua_pushvalue(L, -1);
    lua_insert(L, -5);  // a reference to the params table below the function, for after the call
    std::string error;
    if (!call(3, 0, error)) {
      lua_settop(L, top);
      throw ScriptError(error + " (start of power-up " + name + ")");
    }
    params = numbers_of(L, lua_gettop(L));
  }
  lua_settop(L, top);
  match.grant(player, name, seconds, std::move(params));
}

void Sport::powerup_factors(size_t fate, game::Match& match, double& factor, game::FactorTerms& terms) {
  lua_State* L = sandbox_->L();
  int& zeroed_by = zeroed_by_[fate];
  for (size_t j = 0; j < match.powerups().size(); ++j) {
    const game::ActivePowerup& a = match.powerups()[j];
    if (disabled_powerups_.count(a.name) || sandbox_->spent()) continue;
    int script = LUA_NOREF;
    try {
      script = powerup(a.name);  // granted before this sport was reloaded: its script loads here
    } catch (const std::exception& e) {
      match.report_error(std::string(e.what()) + " (power-up " + a.name + " skipped)");
      continue;
    }
    const int top = lua_gettop(L);
    lua_rawgeti(L, LUA_REGISTRYINDEX, script);
    raw_field(L, -1, "factor");
    fate_tables_.push(L, fate);
    player_tables_.push(L, size_t(a.player));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    powerup_tables_.push(L, j);
    std::string error;
    if (!call(4, 1, error)) {
      match.report_error(error + " (power-up " + a.name + " skipped)");
    } else if (!lua_isnil(L, -1)) {
      const double f = checked_term(L, match, [&] {
        raw_field(L, top + 1, "factor");
        const std::string at = defined_at(L, -1, powerup_files_[a.name]);
        lua_pop(L, 1);
        return at + "power-up " + a.name + ": factor returned ";
      });
      factor = times(factor, f);
      const auto strength = a.params.find("strength");
      terms.add(fate, {game::FactorTerm::Source::Powerup, a.name_id, a.player, {},
                       strength == a.params.end() ? 0 : strength->second, strength != a.params.end(), f});
      if (f == 0 && zeroed_by == kNotZeroed) zeroed_by = powerup_code(j);
    }
    lua_settop(L, top);
  }
}

std::vector<std::string> Sport::reload_powerups(const std::vector<std::string>& names, game::Match& match) {
  begin_frame(match);
  std::vector<std::string> errors;
  for (const std::string& name : names) {
    errors.emplace_back();
    const auto it = powerups_.find(name);
    if (it == powerups_.end()) continue;  // never used: it loads fresh when granted
    const int old = it->second;
    const std::string old_file = powerup_files_[name];
    powerups_.erase(it);
    try {
      sandbox_->protect([&] { powerup(name); });
      disabled_powerups_.erase(name), overruns_.erase(name);  // a new version gets a fresh start
      luaL_unref(sandbox_->L(), LUA_REGISTRYINDEX, old);
    } catch (const std::exception& e) {
      powerups_[name] = old;
      powerup_files_[name] = old_file;
      errors.back() = e.what();
    }
  }
  sandbox_->new_period();
  return errors;
}

namespace {

// Copies sport.state from the old version's Lua state into the new one's. Recursive in C, so the
// nesting is bounded (a chain of tables 10^5 deep would overflow the C and Lua stacks); a state
// past a limit is refused whole rather than carried over in part.
struct PlainCopy {
  static constexpr int kMaxValues = 100000;
  static constexpr int kMaxDepth = 100;
  lua_State* from;
  lua_State* to;
  int seen;  // index in `to` of a table: from's table pointer -> its copy
  int values = 0;
  int depth = 0;

  // Raised in `to`, which runs this under lua_cpcall: `from` never raises (lua_next and the
  // pushes below cannot, and lua_checkstack reports rather than raises).
  void copy(int index) {
    index = index < 0 ? lua_gettop(from) + index + 1 : index;
    Sandbox::check_budget(to);
    if (++values > kMaxValues)
      luaL_error(to, "sport.state holds more than %d values", kMaxValues);
    switch (lua_type(from, index)) {
      case LUA_TBOOLEAN: lua_pushboolean(to, lua_toboolean(from, index)); return;
      case LUA_TNUMBER: lua_pushnumber(to, lua_tonumber(from, index)); return;
      case LUA_TSTRING: {
        size_t n = 0;
        const char* text = lua_tolstring(from, index, &n);
        lua_pushlstring(to, text, n);
        return;
      }
      case LUA_TTABLE: break;
      default: lua_pushnil(to); return;  // functions and the like belong to the old script
    }
    lua_pushlightuserdata(to, const_cast<void*>(lua_topointer(from, index)));
    lua_rawget(to, seen);
    if (!lua_isnil(to, -1)) return;
    if (depth == kMaxDepth) luaL_error(to, "sport.state nests tables more than %d deep", kMaxDepth);
    if (!lua_checkstack(from, 4) || !lua_checkstack(to, 6)) luaL_error(to, "not enough memory");
    ++depth;
    lua_pop(to, 1);
    lua_newtable(to);
    lua_pushlightuserdata(to, const_cast<void*>(lua_topointer(from, index)));
    lua_pushvalue(to, -2);
    lua_rawset(to, seen);
    lua_pushnil(from);
    while (lua_next(from, index)) {
      const int key = lua_type(from, -2);
      if (key == LUA_TSTRING || key == LUA_TNUMBER) {
        copy(-2);
        copy(-1);
        if (lua_isnil(to, -2)) lua_pop(to, 2);
        else lua_rawset(to, -3);
      }
      lua_pop(from, 1);
    }
    --depth;
  }

  // Under lua_cpcall on `to`: running out of the new sandbox's memory is an error, not a panic.
  static int run(lua_State* L) {
    auto* c = static_cast<PlainCopy*>(lua_touserdata(L, 1));
    lua_settop(L, 0);
    lua_newtable(L);
    c->seen = lua_gettop(L);
    c->copy(-1);
    lua_remove(L, c->seen);
    lua_setfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");  // out of the protected call
    return 0;
  }
};

}  // namespace

void Sport::take_over(Sport& old, game::Match& match) {
  // The power-ups the match holds load with the new version, not in its first frame: loading is
  // the engine's work, and under the address sanitizer a few scripts' loading spent a frame's
  // whole budget, so their factors were skipped (seen in the soak). One that fails to load is
  // reported when the frame asks for it.
  for (const game::ActivePowerup& a : match.powerups()) {
    try {
      sandbox_->protect([&] { powerup(a.name); });
    } catch (const std::exception&) {
    }
  }
  if (old.sandbox_->abandoned()) return;  // its state cannot be read: the new version starts afresh
  old.sandbox_->new_period();  // reading its state is the engine's work, whatever the old scripts spent
  try {
    old.sandbox_->protect([&] { sandbox_->protect([&] { carry_state(old, match); }); });
  } catch (const ScriptError& e) {
    if (!stuck(match)) match.report_error(std::string(e.what()) + " (on_reload skipped)");
  }
}

void Sport::carry_state(Sport& old, game::Match& match) {
  lua_State* from = old.sandbox_->L();
  lua_State* L = sandbox_->L();
  const int old_top = lua_gettop(from), top = lua_gettop(L);
  lua_rawgeti(from, LUA_REGISTRYINDEX, old.sport_ref_);
  raw_field(from, lua_gettop(from), "state");
  lua_rawgeti(L, LUA_REGISTRYINDEX, sport_ref_);
  const int t = lua_gettop(L);
  PlainCopy copy{from, L, 0};
  if (lua_cpcall(L, PlainCopy::run, &copy) != 0) {
    match.report_error(std::string("reload: the old state could not be carried over: ") +
                       (lua_tostring(L, -1) ? lua_tostring(L, -1) : "error"));
    lua_pop(L, 1);
    lua_pushnil(L);
  } else {
    lua_getfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");
    lua_pushnil(L);
    lua_setfield(L, LUA_REGISTRYINDEX, "quantum.reload_state");
  }
  lua_settop(from, old_top);
  raw_field(L, t, "on_reload");
  if (lua_isfunction(L, -1)) {
    lua_insert(L, -2);  // on_reload, state
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    lua_insert(L, -2);  // on_reload, game, state
    const Acting acting(*this, match, true);
    std::string error;
    if (!call(2, 0, error)) match.report_error(error + " (on_reload skipped)");
  } else if (!lua_isnil(L, -2)) {  // nothing to carry: the new version's own state stays
    lua_pop(L, 1);
    lua_pushstring(L, "state");
    lua_insert(L, -2);
    lua_rawset(L, t);
  }
  lua_settop(L, top);
}

void Sport::announce_powerup(const game::GameEvent& e, game::Match& match) {
  const auto script = powerups_.find(e.powerup);
  if (script == powerups_.end()) return;
  lua_State* L = sandbox_->L();
  const int top = lua_gettop(L);
  const bool starting = e.type == game::EventKind::Powerup;
  const std::string team = team_name(std::string(e.team));
  auto vars = [&](std::string_view name) -> std::optional<PhraseValue> {
    if (name == "player") return PhraseValue{e.actor, std::nullopt};
    if (name == "team") return PhraseValue{team, std::nullopt};
    return std::nullopt;
  };
  // The sport's own phrase `<name>_start` (or `_over`) takes the script's place.
  const std::string own = e.powerup + (starting ? "_start" : "_over");
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  raw_field(L, -1, "phrases");
  if (phrases_.find(own)) {
    say(match, own, vars);
  } else if (lua_istable(L, -1)) {
    raw_field(L, -1, starting ? "start" : "over");
    if (lua_isstring(L, -1)) {
      said_.clear();
      PhraseTemplate(lua_tostring(L, -1)).fill(said_, vars);
      match.say(said_);
    }
  }
  lua_settop(L, top);
  // stop(holder, game): undoes what start did to the field (the wormhole closes).
  if (starting || e.actor_index < 0) return;
  lua_rawgeti(L, LUA_REGISTRYINDEX, script->second);
  raw_field(L, -1, "stop");
  if (lua_isfunction(L, -1)) {
    lua_newtable(L);
    fill_player(L, match, size_t(e.actor_index));
    lua_rawgeti(L, LUA_REGISTRYINDEX, game_ref_);
    std::string error;
    if (!call(2, 0, error)) match.report_error(error + " (stop of power-up " + e.powerup + " skipped)");
  }
  lua_settop(L, top);
}

}  // namespace quantum::lua
