// A Lua state for designer scripts: text only, a memory cap, a budget of instructions and CPU
// time shared by all calls of a period (a match frame), and only the libraries a rule needs.
// Field files and sports both run in one. docs/lua-api.md, "The sandbox", states the limits.
//
// The scripts run on a thread of the sandbox's own, its lane; the thread that calls them waits.
// A count hook cannot stop a single instruction that runs long (a table whose keys were chosen to
// collide files them all again in one step): when one runs on past the budget, the watchdog
// abandons the sandbox and the caller goes on without it, as if the call had failed.
#pragma once

#include <lua.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "system/sanitizers.h"

namespace quantum::lua {

struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The address sanitizer runs the power-up specs' frames in 2.4 times the CPU (11.6 s against
// 4.8 s), with calls up to 27 ms of a 20 ms budget where the optimized build's longest took 2 ms:
// a sanitized build gives a frame four times the CPU, so what passes there also passes here.
// Instructions are counted, not timed, and stay the same.
inline constexpr double kCpuScale = system::kAddressSanitized ? 4 : 1;

// What the scripts of one sandbox may spend together in one period (new_period: a match frame).
// Instructions are counted by a count hook; CPU time (the calling thread's, so a busy machine does
// not count against a script) is watched by a watchdog thread whose flag the hook looks at every
// kHookEvery instructions. Library functions whose work a hook cannot see are bounded by
// lua_bounded.h.
struct Limits {
  size_t memory = 64u << 20;
  int64_t instructions = 10'000'000;
  double cpu_seconds = 0.02 * kCpuScale;
};

// How much CPU one stretch of Lua may run on once the budget is spent before the sandbox is
// abandoned: the hook raises the budget's error within a few milliseconds of the deadline, so
// only an instruction it cannot interrupt lasts this long. A frame's scripts thus hold it for
// 20 + 15 ms of CPU and the watchdog's look, a millisecond, up to ten on a loaded machine (seen
// with a second test process on the other core): under the 50 ms docs/lua-api.md states.
inline constexpr double kStuckAfter = 0.015 * kCpuScale;

class Sandbox {
 public:
  // Deletes a sandbox, except one that was abandoned: its lane may still be inside the one long
  // instruction, and afterwards parks for good, so it and its Lua state are kept until the
  // process ends (a few megabytes, once per stuck script).
  struct Release {
    void operator()(Sandbox* sandbox) const;
  };
  using Ptr = std::unique_ptr<Sandbox, Release>;

  // Of Lua's own libraries the scripts get the base functions, math (its random numbers each
  // script's own), string (its pattern functions bounded), table and os.clock: no io, the rest
  // of os, debug, package, ffi, jit, load, loadstring, dofile or collectgarbage. With `rules` (sports, not field files), `require` loads
  // the script's own Lua modules, as text, from `module_folders` only (see require_module).
  static Ptr make(Limits limits, bool rules, std::vector<std::filesystem::path> module_folders = {});
  // The name of every sandbox's thread (as `top -H` and a debugger show it).
  static constexpr const char* kLaneName = "quantum-lua";
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;

  // The sandbox was abandoned (see above): from then on nothing touches its Lua state, call()
  // fails and protect() throws at once, with stuck() as the error, and spent() stays true.
  bool abandoned() const;
  // "file:line: script stuck: ..." naming the function that was running (the one whose first line
  // it is), for the error of the call that was abandoned.
  const std::string& stuck() const { return stuck_; }

  lua_State* L() const { return L_; }
  // Pushes the template of the scripts' environments (to add a global of the caller's, like
  // `param`): every script file runs in a copy of it made when it loads.
  void push_environment() const;

  // Loads `file` as Lua text and runs it in an environment of its own (a copy of the template:
  // globals one script sets, no other sees); leaves its one result on the stack. `cache` (a stack
  // index, 0 for a new one) is the module cache its `require` uses: a module shares the cache of
  // the script that required it. Throws ScriptError "file:line: message" (or "file: message").
  void run_file(const std::string& file, int cache = 0);

  // lua_pcall with the period's budget armed; on failure returns the message and pops it. The
  // message always starts with the file and line that failed (errors raised with a table, or
  // with level 0, get the innermost script line). When the period's budget is spent the call
  // does not run: the function and arguments are popped and the error says so.
  bool call(int nargs, int nresults, std::string& error);

  // A script's call into the engine (guard<F>, lua_wrap.h), on the lane: checks the budget (its
  // error is raised here), then marks the lane as waiting for the engine, which the watchdog
  // never abandons, until leave_engine. Once the sandbox is abandoned the lane parks here and
  // never touches the engine again. Null, and nothing done, for a state that is no sandbox's.
  static Sandbox* enter_engine(lua_State* L);
  void leave_engine() { enter_lua(); }

