// Hostile rule scripts: each thing a designer's script must not do is refused with a clear error,
// and the match goes on. Scripts run in the sandbox (bindings/lua_sandbox.h): no io, os but its
// clock, debug, ffi, jit, native modules or bytecode; one budget per frame (20 ms of CPU, 10
// million instructions) for all of a sport's Lua; 64 MiB.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "game/bots.h"
#include "hostile_support.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

using namespace hostile;

TEST(Hostile, EveryForbiddenThingIsRefusedAndTheMatchGoesOn) {
  const Case cases[] = {
      {"io", "io.open('/etc/passwd')", "global 'io'"},
      {"os_execute", "os.execute('true')", "field 'execute'"},
      {"os_exit", "os.exit(1)", "field 'exit'"},
      {"debug", "debug.sethook()", "global 'debug'"},
      {"ffi", "require('ffi')", "no module 'ffi': the sandbox loads only"},
      {"jit", "jit.on()", "global 'jit'"},
      {"native", "package.loadlib('libc.so.6', 'system')", "global 'package'"},
      {"bytecode", "load(string.dump(function() end))()", "global 'load'"},
      {"loadstring", "loadstring('return 1')()", "global 'loadstring'"},
      {"dofile", "dofile('/etc/passwd')", "global 'dofile'"},
      {"gc", "collectgarbage('stop')", "global 'collectgarbage'"},
      {"endless", "while true do end", "script runs too long"},
      {"endless_after_grant", "game.grant('Red\\'s mallet', 'attract') while true do end", "script runs too long"},
      {"recursion", "local function f() return 1 + f() end f()", "stack overflow"},
      // Copying 64 MiB may take longer than a frame's budget: whichever limit comes first stops it.
      {"string_bomb", "local p = string.rep('x', 2^20) local t = {} for i = 1, 100 do t[i] = p end "
                      "local s = table.concat(t)", "not enough memory|script runs too long"},
      {"rep_bomb", "local s = string.rep('x', 2^30)", "script runs too long"},  // charged for its bytes first
      {"table_bomb", "local t = {} for i = 1, 64 do t[i] = string.rep('y', i * 2^20) end",
       "not enough memory|script runs too long"},
  };
  for (const Case& c : cases) {
    lua::ScriptedRules sport(hostile_sport(c.name, c.body));
    Played played(sport);
    game::Match& match = played.match;
    for (int frame = 0; frame < 30; ++frame) played.step();
    const std::span<const std::string> errors = match.errors();
    ASSERT_EQ(errors.size(), 1u) << c.name;
    EXPECT_TRUE(says_one_of(errors[0], c.error)) << c.name << ": " << errors[0];
    EXPECT_NE(errors[0].find("(on.drop skipped)"), std::string::npos) << errors[0];
    EXPECT_NEAR(match.time(), 0.5, 1e-6) << c.name << ": the match went on";
    EXPECT_TRUE(match.world().live()) << c.name;
  }
}

// print writes stderr (stdout carries `--events -`), names its line, and holds a flood back: a
// line is cut at 1000 bytes and a frame shows at most 20.
TEST(Sandbox, PrintGoesToStderrWithItsLineAndAFloodIsHeldBack) {
  // The 3 MB string is made at load: making it in a frame is charged most of the budget.
  lua::ScriptedRules sport(hostile_sport("print", "print('dropped', 1, nil, true) print(long) for i = 1, 1000 do print(i) end",
                                 "long = string.rep('x', 3e6)"));
  Played played(sport);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  for (int frame = 0; frame < 30; ++frame) played.step();
  const std::string out = testing::internal::GetCapturedStdout(), err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_TRUE(played.match.errors().empty()) << played.match.errors()[0];
  std::vector<std::string> lines;
  for (std::istringstream in(err); std::getline(in, lines.emplace_back());) {}
  lines.pop_back();
  ASSERT_EQ(lines.size(), 21u) << err.substr(0, 3000);
  EXPECT_TRUE(std::regex_match(lines[0], std::regex(R"(print: /\S+/sport\.lua:\d+: dropped\t1\tnil\ttrue)"))) << lines[0];
  EXPECT_TRUE(std::regex_match(lines[1], std::regex(R"(print: /\S+/sport\.lua:\d+: x{1000}\.\.\. \(3000000 bytes in all\))")))
      << lines[1].substr(0, 200);
  EXPECT_TRUE(std::regex_match(lines[19], std::regex(R"(print: /\S+/sport\.lua:\d+: 18)"))) << lines[19];
  EXPECT_EQ(lines[20], "print: more than 20 lines in one frame: the rest of this frame's are not shown");
}

