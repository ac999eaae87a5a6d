// A running match allocates nothing per frame: step, decisions, prediction, tweak, the Lua rules,
// the simulated players, the event log, the transcript and the sound all work in memory made
// before. Every malloc of this process goes through the hook below, so nothing escapes the count
// (C++'s operator new, OpenAL, libsndfile and LuaJIT's allocator all come here). Lua's own
// allocations are counted apart: the rules' garbage is kept small, not zero.
//
// Set QUANTUM_ALLOCATION_TRACE=1 to print a stack for every allocation counted against a frame.
#include <gtest/gtest.h>

#include <execinfo.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <utility>
#include <sstream>

#include "lua_sandbox.h"
#include "session.h"
#include "system/sanitizers.h"
#include "lua_sport.h"

namespace {

thread_local bool counting = false;  // the frame's thread
std::atomic<bool> lanes_counting{false};  // the sandboxes' lanes, which run the frame's Lua
std::atomic<size_t> allocations{0};
bool tracing = false;  // the measurement that the test judges

bool on_a_lane() {
  thread_local const bool lane = [] {
    char name[16] = {};
    pthread_getname_np(pthread_self(), name, sizeof name);
    return std::string_view(name) == quantum::lua::Sandbox::kLaneName;
  }();
  return lane;
}

void count() {
  if (!counting && !(lanes_counting && on_a_lane())) return;
  ++allocations;
  static const bool trace = std::getenv("QUANTUM_ALLOCATION_TRACE") != nullptr;
  if (!trace || !tracing) return;
  const bool was = std::exchange(counting, false);
  const bool lanes = lanes_counting.exchange(false);
  void* frames[32];
  const int n = backtrace(frames, 32);
  backtrace_symbols_fd(frames, n, STDERR_FILENO);
  write(STDERR_FILENO, "--\n", 3);
  counting = was;
  lanes_counting = lanes;
}

}  // namespace

#if QUANTUM_ADDRESS_SANITIZED
// The address sanitizer owns malloc; it calls these hooks for every allocation instead.
#include <sanitizer/allocator_interface.h>

namespace {
void on_malloc(const volatile void*, size_t) { count(); }
void on_free(const volatile void*) {}
[[maybe_unused]] const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}  // namespace
#else
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);

void* malloc(size_t n) {
  count();
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t size) {
  count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t n) {
  count();
  return __libc_realloc(p, n);
}
void* memalign(size_t alignment, size_t n) {
  count();
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(size_t alignment, size_t n) {
  count();
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, size_t alignment, size_t n) {
  count();
  *out = __libc_memalign(alignment, n);
  return *out ? 0 : ENOMEM;
}
}
#endif

