#include "lua_sandbox.h"

#include <linux/futex.h>
#include <luajit.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "confined_path.h"
#include "lua_bounded.h"
#include "lua_random.h"
#include "lua_wrap.h"
#include "system/regular_file.h"

namespace quantum::lua {
namespace {

// require's upvalue 4 is the module cache of the script whose environment holds it.
int require_module(lua_State* L) {
  const std::string name = check_string(L, 1);
  lua_pushvalue(L, lua_upvalueindex(4));
  upvalue_self<Sandbox>(L).require_module(name, lua_gettop(L));
  return 1;
}

// Lua's rawset, except on sealed tables (lua_wrap.h), which it would otherwise change behind
// their metatable's back.
int guarded_rawset(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  luaL_checkany(L, 2);
  luaL_checkany(L, 3);
  if (is_read_only(L, 1)) return luaL_error(L, "rawset: the table is read-only (the game table or a library)");
  lua_settop(L, 3);
  lua_rawset(L, 1);
  return 1;
}

double seconds(const timespec& t) { return double(t.tv_sec) + 1e-9 * double(t.tv_nsec); }

timespec thread_cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t;
}

// "rules/x/sport.lua:12: ": the source and line of a script frame, "" for a C function.
std::string where_of(lua_State* L, lua_Debug& ar, const char* what) {
  lua_getinfo(L, what, &ar);
  if (ar.currentline <= 0 && ar.linedefined <= 0) return {};
  const std::string file = ar.source && ar.source[0] == '@' ? ar.source + 1 : ar.short_src;
  return file + ":" + std::to_string(ar.currentline > 0 ? ar.currentline : ar.linedefined) + ": ";
}

// Frames these walks look at, from the innermost: LuaJIT finds a level by walking every frame above
// it, so a walk to the bottom of a deep recursion (a stack overflow's error) is quadratic, with
// no hook to stop it. An error names a line a few levels up at most, or below callbacks nested
// as deep as the sandbox allows (each a C frame, its Lua one gone when it ends in a tail call).
constexpr int kLevelsLooked = 256;

// The innermost script frame's "file:line: " (level 1 up), "" when no script runs (none called,
// or a tail call left only C functions: a __tostring that returns string.format("%s", self)).
std::string innermost_script_line(lua_State* L) {
  lua_Debug ar;
  for (int level = 1; level <= kLevelsLooked && lua_getstack(L, level, &ar); ++level)
    if (std::string w = where_of(L, ar, "Sl"); !w.empty() && ar.currentline > 0) return w;
  return {};
}

// Lua's own messages start "file:line: " with a line that runs now (error's level picks which);
// error("x", 0), error objects that are not strings and a message that names another file or
// line (a script blaming another) do not. LuaJIT names a file by its short_src, which cuts a
// long path at the front.
bool names_a_running_line(lua_State* L, const char* m) {
  const std::string_view message = m;
  lua_Debug ar;
  for (int level = 1; level <= kLevelsLooked && lua_getstack(L, level, &ar); ++level) {
    if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
    const std::string line = ':' + std::to_string(ar.currentline) + ":";
    if (message.starts_with(std::string(ar.short_src) + line)) return true;
    if (ar.source && ar.source[0] == '@' && message.starts_with(std::string(ar.source + 1) + line)) return true;
  }
  return false;
}

// The message handler of every call: the error as text, starting with the script line that
// raised it (Sandbox::script_place).
int on_error(lua_State* L) {
  const std::string where = Sandbox::of(L).script_place(L);
  if (lua_type(L, 1) == LUA_TSTRING || lua_type(L, 1) == LUA_TNUMBER) {
    const char* m = lua_tostring(L, 1);
    if (!names_a_running_line(L, m)) lua_pushstring(L, (where + m).c_str());
    else lua_pushvalue(L, 1);
    return 1;
  }
  lua_pushstring(L, (where + "error raised with a " + luaL_typename(L, 1) +
                     " as its message (the engine reports text: error(\"what went wrong\"))")
                        .c_str());
  return 1;
}

}  // namespace