  // Runs `body` (the engine reading and filling a script's tables) protected and under the
  // budget: a metamethod that errors or loops, or memory running out, becomes a ScriptError
  // instead of LuaJIT's panic. C++ exceptions thrown by `body` pass through unchanged. The stack
  // is restored to its height before.
  template <class Body>
  void protect(Body&& body) {
    struct Run {
      Body* body;
      std::exception_ptr thrown;
      static int trampoline(lua_State* L) {
        auto* run = static_cast<Run*>(lua_touserdata(L, 1));
        lua_pop(L, 1);
        try {
          (*run->body)();
        } catch (const std::exception&) {  // Lua's own errors are not std::exceptions: they unwind on
          run->thrown = std::current_exception();
        }
        return 0;
      }
    } run{&body, nullptr};
    protect_raw(&Run::trampoline, &run);
    if (run.thrown) std::rethrow_exception(run.thrown);
  }

  // Starts a new period: the budget is whole again.
  void new_period();
  // The instructions and CPU time of a period from now on (the memory limit is the state's).
  // longest_period_cpu() starts again: a sport's loading, with its second, is no frame.
  void set_budget(const Limits& limits);
  // The budget ran out this period (the rest of its calls are refused), or the sandbox was
  // abandoned.
  bool spent() const { return abandoned() || spent_ || time_up_.load(std::memory_order_relaxed); }
  // Where the budget ran out: the source file of the script running then ("" for none).
  const std::string& spent_in() const { return spent_in_; }
  // CPU seconds Lua used in this period, and in the longest period since the budget was set.
  double period_cpu() const { return period_cpu_; }
  double longest_period_cpu() const { return longest_period_cpu_; }
  const Limits& limits() const { return limits_; }

  // For bounded library functions: counts `work` instructions' worth of work done in C; raises
  // the budget error (a Lua error) when the budget is spent.
  void charge(lua_State* L, int64_t work);
  // charge(L, 1) for the sandbox `L` belongs to, nothing for a state that is no sandbox's (the
  // specs'). Every call of the game table, and every step of the engine's walks over a script's
  // tables, look at the budget: a step of lua_next walks a hash chain, which keys chosen to
  // collide make as long as the table, and a call may ask the engine for a whole prediction.
  static void check_budget(lua_State* L);
  // Library functions that call back into Lua (string.gsub with a function) count their nesting:
  // each C level takes C stack, which a recursion through them would exhaust.
  class Nested {
   public:
    Nested(lua_State* L, Sandbox& sandbox, const char* what);
    ~Nested() { --sandbox_.nesting_; }
    Nested(const Nested&) = delete;
    Nested& operator=(const Nested&) = delete;

   private:
    Sandbox& sandbox_;
  };
  static Sandbox& of(lua_State* L);
  // Where an error in a call names its place, "file:line: ": the innermost script line running,
  // or when none runs (a tail call left only C functions, as a __tostring that returns
  // string.format("%s", self) does) the first line of the function the engine called; "" when
  // that is no script's either (a value that is not a function).
  std::string script_place(lua_State* L) const;

  // Scripts' print: one line on stderr, "print: file:line: text", the text cut at kPrintedLine
  // bytes (`whole` is its length before the cut). At most kPrintedPerPeriod lines a period, then
  // one line that says the rest is not shown: a script printing every instruction must not
  // flood the terminal or cost the frame its writes.
  static constexpr size_t kPrintedLine = 1000;
  static constexpr int kPrintedPerPeriod = 20;
  void print_line(lua_State* L, std::string_view text, size_t whole);

  // require(name) for scripts: "util" or "lib.util" is util.lua or lib/util.lua in the first
  // module folder that has it, loaded once for the calling script's cache (as text, in the
  // sandbox) and its result kept there. `cache` is the stack index of that cache.
  // Pushes the result. Throws ScriptError for a bad name, a module that is not there (saying
  // that the sandbox looks only in its folders) or one that fails, and ReadError for a module
  // file that is not a regular file or leads out of the folders (confined_path).
  void require_module(const std::string& name, int cache);

  // Every Lua allocation, freeing and resizing so far: the tests' measure of the garbage a frame
  // makes.
  size_t allocations() const { return memory_.calls; }

  // Every file run so far (run_file, and the modules require loaded), in order.
  const std::vector<std::string>& files() const { return files_; }

  // The seed of the match the scripts play in, from which each script's random numbers start
  // (lua_random.h): a sport sets it for every call that has a match. None while files load
  // before one.
  void set_seed(uint64_t seed) { seed_ = seed; }
  const std::optional<uint64_t>& seed() const { return seed_; }