// Loading is not a frame: a sport.lua that spends twice a frame's CPU loading loads, and a grant
// before the first frame whose power-up's start spends 60 % of a frame has a frame's budget of its
// own (as a rule spec does: it grants, then runs).
TEST(Sandbox, LoadingHasItsOwnBudgetAndLeavesTheFirstFramesWhole) {
  const auto spend = [](double frames) {
    return "local t = os.clock() while os.clock() - t < " + std::to_string(frames * lua::Limits{}.cpu_seconds) +
           " do end";
  };
  lua::ScriptedRules sport(hostile_sport("load_budget", "", spend(2),
                                 "return { duration = 5, factor = function() return 1 end,\n"
                                 "  start = function() " + spend(0.6) + " end }\n"));
  Played played(sport);
  EXPECT_NO_THROW(sport.grant(played.match, 0, "evil", {}));
  for (int frame = 0; frame < 30; ++frame) played.step();
  EXPECT_TRUE(played.match.errors().empty()) << played.match.errors()[0];
  EXPECT_EQ(played.match.powerups().size(), 1u);
}

TEST(Hostile, OsClockIsThere) {
  lua::ScriptedRules sport(hostile_sport("clock", "assert(type(os.clock()) == 'number')"));
  Played played(sport);
  played.step();
  EXPECT_TRUE(played.match.errors().empty());
}

// A power-up's factor that loops forever: its factor is skipped each frame, reported, and the
// match goes on.
TEST(Hostile, AnEndlessPowerUpIsSkipped) {
  const fs::path root = fs::temp_directory_path() / "quantum_hostile_powerup";
  fs::remove_all(root);
  fs::create_directories(root / "powerups");
  fs::copy(QUANTUM_SOURCE_DIR "/rules/airhockey", root / "airhockey", fs::copy_options::recursive);
  std::ofstream(root / "powerups" / "spin.lua") << "return { duration = 5, factor = function() while true do end end }\n";
  lua::ScriptedRules sport((root / "airhockey").string());
  Played played(sport);
  game::Match& match = played.match;
  played.step();
  sport.grant(match, 0, "spin", {});
  for (int frame = 0; frame < 3; ++frame) played.step();
  const std::span<const std::string> errors = match.errors();
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find("script runs too long"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("power-up spin skipped"), std::string::npos) << errors[0];
  EXPECT_NEAR(match.time(), 4 / 60.0, 1e-6);
  fs::remove_all(root);
}