// One thread for every sandbox of the process: while a call runs it looks at the lane's CPU
// clock every millisecond, and when the call's share of the period is used up it raises the
// sandbox's flag, which the count hook, the allocator and the bounded library functions look at.
// From then on it watches the lane's state: one stretch of Lua that goes on for kStuckAfter is
// inside an instruction the hook cannot interrupt, and it abandons the sandbox. It never calls
// into Lua: lua_sethook from another thread rewrites the hook mask while the Lua thread may be
// toggling its "in a hook" bit, and a stale bit turns every hook off for good. It keeps looking
// for a while after the last call, so a match's many short calls do not wake it each time.
class Watchdog {
 public:
  static Watchdog& get() {
    static Watchdog dog;
    return dog;
  }
  void watch(Sandbox* s, clockid_t clock, double armed_at, double deadline) {
    std::lock_guard lock(mutex_);
    watched_.push_back({s, clock, armed_at, deadline});
    if (idle_) wake_.notify_one();
  }
  // Once this returns, the watchdog does not touch `s`.
  void forget(Sandbox* s) {
    std::lock_guard lock(mutex_);
    std::erase_if(watched_, [&](const Entry& e) { return e.sandbox == s; });
  }

 private:
  struct Entry {
    Sandbox* sandbox;
    clockid_t clock;
    double armed_at, deadline;  // on the lane's CPU clock
    bool due = false;
    uint64_t seen = Sandbox::kEngine;  // the stretch of Lua last seen past the deadline...
    double seen_at = 0;                // ...and from when it counts
    double looked_at = 0;              // the previous look
  };
  // False once the entry is done with: the sandbox abandoned.
  static bool look(Entry& e) {
    timespec now{};
    if (clock_gettime(e.clock, &now) != 0) return true;
    const double t = seconds(now), previous = std::exchange(e.looked_at, t);
    if (!e.due) {
      if (t < e.deadline) return true;
      e.due = true;
      e.sandbox->time_up();
    }
    const uint64_t word = e.sandbox->lane_state_.load(std::memory_order_acquire);
    if ((word & Sandbox::kWhat) != Sandbox::kLua) {
      e.seen = Sandbox::kEngine;  // the engine's work is bounded by its own looks at the budget
      return true;
    }
    // A new stretch began after the previous look, or is the one the deadline found running: it
    // counts from then, not from this look, which a loaded machine may make late by ten
    // milliseconds of the lane's CPU. Never abandoned at the look that raised the flag: the hook
    // gets its chance first.
    if (word != e.seen) {
      e.seen = word, e.seen_at = std::max(previous, e.deadline);
      return true;
    }
    return !(t - e.seen_at >= kStuckAfter && e.sandbox->abandon(word, t - e.armed_at));
  }
  Watchdog() : thread_([this] { run(); }) {}
  ~Watchdog() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  void run() {
    using namespace std::chrono_literals;
    std::unique_lock lock(mutex_);
    auto last_seen = std::chrono::steady_clock::now();
    while (!stop_) {
      if (watched_.empty() && std::chrono::steady_clock::now() - last_seen > 200ms) {
        idle_ = true;
        wake_.wait(lock, [&] { return stop_ || !watched_.empty(); });
        idle_ = false;
      }
      for (size_t k = 0; k < watched_.size();)
        if (look(watched_[k])) ++k;
        else watched_.erase(watched_.begin() + std::ptrdiff_t(k));
      if (!watched_.empty()) last_seen = std::chrono::steady_clock::now();
      wake_.wait_for(lock, 1ms);
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Entry> watched_;
  bool idle_ = false, stop_ = false;
  std::thread thread_;
};

// The sandbox's thread: runs one job at a time for the thread that waits on it. A match calls its
// scripts a few times a frame, and waking a sleeping thread costs tens of microseconds on a
// virtual machine (50 us a round trip here), more than most calls: so each side keeps looking a
// little before it sleeps, the caller while the job runs, the lane for the frame's next call. It
// looks between yields of its core, not in a busy loop: when threads outnumber cores (studies
// that play matches side by side) a spinning thread would take the core its partner needs.
struct Sandbox::Lane {
  enum Turn : uint32_t { kIdle, kPosted, kDone, kAbandoned, kStop };
  static constexpr auto kCallerSpins = std::chrono::microseconds(500);
  static constexpr auto kLaneSpins = std::chrono::microseconds(100);
  static constexpr timespec kCallerNap{0, 2'000'000};
  std::atomic<uint32_t> turn{kIdle};
  void (*job)(void*) = nullptr;  // set before kPosted; the results after kDone
  void* arg = nullptr;
  std::exception_ptr thrown;
  double stuck_cpu = 0;  // set before kAbandoned: the abandoned call's CPU
  std::atomic<pid_t> tid{0};
  std::thread thread{[this] { loop(); }};

  // The turn once it is no longer `from`: spinning for `spin`, then asleep on the turn's futex,
  // for `nap` at most at a time when given. Not std::atomic::wait: libstdc++ 12 skips the wake
  // when its count of sleepers reads 0, and a caller once slept for good beside an idle lane (a
  // seeded soccer match in a test, hung 20 minutes). Here every change of turn wakes (set), and
  // the caller, who naps, wakes the lane again after each nap it finds the job still posted, so
  // a wake gone astray on either side costs a nap, not the match. The idle lane sleeps untimed:
  // a test holds hundreds of sandboxes, and lanes napping by the hundred took the cores.
  uint32_t wait_past(uint32_t from, std::chrono::microseconds spin, const timespec* nap = nullptr) const {
    const auto until = std::chrono::steady_clock::now() + spin;
    for (int k = 0;; ++k) {
      if (const uint32_t t = turn.load(std::memory_order_acquire); t != from) return t;
      if (k % 16 == 15 && std::chrono::steady_clock::now() > until) break;
      sched_yield();
    }
    for (bool napped = false;; napped = true) {
      if (const uint32_t t = turn.load(std::memory_order_acquire); t != from) return t;
      if (napped) wake();
      syscall(SYS_futex, futex(), FUTEX_WAIT_PRIVATE, from, nap, nullptr, 0);
    }
  }

  void set(uint32_t t) {
    turn.store(t, std::memory_order_seq_cst);
    wake();
  }

  void wake() const { syscall(SYS_futex, futex(), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0); }

  uint32_t* futex() const { return reinterpret_cast<uint32_t*>(const_cast<std::atomic<uint32_t>*>(&turn)); }
  static_assert(sizeof(std::atomic<uint32_t>) == sizeof(uint32_t) && std::atomic<uint32_t>::is_always_lock_free);

  void loop() {
    pthread_setname_np(pthread_self(), kLaneName);
    tid = gettid();
    for (uint32_t t = kIdle;;) {
      while (t != kPosted && t != kStop) t = wait_past(t, kLaneSpins);
      if (t == kStop) return;
      std::exception_ptr caught;
      try {
        job(arg);
      } catch (...) {
        caught = std::current_exception();
      }
      thrown = caught;
      set(t = kDone);
    }
  }
};

void* Sandbox::alloc(void* ud, void* ptr, size_t old_size, size_t new_size) {
  auto* s = static_cast<Sandbox*>(ud);
  Memory& memory = s->memory_;
  if (ptr == nullptr) old_size = 0;
  const size_t old_large = old_size >= kSmallAllocation ? old_size : 0;
  if (new_size == 0) {
    memory.used -= old_size;
    memory.large -= old_large;
    std::free(ptr);
    return nullptr;
  }
  if (new_size > old_size && memory.used + (new_size - old_size) > memory.limit) return nullptr;
  // A large block's growth is charged for its bytes before it is made: the instruction that fills
  // it (a concatenation, a table's rehash) pays the kernel to fault its fresh pages in, work no
  // hook sees (2.8 ms a megabyte on this project's virtual machines). Out of budget, or of time,
  // it fails, so a library function building something big (string.rep, table.concat) stops
  // there instead of finishing; a block whose faults would take it past the budget is the budget
  // spent. Its whole size counts: realloc may move it to fresh pages. Small ones go on: the error
  // message needs one.
  if (new_size > old_size + kSmallAllocation && s->depth_ > 0) {
    s->instructions_ += int64_t((new_size - old_size) / kFaultedBytesPerInstruction);
    if (!s->out_of_budget() && !s->in_time_for(new_size)) s->time_up();
    if (s->out_of_budget()) return nullptr;
  }
  ++memory.calls;
  void* p = std::realloc(ptr, new_size);
  if (!p) return nullptr;
  memory.used = memory.used + new_size - old_size;
  memory.large = memory.large - old_large + (new_size >= kSmallAllocation ? new_size : 0);
  // A script that just built a large string may compare it next: look more often from now on,
  // not from the next look. (lua_sethook is safe here: this is the thread running the script.)
  if (s->depth_ > 0 && new_size >= kSmallAllocation)
    if (const int period = s->hook_period(); period < s->hook_count_) s->set_hook_period(period);
  return p;
}

Sandbox& Sandbox::of(lua_State* L) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  return *static_cast<Sandbox*>(ud);
}

void Sandbox::on_hook(lua_State* L, lua_Debug* ar) {
  Sandbox& s = of(L);
  s.instructions_ += s.hook_count_;
  if (s.out_of_budget()) s.run_out(L, ar);
  if (const int period = s.hook_period(); period != s.hook_count_) s.set_hook_period(period);
}

int Sandbox::hook_period() const {
  if (spent_) return 1;
  const size_t period = kLargeBytesPerHook / std::max<size_t>(memory_.large, 1);
  return int(std::clamp<size_t>(period, 1, kHookEvery));
}

void Sandbox::set_hook_period(int period) {
  hook_count_ = period;
  lua_sethook(L_, on_hook, LUA_MASKCOUNT, period);
}

void Sandbox::charge(lua_State* L, int64_t work) {
  instructions_ += work;
  if (out_of_budget()) run_out(L, nullptr);
}

void Sandbox::check_budget(lua_State* L) {
  void* ud = nullptr;
  if (lua_getallocf(L, &ud) == &Sandbox::alloc) static_cast<Sandbox*>(ud)->charge(L, 1);
}

void Sandbox::run_out(lua_State* L, lua_Debug* ar) {
  spent_ = true;
  // From now on every instruction raises this again: a script that catches it with pcall cannot
  // go on, and neither can an error handler.
  set_hook_period(1);
  std::string where = ar ? where_of(L, *ar, "Sl") : script_place(L);
  if (spent_in_.empty()) spent_in_ = where.substr(0, where.find(':'));
  char message[160];
  std::snprintf(message, sizeof message,
                "script runs too long: the Lua budget of a frame (%.0f ms of CPU, %lld million instructions) is spent",
                limits_.cpu_seconds * 1e3, static_cast<long long>(limits_.instructions / 1'000'000));
  where += message;
  lua_pushstring(L, where.c_str());
  lua_error(L);
  std::abort();  // lua_error does not return
}

void Sandbox::time_up() { time_up_.store(true, std::memory_order_relaxed); }

bool Sandbox::out_of_budget() const {
  return time_up_.load(std::memory_order_relaxed) || instructions_ >= limits_.instructions;
}

bool Sandbox::in_time_for(size_t bytes) const {
  if (limits_.cpu_seconds <= 0) return true;
  const double spent = period_cpu_ + seconds(thread_cpu_now()) - seconds(armed_at_);
  return spent + double(bytes) * kFaultSecondsPerByte < limits_.cpu_seconds;
}

bool Sandbox::abandoned() const { return lane_state_.load(std::memory_order_acquire) == kAbandoned; }

void Sandbox::enter_lua() {
  uint64_t engine = stretches_ << 2 | kEngine;
  ++stretches_;
  if (!lane_state_.compare_exchange_strong(engine, stretches_ << 2 | kLua, std::memory_order_acq_rel)) park();
}

void Sandbox::leave_lua() {
  uint64_t lua = stretches_ << 2 | kLua;
  if (!lane_state_.compare_exchange_strong(lua, stretches_ << 2 | kEngine, std::memory_order_acq_rel)) park();
}

// The lane of an abandoned sandbox, back from its long instruction, would next touch the engine,
// which has gone on without it: it stops here, for good, holding nothing.
void Sandbox::park() {
  for (;;) std::this_thread::sleep_for(std::chrono::hours(24));
}

Sandbox* Sandbox::enter_engine(lua_State* L) {
  void* ud = nullptr;
  if (lua_getallocf(L, &ud) != &Sandbox::alloc) return nullptr;
  auto* s = static_cast<Sandbox*>(ud);
  s->charge(L, 1);
  s->leave_lua();
  return s;
}

bool Sandbox::abandon(uint64_t seen, double call_cpu) {
  if (!lane_state_.compare_exchange_strong(seen, kAbandoned, std::memory_order_acq_rel)) return false;
  setpriority(PRIO_PROCESS, id_t(lane_->tid.load()), 19);  // it may run on for minutes: the match comes first
  lane_->stuck_cpu = call_cpu;
  lane_->set(Lane::kAbandoned);
  return true;
}

bool Sandbox::run_on_lane(void (*job)(void*), void* arg) {
  if (std::this_thread::get_id() == lane_->thread.get_id()) {
    job(arg);
    return true;
  }
  if (abandoned()) return false;
  lane_->job = job;
  lane_->arg = arg;
  lane_->set(Lane::kPosted);
  if (lane_->wait_past(Lane::kPosted, Lane::kCallerSpins, &Lane::kCallerNap) == Lane::kDone) {
    if (lane_->thrown) std::rethrow_exception(std::exchange(lane_->thrown, nullptr));
    return true;
  }
  const double cpu = lane_->stuck_cpu;
  longest_period_cpu_ = std::max(longest_period_cpu_, period_cpu_ + cpu);
  const Where& w = where_[std::clamp(where_depth_ - 1, 0, int(std::size(where_)) - 1)];
  char text[400];
  std::snprintf(text, sizeof text,
                "script stuck: one step of Lua %s ran on past the budget (%.0f ms of CPU, of %.0f ms) inside a "
                "single instruction no hook can stop, such as filing again a table's keys chosen to collide; its "
                "Lua state is abandoned",
                w.line > 0 ? "in the function starting here" : "here", cpu * 1e3, limits_.cpu_seconds * 1e3);
  stuck_ = called_place() + text;
  return false;
}

void Sandbox::new_period() {
  if (abandoned()) return;
  instructions_ = 0;
  printed_ = 0;
  period_cpu_ = 0;
  time_up_ = false;
  spent_ = false;
  spent_in_.clear();
}

void Sandbox::print_line(lua_State* L, std::string_view text, size_t whole) {
  if (++printed_ > kPrintedPerPeriod) {
    if (printed_ == kPrintedPerPeriod + 1)
      std::fprintf(stderr, "print: more than %d lines in one frame: the rest of this frame's are not shown\n",
                   kPrintedPerPeriod);
    return;
  }
  std::string line = "print: " + script_place(L);
  line.append(text);  // as written, NUL bytes too
  if (whole > text.size()) line += "... (" + std::to_string(whole) + " bytes in all)";
  line += '\n';
  std::fwrite(line.data(), 1, line.size(), stderr);
}

bool Sandbox::arm(std::string* refused) {
  if (spent_ || time_up_) {
    if (refused) {
      // A call from inside a running script is refused at that script's line: the watchdog may
      // have spent the budget between two looks of the hook, before any script error named the place.
      std::string where = depth_ > 0 ? script_place(L_) : std::string();
      if (where.empty() && !spent_in_.empty()) where = spent_in_ + ": ";
      *refused = where + "script runs too long: this frame's Lua budget is spent (call skipped)";
    }
    return false;
  }
  if (depth_ >= kMostNested) {  // handlers that call each other (on.give throws, on.throw gives)
    if (refused)
      *refused = script_place(L_) + "calls into the scripts nested more than " + std::to_string(kMostNested) + " deep";
    return false;
  }
  if (depth_++ > 0) return true;  // a call made from inside another spends the outer one's budget
  set_hook_period(hook_period());
  armed_at_ = thread_cpu_now();
  clockid_t cpu_clock{};
  if (limits_.cpu_seconds > 0 && pthread_getcpuclockid(pthread_self(), &cpu_clock) == 0)
    Watchdog::get().watch(this, cpu_clock, seconds(armed_at_), seconds(armed_at_) + (limits_.cpu_seconds - period_cpu_));
  return true;
}

void Sandbox::disarm() {
  if (--depth_ > 0) return;
  if (limits_.cpu_seconds > 0) Watchdog::get().forget(this);
  lua_sethook(L_, nullptr, 0, 0);
  period_cpu_ += seconds(thread_cpu_now()) - seconds(armed_at_);
  longest_period_cpu_ = std::max(longest_period_cpu_, period_cpu_);
  if (out_of_budget() || (limits_.cpu_seconds > 0 && period_cpu_ >= limits_.cpu_seconds)) spent_ = true;
}

std::string Sandbox::called_place() const {
  const Where& w = where_[std::clamp(where_depth_ - 1, 0, int(std::size(where_)) - 1)];
  if (where_depth_ == 0 || !w.source) return {};
  return w.source + (w.line > 0 ? ':' + std::to_string(w.line) : std::string()) + ": ";
}

std::string Sandbox::script_place(lua_State* L) const {
  std::string where = innermost_script_line(L);
  return where.empty() ? called_place() : where;
}

Sandbox::Nested::Nested(lua_State* L, Sandbox& sandbox, const char* what) : sandbox_(sandbox) {
  if (sandbox.nesting_ >= kMostNested) luaL_error(L, "%s: callbacks nested more than %d deep", what, kMostNested);
  ++sandbox.nesting_;
}

Sandbox::Sandbox(Limits limits, bool rules, std::vector<std::filesystem::path> module_folders)
    : limits_(limits), rules_(rules), module_folders_(std::move(module_folders)) {
  Watchdog::get();  // made before any sandbox is whole, so it outlives even a static one
  memory_.limit = limits.memory;
  L_ = lua_newstate(alloc, this);
  if (!L_) throw std::runtime_error("cannot create a Lua state (this LuaJIT build does not take an allocator)");
  luaL_openlibs(L_);
  install_bounded(L_);
  // Count hooks do not fire inside compiled traces, so the budget needs the interpreter. Rules
  // run a few times a second; the JIT would not pay for itself. (After openlibs: opening the
  // jit library switches it back on.)
  luaJIT_setmode(L_, 0, LUAJIT_MODE_ENGINE | LUAJIT_MODE_OFF);
  // Scripts sharing this state (a sport, its modules and power-ups) must not change what the
  // others run: the libraries are sealed (lua_wrap.h), the string metatable protected, and each
  // script file runs in an environment of its own, a copy of this template (new_environment)
  // with a math library of its own (its random numbers, lua_random.h).
  lua_pushstring(L_, "");
  lua_getmetatable(L_, -1);
  lua_pushstring(L_, "read-only");
  lua_setfield(L_, -2, "__metatable");
  lua_pop(L_, 2);
  lua_newtable(L_);
  const int env = lua_gettop(L_);
  const char* base[] = {"assert", "error",    "ipairs", "next",   "pairs",  "pcall",  "select", "tonumber",
                        "tostring", "type", "unpack", "rawequal", "rawget", "setmetatable",
                        "getmetatable", "xpcall", "print"};
  for (const char* name : base) {
    lua_getglobal(L_, name);
    lua_setfield(L_, env, name);
  }
  lua_pushcfunction(L_, guarded_rawset);
  lua_setfield(L_, env, "rawset");
  for (const char* name : {"string", "table"}) {
    lua_newtable(L_);
    lua_getglobal(L_, name);
    seal(L_, -2, -1, name);
    lua_pop(L_, 1);
    lua_setfield(L_, env, name);
  }
  // Of os, only its clock: a rule may time itself, never touch the machine.
  lua_newtable(L_);
  lua_newtable(L_);
  lua_getglobal(L_, "os");
  lua_getfield(L_, -1, "clock");
  lua_setfield(L_, -3, "clock");
  lua_pop(L_, 1);
  seal(L_, -2, -1, "os");
  lua_pop(L_, 1);
  lua_setfield(L_, env, "os");
  env_ = luaL_ref(L_, LUA_REGISTRYINDEX);
  lua_pushcfunction(L_, on_error);
  on_error_ = luaL_ref(L_, LUA_REGISTRYINDEX);
  lane_ = std::make_unique<Lane>();
}

Sandbox::Ptr Sandbox::make(Limits limits, bool rules, std::vector<std::filesystem::path> module_folders) {
  return Ptr(new Sandbox(limits, rules, std::move(module_folders)));
}

void Sandbox::Release::operator()(Sandbox* sandbox) const {
  if (!sandbox->abandoned()) {
    delete sandbox;
    return;
  }
  static std::mutex mutex;
  static auto* kept = new std::vector<Sandbox*>;  // never freed: the leak checker sees them kept
  std::lock_guard lock(mutex);
  kept->push_back(sandbox);
}

void Sandbox::set_budget(const Limits& limits) {
  if (abandoned()) return;
  limits_.instructions = limits.instructions;
  limits_.cpu_seconds = limits.cpu_seconds;
  longest_period_cpu_ = 0;
}

void Sandbox::require_module(const std::string& name, int cache) {
  namespace fs = std::filesystem;
  bool valid = !name.empty() && name.front() != '.' && name.back() != '.' && name.find("..") == std::string::npos;
  for (char c : name) valid &= (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.';
  if (!valid)
    throw ScriptError("'" + name + "' is not a module name: lower-case words joined by dots, e.g. 'util' or 'lib.util'");
  lua_getfield(L_, cache, name.c_str());
  if (!lua_isnil(L_, -1)) return;
  lua_pop(L_, 1);
  std::string relative = name;
  std::replace(relative.begin(), relative.end(), '.', '/');
  relative += ".lua";
  std::string looked;
  if (const fs::path file = confined_path(module_folders_, relative, "'" + name + "'", looked); !file.empty()) {
    run_file(file.string(), cache);
    if (lua_isnil(L_, -1)) {  // a module that returns nothing is loaded all the same
      lua_pop(L_, 1);
      lua_pushboolean(L_, 1);
    }
    lua_pushvalue(L_, -1);
    lua_setfield(L_, cache, name.c_str());
    return;
  }
  throw ScriptError("no module '" + name + "': the sandbox loads only the sport's own Lua modules (" +
                    (looked.empty() ? std::string("no folders") : looked) +
                    "); Lua's own libraries beyond math, string, table and os.clock, and native modules, are "
                    "not available to rules");
}

void Sandbox::new_environment(int cache, const std::string& file) {
  const int top = lua_gettop(L_);
  lua_newtable(L_);
  const int env = top + 1;
  lua_rawgeti(L_, LUA_REGISTRYINDEX, env_);
  for (lua_pushnil(L_); lua_next(L_, env + 1);) {
    lua_pushvalue(L_, -2);
    lua_insert(L_, -2);
    lua_rawset(L_, env);
  }
  lua_pop(L_, 1);
  lua_pushvalue(L_, env);
  lua_setfield(L_, env, "_G");
  // A module's random numbers are named after the script whose copy it is too (its cache's [1],
  // which no module name is): each copy draws its own.
  std::string name = stream_name(file);
  if (cache != 0) {
    lua_rawgeti(L_, cache, 1);
    name = lua_tostring(L_, -1) + (" " + name);
    lua_pop(L_, 1);
  }
  set_own_math(L_, env, name);
  if (!rules_) return;
  // Each script's own `require` and module cache: a power-up's `require "two_teams"` is its own
  // copy, so what it does to the module's table the sport never sees. A module shares the cache
  // of the script that required it. (Upvalues as push_module's, then the cache.)
  lua_pushstring(L_, "require");
  lua_newtable(L_);
  lua_pushlightuserdata(L_, this);
  if (cache != 0) {
    lua_pushvalue(L_, cache);
  } else {
    lua_newtable(L_);
    lua_pushstring(L_, name.c_str());
    lua_rawseti(L_, -2, 1);
  }
  lua_pushcclosure(L_, guard<lua::require_module>, 4);
  lua_setfield(L_, env, "require");
}

Sandbox::~Sandbox() {
  lane_->set(Lane::kStop);
  lane_->thread.join();
  Watchdog::get().forget(this);
  lua_close(L_);
}

void Sandbox::push_environment() const { lua_rawgeti(L_, LUA_REGISTRYINDEX, env_); }

bool Sandbox::call(int nargs, int nresults, std::string& error) {
  bool ok = false;
  auto job = [&] { ok = call_here(nargs, nresults, error); };
  if (!on_lane(job)) error = stuck_;
  return ok;
}

bool Sandbox::call_here(int nargs, int nresults, std::string& error) {
  const int function = lua_gettop(L_) - nargs;
  if (!arm(&error)) {
    lua_settop(L_, function - 1);
    return false;
  }
  // The handler below the function; the function's own place kept for a memory error's message,
  // which Lua raises without running the handler.
  lua_rawgeti(L_, LUA_REGISTRYINDEX, on_error_);
  lua_insert(L_, function);
  lua_pushvalue(L_, function + 1);
  lua_insert(L_, function);
  lua_Debug called{};
  lua_pushvalue(L_, function);
  lua_getinfo(L_, ">S", &called);
  const bool script = called.source && called.source[0] == '@';
  where_[std::min(where_depth_++, int(std::size(where_)) - 1)] = {script ? called.source + 1 : nullptr, called.linedefined};
  enter_lua();
  const int status = lua_pcall(L_, nargs, nresults, function + 1);
  leave_lua();
  --where_depth_;
  disarm();
  if (status == 0) {
    lua_remove(L_, function);
    lua_remove(L_, function);
    return true;
  }
  const char* m = lua_tostring(L_, -1);
  error = m ? m : "error";
  if (status == LUA_ERRMEM) {  // raised without the handler: the called function is the place
    lua_Debug ar;
    lua_pushvalue(L_, function);
    lua_getinfo(L_, ">S", &ar);
    const std::string where =
        ar.linedefined > 0 && ar.source[0] == '@' ? std::string(ar.source + 1) + ":" + std::to_string(ar.linedefined) + ": " : "";
    if (out_of_budget() && spent_in_.empty() && ar.source[0] == '@') spent_in_ = ar.source + 1;  // whose overrun it was
    error = where + (out_of_budget() ? "script runs too long: the Lua budget of a frame is spent" : "not enough memory") +
            (where.empty() ? "" : " (in the function starting there)");
  }
  lua_settop(L_, function - 1);
  return false;
}

void Sandbox::protect_raw(lua_CFunction trampoline, void* run) {
  auto job = [&] { protect_here(trampoline, run); };
  if (!on_lane(job)) throw ScriptError(stuck_);
}

void Sandbox::protect_here(lua_CFunction trampoline, void* run) {
  const int top = lua_gettop(L_);
  std::string refused;
  if (!arm(&refused)) throw ScriptError(refused);
  const int status = lua_cpcall(L_, trampoline, run);
  disarm();
  if (status != 0) {
    std::string m = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "error";
    if (status == LUA_ERRMEM && out_of_budget()) m = "script runs too long: the Lua budget of a frame is spent";
    lua_settop(L_, top);
    throw ScriptError(m);
  }
  lua_settop(L_, top);
}

void Sandbox::run_file(const std::string& file, int cache) {
  // sport.lua and a field given on the command line are named by no script, but a FIFO there
  // would block the load (or a reload in the middle of a match) all the same.
  if (const std::string why = system::not_a_regular_file(file); !why.empty()) throw ScriptError(why);
  if (!std::filesystem::exists(file)) throw ScriptError(file + ": no such file");
  files_.push_back(file);
  // The parser files a chunk's constants in a table too: keys chosen to collide stall it as well.
  where_[std::min(where_depth_++, int(std::size(where_)) - 1)] = {files_.back().c_str(), 0};
  enter_lua();
  const int status = luaL_loadfilex(L_, file.c_str(), "t");
  leave_lua();
  --where_depth_;
  if (status != 0) {
    std::string m = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "not enough memory";
    lua_pop(L_, 1);
    if (m.find("wrong mode") != std::string::npos)
      m = file + ": binary chunk (precompiled bytecode) refused: scripts must be Lua text";
    throw ScriptError(m.rfind(file, 0) == 0 ? m : file + ": " + m);
  }
  new_environment(cache, file);
  lua_setfenv(L_, -2);
  std::string error;
  if (!call(0, 1, error)) throw ScriptError(error.rfind(file, 0) == 0 ? error : file + ": " + error);
}

}  // namespace quantum::lua