 private:
  friend class Watchdog;
  struct Lane;
  Sandbox(Limits limits, bool rules, std::vector<std::filesystem::path> module_folders);
  ~Sandbox();
  // Runs `job` on the lane (at once when this is the lane) and waits. False when the sandbox was
  // abandoned while it ran; an exception the job threw is thrown here.
  template <class Job>
  bool on_lane(Job& job) {
    return run_on_lane(+[](void* j) { (*static_cast<Job*>(j))(); }, &job);
  }
  bool run_on_lane(void (*job)(void*), void* arg);
  bool call_here(int nargs, int nresults, std::string& error);
  void protect_here(lua_CFunction trampoline, void* run);
  // The lane's state, one word the watchdog reads: what the lane does (kEngine, kLua, or
  // kAbandoned for good) and, above it, how many stretches of Lua it has begun, so that the
  // watchdog can tell one long stretch from many short ones.
  static constexpr uint64_t kEngine = 0, kLua = 1, kAbandoned = 2, kWhat = 3;
  void enter_lua();
  void leave_lua();  // parks once the sandbox is abandoned
  [[noreturn]] static void park();
  // The watchdog's: abandons the sandbox if the lane is still in the stretch of Lua `seen`.
  bool abandon(uint64_t seen, double call_cpu);
  std::string called_place() const;  // "file:line: " of the function the innermost call runs, or ""
  // Where the lane's calls in progress are, innermost last: a script function's file and first
  // line, or a file being loaded (line 0); no file for a C function. stuck() names the innermost.
  struct Where {
    const char* source;
    int line;
  };
  struct Memory {
    size_t used = 0, limit = 0, calls = 0;
    size_t large = 0;  // in blocks of kSmallAllocation or more: the longest string is no longer
  };
  static void* alloc(void* ud, void* ptr, size_t old_size, size_t new_size);
  static void on_hook(lua_State* L, lua_Debug* ar);
  [[noreturn]] void run_out(lua_State* L, lua_Debug* ar);
  void protect_raw(lua_CFunction trampoline, void* run);
  // Instructions between two hooks. One instruction may compare, scan or move a whole string
  // or table part in C (a < b, tonumber, table.insert at the front), work a count hook cannot
  // see: the more large blocks the state holds, the more often the hook looks (every
  // instruction with 32 MB of them), so that time between two looks stays a few milliseconds.
  int hook_period() const;
  void set_hook_period(int period);
  bool arm(std::string* refused);  // false (and why) when the period's budget is spent
  void disarm();
  void time_up();  // raises the flag, nothing more: the watchdog's call (from its thread), and the allocator's
  bool out_of_budget() const;  // the time is up or the instructions counted (the hook raises it next)
  // The period's CPU so far and the time to fault `bytes` in fit its budget (or it has no CPU
  // limit): the instruction that fills a block cannot be interrupted, so one that would end past
  // the budget is refused before it starts, never abandoned halfway.
  bool in_time_for(size_t bytes) const;
  // Pushes a copy of the template for script `file`, its module cache `cache` (0: a new one).
  void new_environment(int cache, const std::string& file);

  Limits limits_;
  bool rules_;  // scripts get `require`
  Memory memory_;
  lua_State* L_ = nullptr;
  int env_ = LUA_NOREF;
  int depth_ = 0;  // calls in progress (a handler's game.grant calls into the script again)
  int nesting_ = 0;
  static constexpr int kMostNested = 64;     // calls, or library callbacks, inside one another
  static constexpr size_t kSmallAllocation = 64 << 10;
  static constexpr int kHookEvery = 1000;  // instructions between two looks at the budget, at most
  static constexpr size_t kLargeBytesPerHook = 32u << 20;  // large blocks' bytes x hook period
  // A large block's new bytes cost an instruction each, as whole-string functions' bytes do: an
  // instruction takes 1 to 2 ns, faulting a fresh byte in up to 2.8 ns.
  static constexpr size_t kFaultedBytesPerInstruction = 1;
  // That count alone lets an 8 MB block through early in a frame, and its page faults (23 ms
  // alone, 35 with a second process busy on the other core) run past the budget by the stuck
  // window inside one instruction: so a block is also made only in time (in_time_for).
  static constexpr double kFaultSecondsPerByte = 2.8e-9;
  int hook_count_ = kHookEvery;
  int64_t instructions_ = 0;
  int printed_ = 0;  // print lines this period
  double period_cpu_ = 0, longest_period_cpu_ = 0;
  timespec armed_at_{};
  std::atomic<bool> time_up_{false};
  bool spent_ = false;
  std::string spent_in_;
  int on_error_ = LUA_NOREF;  // the message handler that puts the file and line on every error
  std::vector<std::filesystem::path> module_folders_;
  std::vector<std::string> files_;
  std::optional<uint64_t> seed_;
  std::atomic<uint64_t> lane_state_{kEngine};
  uint64_t stretches_ = 0;  // the lane's own count of stretches of Lua (lane_state_ >> 2)
  Where where_[kMostNested + 2] = {};
  int where_depth_ = 0;
  std::string stuck_;
  std::unique_ptr<Lane> lane_;  // last: its thread starts once the rest is whole
};

}  // namespace quantum::lua