TEST(Sandbox, CatchingTheBudgetErrorDoesNotResetIt) {
  const Attack attacks[] = {
      {"pcall_loop", "while true do pcall(function() while true do end end) end", "", "", "script runs too long"},
      {"xpcall_handler", "while true do xpcall(function() while true do end end, function() while true do end end) end",
       "", "", "script runs too long"},
      {"pcall_error", "for i = 1, 1e12 do pcall(error, 'again') end", "", "", "script runs too long"},
      {"timer", "game.after(0.1, function() while true do pcall(function() while true do end end) end end)", "", "",
       "script runs too long"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// Lua for the sport's loading that makes the global `s`, `mb` megabytes of `c`, from 1 MB pieces
// (string.rep would be charged for the whole). Loading has a second: in a frame, the fresh pages
// alone are charged most of the budget (and take it, on a virtual machine).
std::string megabytes(int mb, char c) {
  return "do local p = string.rep('" + std::string(1, c) + "', 2^20) local t = {} for i = 1, " + std::to_string(mb) +
         " do t[i] = p end s = table.concat(t) end ";
}

TEST(Sandbox, TimeInsideLibraryFunctionsIsBounded) {
  const std::string mb30 = megabytes(30, 'a'), mb15 = megabytes(15, 'a') + "b = s:sub(1, -2) .. 'b'",
                    digits30 = megabytes(30, '1'), hex12 = megabytes(12, 'f') + "s = '0x' .. s";
  const Attack attacks[] = {
      {"find_30mb", "while true do s:find('b', 1, true) end", mb30.c_str(), "", "script runs too long"},
      // The hook looks at the budget every instruction once the state holds 32 MB of large blocks.
      {"compare_15mb", "while true do local _ = s < b end", mb15.c_str(), "", "script runs too long"},
      // Whole-string functions are charged for their bytes before they run: refused at once.
      {"tonumber_30mb", "while true do local _ = tonumber(s) end", digits30.c_str(), "", "script runs too long"},
      {"tonumber_hex_12mb", "while true do local _ = tonumber(s) end", hex12.c_str(), "", "script runs too long"},
      {"upper_30mb", "while true do local _ = s:upper() end", mb30.c_str(), "", "script runs too long"},
      // So is a large block's growth: the 30 MB for the result are refused before they are made.
      {"concat_30mb", "while true do local _ = #(s .. 'x') end", mb30.c_str(), "", "script runs too long"},
      {"rep_40mb", "local _ = string.rep('ab', 2e7)", "", "", "script runs too long"},
      {"backtracking_find", "string.find(string.rep('a', 5000), '.-.-.-.-b')", "", "", "script runs too long"},
      {"backtracking_gmatch", "for w in string.rep('a', 5000):gmatch('.-.-.-b') do end", "", "", "script runs too long"},
      {"backtracking_gsub", "local s = string.rep('a', 5000):gsub('.-.-.-b', '')", "", "", "script runs too long"},
      {"sort_huge", "local t = {} for i = 1, 1e5 do t[i] = -i end table.sort(t)", "", "", "more than the sandbox sorts"},
      {"huge_set", "local set = '[' .. string.rep('b', 2e5) .. ']' string.find(string.rep('a', 2e4), set .. '+c')", "",
       "", "script runs too long"},
      // A linear search (memmem) finishes this well inside the budget: the error after it says so.
      {"plain_find_quadratic",
       "local s = string.rep('a', 1e6) string.find(s, string.rep('a', 5e5 - 1) .. 'b', 1, true) error('searched')", "",
       "", "searched"},
      {"sort_by_c_comparator", "local s = string.rep('x', 2e6) local t = {} for i = 1, 2e4 do t[i] = s end "
       "table.sort(t, string.reverse)", "", "", "the comparator must be a Lua function"},
      {"sort_long_strings", "table.sort(long)", "local x = string.rep('x', 1e6) long = {} "
       "for i = 1, 40 do long[i] = x .. i end for k = 41, 4e4 do long[k] = long[k % 40 + 1] end", "",
       "script runs too long"},
      {"gsub_replacement", "local _ = string.rep('x', 1e5):gsub('(x-)', string.rep('%1', 5e5))", "", "",
       "script runs too long"},
      {"fifty_modifiers", "",
       "sport.modifiers = {} for i = 1, 50 do sport.modifiers[i] = function() for k = 1, 3e5 do end return 1 end end",
       "", "script runs too long"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// Memory a script keeps: once the state is full, even the engine's own work in it (an event's
// table, a fate's) fails. Each failure is one reported error, the goals still count (by the plain
// rules when a handler cannot run), and the match ends.
TEST(Sandbox, AStateLeftFullOfMemoryPlaysOn) {
  // 8 MB a piece, kept: the 64 MiB are gone after a few.
  const std::string hoard = "local p = string.rep('x', 2^16) local t = {} for i = 1, 128 do t[i] = p end "
                            "for i = 1, 10 do hoard[#hoard + 1] = table.concat(t) .. i end";
  const std::string in_drop = "hoard = hoard or {} " + hoard;
  const std::string in_timer = "hoard = hoard or {} game.after(0.5, function() " + hoard + " end)";
  const std::string powerup = "hoard = {}\nreturn { duration = 60, factor = function() " + hoard + " return 1 end }\n";
  const Attack attacks[] = {
      {"hoard_in_drop", in_drop.c_str(), "", "", "not enough memory|script runs too long"},
      {"hoard_in_timer", in_timer.c_str(), "", "", "not enough memory|script runs too long"},
      {"hoard_in_factor", "game.grant(\"Red's mallet\", 'evil', { seconds = 60 })", "", powerup.c_str(),
       "not enough memory|script runs too long"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

TEST(Sandbox, CallbacksThatRecurseThroughCEndInAnError) {
  const Attack attacks[] = {
      {"gsub_function", "local function f(s) return (s:gsub('.', f)) end f('ab')", "", "", "nested more than 64 deep"},
      {"gsub_table", "local t t = setmetatable({}, {__index = function(_, k) return (('x' .. k):gsub('.', t)) end}) "
                     "local _ = ('ab'):gsub('.', t)",
       "", "", "nested more than 64 deep"},
      {"sort_comparator", "local function f() table.sort({2, 1}, function(a, b) f() return a < b end) end f()", "", "",
       "nested more than 64 deep"},
      {"format_tostring", "local mt = {} mt.__tostring = function(t) return string.format('%s', t) end "
       "local _ = string.format('%s', setmetatable({}, mt))", "", "", "nested more than 64 deep"},
      {"print_tostring", "local mt = {} mt.__tostring = function(t) print(t) return 'x' end print(setmetatable({}, mt))",
       "", "", "nested more than 64 deep"},
      {"grant_itself", "game.grant(\"Red's mallet\", 'evil')", "",
       "return { duration = 5, factor = function() return 1 end,\n"
       "  start = function(holder, game) game.grant(holder.name, 'evil') end }\n",
       "nested more than 64 deep"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

TEST(Sandbox, TablesTheEngineReadsMayCarryHostileMetatables) {
  const char* const kErring = "{__index = function() error('boo') end, __newindex = function() error('boo') end}";
  const std::string sport_meta = std::string("setmetatable(sport, ") + kErring + ")";
  const std::string on_meta = "setmetatable(sport.on, {__index = function() while true do end end})";
  const std::string factors_meta = std::string("setmetatable(sport.factors, ") + kErring + ")";
  const Attack attacks[] = {
      // The engine reads these raw: the metatables never run, and only the drop's error is heard.
      {"sport_meta", "error('first')", sport_meta.c_str(), "", "first"},
      {"on_meta", "error('first')", on_meta.c_str(), "", "first"},
      {"factors_meta", "error('first')", factors_meta.c_str(), "", "first"},
      // A fate table the engine fills again next time, with a field gone and writes refused: its
      // metatable is dropped first (the tables are handed to other scripts too), so it never runs.
      {"fate_meta", "error('first')",
       "sport.modifiers = { function(fate) fate.kind = nil setmetatable(fate, {__newindex = function() error('no "
       "writes') end}) return 1 end }",
       "", "first"},
      {"powerup_meta", "game.grant(\"Red's mallet\", 'evil') error('first')", "",
       "return setmetatable({ duration = 5, factor = function(fate, holder) holder.name = nil\n"
       "  setmetatable(holder, {__newindex = function() error('no writes') end}) return 1 end },\n"
       "  {__index = function() error('boo') end})\n",
       "first"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// `n` numbers that LuaJIT files under one hash slot, as Lua that defines `key(i)`, the i-th of
// them (i in 1..n). LuaJIT hashes a number by its bits with no seed (lj_tab.c's hashrot), so the hash can be
// run backwards: for each low word, the high word that makes the hash 0x12345678. Every store
// and every step of lua_next over such a table walks a chain as long as the table. (Were a
// LuaJIT to seed that hash, the keys would no longer collide and these attacks would cost
// nothing: the tests still pass, and prove less.)
std::string colliding_keys(int n) {
  auto rol = [](uint32_t x, int k) { return (x << k) | (x >> (32 - k)); };
  auto ror = [](uint32_t x, int k) { return (x >> k) | (x << (32 - k)); };
  constexpr uint32_t kHash = 0x12345678;
  std::string hex;
  char word[17];
  for (uint32_t x = 1; int(hex.size()) < 16 * n; ++x) {
    const uint32_t h1 = ror((kHash + rol(x, 13)) ^ x, 5), h = ror(h1, 14);
    if (h & 1) continue;
    const uint32_t lo = (x + h1) ^ h, hi = h >> 1;
    const uint32_t exponent = (hi >> 20) & 0x7ff;
    const double d = std::bit_cast<double>((uint64_t(hi) << 32) | lo);
    if (exponent == 0 || exponent == 0x7ff || d == std::trunc(d)) continue;  // not a number, or an array index
    std::snprintf(word, sizeof word, "%08x%08x", hi, lo);
    hex += word;
  }
  // From hex in one string, not as n literals: the parser would file the literals in a table too.
  return "local hex = '" + hex + "' local function key(i) "
         "local hi, lo = tonumber(hex:sub(16 * i - 15, 16 * i - 8), 16), tonumber(hex:sub(16 * i - 7, 16 * i), 16) "
         "local m = 1 + ((hi % 2^20) * 2^32 + lo) / 2^52 "
         "local k = math.ldexp(m, math.floor(hi / 2^20) % 2048 - 1023) return hi >= 2^31 and -k or k end\n";
}

// Work the engine does in C for a script is under the budget too, with no hook to look: every
// call of the game table checks it before it runs, and every step of the engine's reads of a
// script's table (here game.grant's options: lua_next over keys that collide, each step a walk
// of the whole chain; before, one grant took 0.6 s at 32,768 keys). An error that names a line
// no running script is at (a script blaming another) gets its own line in front.
TEST(Sandbox, EngineWorkForAScriptIsWithinTheBudget) {
  const std::string options = colliding_keys(8192) + " OPTS = {} for i = 1, 8192 do OPTS[key(i)] = 1 end";
  const Attack attacks[] = {
      {"grant_colliding_options", "for i = 1, 1000 do game.grant(\"Red's mallet\", 'attract', OPTS) end", options.c_str(),
       "", "script runs too long"},
      {"blaming_another_file", "error('/tmp/elsewhere/other.lua:1: not me', 0)", "", "", "not me"},
  };
  for (const Attack& a : attacks) expect_survived(a);

  // Each game.wormhole predicts the whole cloud again; a loop of them spent 0.75 s of one handler
  // at 20,000 particles, 109 calls between two looks of the hook.
  SCOPED_TRACE("wormhole_loop");
  lua::ScriptedRules sport(hostile_sport("wormhole_loop", "for i = 1, 1e6 do game.wormhole(-0.3, 0.3, 0.6, 0, 0.1) end"));
  const Finished f = play_out(sport, 10, 20000);
  EXPECT_TRUE(f.finished);
  ASSERT_FALSE(f.errors.empty());
  EXPECT_TRUE(std::regex_search(f.errors[0], std::regex(R"(^/\S+/sport\.lua:\d+: .*script runs too long)"))) << f.errors[0];
  EXPECT_LE(sport.sandbox().longest_period_cpu(), kFrameBound);
}

// One instruction no hook can interrupt: a table whose keys all collide files every key again, in
// one step, when it grows (LuaJIT hashes numbers with no seed), in time quadratic in the keys.
// Each attack grows one by 200 keys a frame until a rehash of 8,192 keys (about 50 ms), 16,384
// (0.16 s) or 32,768 (0.65 s) runs in one instruction: in a timer, in a modifier (inside the
// engine's walk over the fates) and in a power-up's start (a script's game.grant calling the
// script again, engine frames between). The watchdog abandons the sandbox at the bound, the sport
// is disabled with one error naming the function that ran, and the match plays on by the plain
// rules, every goal counted. (A rehash that ends within the bound is an overrun: at most one
// before the one that is not.)
TEST(Sandbox, AnInstructionNoHookCanStopIsAbandonedAtTheBound) {
  const std::string keys = colliding_keys(32769);
  const std::string grow = keys + R"(
local table_of_keys, filed = {}, 0
local function grow()
  for i = filed + 1, math.min(filed + 200, 32769) do table_of_keys[key(i)] = true end
  filed = math.min(filed + 200, 32769)
end
)";
  const std::string in_timer = grow + "function tick(game) game.after(0.02, tick) grow() end";
  const std::string in_modifier =
      grow + "local last sport.modifiers = { function(fate, game) if game.time() ~= last then last = game.time() grow() end "
             "return 1 end }";
  const std::string in_powerup = grow + "return { duration = 0.01, factor = function() return 1 end, start = grow }\n";
  const struct {
    const char* name;
    const char* drop;
    const std::string& extra;
    const std::string& powerup;
  } attacks[] = {
      {"collide_timer", "if not TICKING then TICKING = true game.after(0.02, tick) end", in_timer, ""},
      {"collide_modifier", "", in_modifier, ""},
      {"collide_powerup", "if not TICKING then TICKING = true game.after(0.02, tick) end",
       "function tick(game) game.after(0.02, tick) game.grant(\"Red's mallet\", 'evil', { seconds = 0.01 }) end", in_powerup},
  };
  for (const auto& a : attacks) {
    SCOPED_TRACE(a.name);
    lua::ScriptedRules sport(hostile_sport(a.name, a.drop, a.extra, a.powerup));
    const Finished f = play_out(sport);
    EXPECT_TRUE(sport.sandbox().abandoned());
    EXPECT_TRUE(sport.disabled());
    EXPECT_TRUE(f.finished);
    EXPECT_GT(f.goals, 0);
    EXPECT_EQ(f.scored, f.goals) << "a goal went uncounted";
    int stuck = 0;
    std::string all;
    for (const std::string& e : f.errors) {
      all += e + "\n";
      if (e.find("script stuck") != std::string::npos) {
        ++stuck;
        EXPECT_TRUE(std::regex_search(e, std::regex(R"(^/\S+/(sport|evil)\.lua:\d+: script stuck: .*; Quantum air hockey disabled: )")))
            << e;
      }
    }
    EXPECT_EQ(stuck, 1) << all;
    EXPECT_LE(f.errors.size(), 2u) << all;  // and at most one overrun before
    EXPECT_LE(sport.sandbox().longest_period_cpu(), kFrameBound) << all;
  }
}

TEST(Sandbox, EveryErrorNamesItsFileAndLine) {
  const Attack attacks[] = {
      {"error_table", "error({ code = 1 })", "", "", "error raised with a table"},
      {"error_nil", "error()", "", "", "error raised with a nil"},
      {"error_false", "error(false)", "", "", "error raised with a boolean"},
      {"error_level0", "error('no place given', 0)", "", "", "no place given"},
      {"error_in_powerup", "game.grant(\"Red's mallet\", 'evil')", "",
       "return { duration = 5, factor = function() error(setmetatable({}, {__tostring = function() while true do end "
       "end})) end }\n",
       "error raised with a table"},
  };
  for (const Attack& a : attacks) expect_survived(a);
}

// The sandbox's own pattern functions (bindings/lua_bounded.h) against LuaJIT's: the same results
// for a fixed list and 20,000 random subjects and patterns (or an error from both).
TEST(Sandbox, PatternFunctionsMatchLuajitsOwn) {
  const char* probe = R"(
    local s, p = ...
    local out = {}
    local function add(ok, ...)
      if not ok then out[#out + 1] = "error" return end
      local n = select("#", ...)
      out[#out + 1] = n .. ":"
      for i = 1, n do out[#out + 1] = tostring((select(i, ...))) end
    end
    add(pcall(string.find, s, p))
    add(pcall(string.find, s, p, 3))
    add(pcall(string.find, s, p, -2, true))
    add(pcall(string.match, s, p))
    add(pcall(string.gsub, s, p, "<%0>"))
    add(pcall(string.gsub, s, p, function(c) return c == "a" and "A" or nil end, 2))
    add(pcall(string.gsub, s, p, { a = "1", b = false }))
    add(pcall(function() local t = {} for a, b in s:gmatch(p) do t[#t + 1] = tostring(a) .. "," .. tostring(b) end return table.concat(t, ";") end))
    return table.concat(out, "|")
  )";
  const lua::Sandbox::Ptr sandbox = lua::Sandbox::make(lua::Limits{}, false);
  lua_State* own = sandbox->L();
  lua_State* jit = luaL_newstate();
  luaL_openlibs(jit);
  auto load = [&](lua_State* L, bool sandboxed) {
    ASSERT_EQ(luaL_loadstring(L, probe), 0);
    if (sandboxed) {
      sandbox->push_environment();
      lua_setfenv(L, -2);
    }
    lua_setglobal(L, "probe");
  };
  load(own, true);
  load(jit, false);
  auto run = [&](lua_State* L, const std::string& subject, const std::string& pattern, bool sandboxed) {
    lua_getglobal(L, "probe");
    lua_pushlstring(L, subject.data(), subject.size());
    lua_pushlstring(L, pattern.data(), pattern.size());
    std::string result, error;
    if (sandboxed) {
      sandbox->new_period();
      if (!sandbox->call(2, 1, error)) return "failed: " + error;
    } else if (lua_pcall(L, 2, 1, 0) != 0) {
      return std::string("failed: ") + lua_tostring(L, -1);
    }
    result = lua_tostring(L, -1);
    lua_pop(L, 1);
    return result;
  };
  std::vector<std::pair<std::string, std::string>> cases = {
      {"hello world", "o w"},      {"hello world", "(o)(r)"},   {"key = value", "(%w+)%s*=%s*(%w+)"},
      {"a(b(c)d)e", "%b()"},       {"THE (quick) fox", "%f[%a]%a+"}, {"aaa", "a-b"},
      {"abcabc", "(abc)%1"},       {"x = 1, y = 2", "()=()"},   {"[tag]", "[%[%]]"},
      {"", ""},                    {"abc", "^b"},               {"abc", "c$"},
      {"a.b", "%."},               {"100%", "%d+%%"},           {"  trim  ", "^%s*(.-)%s*$"},
      {"abc", "[a-"},              {"abc", "%"},                {"abc", "(()"},
      {"abc", "%2"},               {"a\0b", "%z"},             {"abc", "[]]"},
      {"a]b", "[]]"},              {"abc", "[^]a]"},            {"caab", "a*b"},
      {"one two  three", "%S+"},   {"x", "x?x?x"},              {"abc", ".-$"},
  };
  std::mt19937 rng(17);
  const std::vector<std::string> tokens = {"a", "b", ".", "%a", "%d", "%s", "[ab]", "[^a]", "[%d.]", "*", "+", "-", "?",
                                           "(", ")", "()", "%b()", "%f[a]", "^", "$", "%1", "%", "[", "]", "x"};
  const std::string letters = "ab(). 1x";
  for (int k = 0; k < 20000; ++k) {
    std::string subject, pattern;
    for (int i = int(rng() % 9); i > 0; --i) subject += letters[rng() % letters.size()];
    for (int i = 1 + int(rng() % 5); i > 0; --i) pattern += tokens[rng() % tokens.size()];
    cases.push_back({subject, pattern});
  }
  int differ = 0;
  for (const auto& [subject, pattern] : cases) {
    const std::string ours = run(own, subject, pattern, true), theirs = run(jit, subject, pattern, false);
    if (ours != theirs && ++differ <= 10)
      ADD_FAILURE() << "'" << subject << "' ~ '" << pattern << "':\n  sandbox: " << ours << "\n  luajit:  " << theirs;
  }
  EXPECT_EQ(differ, 0);
  lua_close(jit);
}

// A script that overruns again and again is disabled once, by name, and the match plays on by
// the plain rules: a goal counts for the team that did not defend it.
TEST(Sandbox, AScriptThatKeepsOverrunningIsDisabled) {
  lua::ScriptedRules sport(hostile_sport("overrun", "",
                                 "sport.modifiers = { function() while true do end end }\n"
                                 "sport.on.goal = function(game, e) while true do end end"));
  const Finished f = play_out(sport);
  EXPECT_TRUE(sport.disabled());
  int disabled = 0;
  for (const std::string& e : f.errors) disabled += e.find("disabled") != std::string::npos;
  EXPECT_EQ(disabled, 1);
  EXPECT_EQ(f.errors.size(), size_t(lua::ScriptedRules::kOverrunsToDisable) + 1);
  EXPECT_GT(f.goals, 0);
  EXPECT_EQ(f.scored, f.goals);
  EXPECT_TRUE(f.finished);
}

// A team sport disabled by its own script goes on being played by the plain rules: the ball the
// engine drops after it went out is caught, thrown and passed, and goals count.
TEST(Sandbox, ADisabledTeamSportIsStillPlayed) {
  const fs::path dir = fs::temp_directory_path() / "quantum_hostile_handball";
  fs::remove_all(dir);
  fs::copy(QUANTUM_SOURCE_DIR "/rules/handball", dir, fs::copy_options::recursive);
  write_with_before_return(dir / "sport.lua", dir / "sport.lua", "sport.modifiers = { function() while true do end end }");
  lua::ScriptedRules sport(dir.string());
  const Finished f = play_out(sport, 60);
  EXPECT_TRUE(sport.disabled());
  EXPECT_TRUE(f.finished);
  EXPECT_GE(f.holds_after_disabled, 10) << "the ball lay where it dropped";
  EXPECT_EQ(f.scored, f.goals);
}

TEST(Sandbox, AnOverrunningPowerUpIsDisabledAndTheSportPlaysOn) {
  lua::ScriptedRules sport(hostile_sport("overrun_powerup", "game.grant(\"Red's mallet\", 'evil', { seconds = 60 })", "",
                                 "return { duration = 60, factor = function() while true do end end }\n"));
  const Finished f = play_out(sport);
  EXPECT_FALSE(sport.disabled());
  EXPECT_TRUE(sport.powerup_disabled("evil"));
  int disabled = 0;
  for (const std::string& e : f.errors) disabled += e.find("evil.lua: power-up evil disabled") != std::string::npos;
  EXPECT_EQ(disabled, 1);
  EXPECT_GT(f.goals, 0);
  EXPECT_EQ(f.scored, f.goals);
}

}  // namespace
}  // namespace quantum