namespace quantum {
namespace {

namespace fs = std::filesystem;

constexpr int kWarmUp = 1200;  // 20 s of play: every buffer has met a busy moment
constexpr int kMeasured = 600;  // 10 s

struct Measured {
  size_t cxx = 0, lua = 0;           // allocations over the measured frames
  size_t first_heard_frames = 0;     // frames that played a sound or phrase for the first time
  size_t worst_first_heard = 0;      // the most allocations of one such frame, per thing heard first in it
  size_t frames_with_events = 0;
};

// A match of a sport (air hockey unless told) between simulated players at `particles`, with its
// sound rendered to a WAV file, its events logged and its transcript written, as `quantum play`
// runs it.
Measured measure(uint32_t particles, const std::string& audio, const std::string& powerup = "",
                 const std::string& sport = "airhockey") {
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/" + sport;
  o.seconds = 600;
  o.particles = particles;
  o.seed = 5;
  o.audio = audio;
  o.events = (fs::temp_directory_path() / "quantum_allocation_events.jsonl").string();
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  std::ofstream transcript(fs::temp_directory_path() / "quantum_allocation_transcript.txt");
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, &transcript, errors);
  // A phrase or sound heard for the first time is synthesized or loaded and handed to OpenAL
  // once: that frame may allocate. Every other frame must not.
  std::set<std::string> heard;
  size_t first_heard = 0;  // things heard for the first time this frame
  bool any_event = false;
  session.watch([&](const runtime::News& news) {
    const bool was_counting = std::exchange(counting, false);
    for (const game::GameEvent& e : news.events) first_heard += heard.insert(game::to_string(e.type)).second;
    for (const game::Said& s : news.said) first_heard += heard.insert(s.text).second;
    any_event |= !news.events.empty();
    counting = was_counting;
  });
  // A power-up's factor runs for every fate of every frame, with the fate, its holder and its
  // numbers as tables: the engine's own, refilled in place.
  if (!powerup.empty()) tools::scripted_rules(session).grant(session.match(), 1, powerup, {{"seconds", 600}});
  for (int f = 0; f < kWarmUp; ++f) session.frame();
  Measured m;
  for (int f = 0; f < kMeasured; ++f) {
    first_heard = 0;
    any_event = false;
    const size_t lua_before = tools::scripted_rules(session).sandbox().allocations();
    allocations = 0;
    counting = lanes_counting = true;
    session.frame();
    counting = lanes_counting = false;
    const size_t lua = tools::scripted_rules(session).sandbox().allocations() - lua_before;
    const size_t cxx = allocations - lua;
    m.lua += lua;
    m.frames_with_events += any_event;
    if (first_heard) {
      ++m.first_heard_frames;
      m.worst_first_heard = std::max(m.worst_first_heard, (cxx + first_heard - 1) / first_heard);
    } else {
      m.cxx += cxx;
    }
  }
  EXPECT_EQ(errors.str(), "");
  EXPECT_FALSE(session.over());
  return m;
}

TEST(Allocations, ARunningMatchAllocatesNothingPerFrame) {
  // Once through first, so every phrase of this seeded match is synthesized (espeak-ng's cache
  // is the process's), as it is in any match once its phrases have been heard.
  measure(1000, "wav:" + (fs::temp_directory_path() / "quantum_allocation_warm.wav").string());
  tracing = true;
  const Measured m = measure(1000, "wav:" + (fs::temp_directory_path() / "quantum_allocation.wav").string());
  std::cout << "frames with events " << m.frames_with_events << ", C++ allocations " << m.cxx
            << ", frames hearing something new " << m.first_heard_frames << " (at most " << m.worst_first_heard
            << " allocations per new clip), Lua allocations " << m.lua << " (" << double(m.lua) / kMeasured << " a frame)\n";
  EXPECT_GT(m.frames_with_events, 20u);  // a match in full flow, not an empty field
  EXPECT_EQ(m.cxx, 0u);
  // A clip played for the first time: its OpenAL buffer and a map node in the mixer (a frame can
  // hear two things first: a goal's horn and its call).
  EXPECT_LE(m.worst_first_heard, 4u);
  // The rules' garbage: a table per event told to a handler, and the strings it builds.
  EXPECT_LT(double(m.lua) / kMeasured, 5.0);
}

TEST(Allocations, APowerUpsFactorMakesNoGarbagePerFate) {
  const Measured m = measure(1000, "none", "slow_motion");
  std::cout << "Lua allocations " << m.lua << " (" << double(m.lua) / kMeasured << " a frame)\n";
  EXPECT_EQ(m.cxx, 0u);
  EXPECT_LT(double(m.lua) / kMeasured, 5.0);
}

// Handball: simulated players who run, pass and mark, the ball held, thrown and caught, and
// rules that read the players every frame.
TEST(Allocations, AHandballMatchAllocatesNothingPerFrame) {
  measure(1000, "none", "", "handball");  // every phrase of the match heard once
  tracing = true;
  const Measured m = measure(1000, "none", "", "handball");
  std::cout << "frames with events " << m.frames_with_events << ", C++ allocations " << m.cxx
            << ", Lua allocations " << m.lua << " (" << double(m.lua) / kMeasured << " a frame)\n";
  EXPECT_GT(m.frames_with_events, 5u);  // a catch, a pass or a throw every second or two
  EXPECT_EQ(m.cxx, 0u);
  // The rules' garbage: handball's modifier reads game.players() once a frame (a table for each
  // of the six players and the list, about 8 allocations), and a table per event.
  EXPECT_LT(double(m.lua) / kMeasured, 12.0);
}

// Twenty times the particles, and no sound: the core's buffers are sized by the cloud, not by
// what a frame happens to meet.
TEST(Allocations, ALargerCloudAllocatesNothingEither) {
  tracing = true;
  const Measured m = measure(20'000, "none");
  EXPECT_GT(m.frames_with_events, 20u);
  EXPECT_EQ(m.cxx, 0u);
}

}  // namespace
}  // namespace quantum
