// Speed of the quantum core on the air hockey table with two scripted mallets, single thread.
// Run: build/quantum-bench   (figures and how to read them: docs/PERFORMANCE.md)
#include <benchmark/benchmark.h>
#include <lua.hpp>
#include <luajit.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include "audio/audio.h"
#include "box2d_backend.h"
#include "field_loader.h"
#include "session.h"
#include "scripted_rules.h"
#include "lua_sandbox.h"
#include "picture.h"
#include "quantum/noise.h"
#include "quantum/world.h"
#include "scenes.h"
#include "synthetic.h"
#include "tracking/tracking.h"
#include "lua_sport.h"

namespace {

using namespace quantum;

const Field& airhockey() {
  static const Field field = lua::load_field("airhockey");
  return field;
}

// Steps a spread cloud with moving mallets, decisions included: a realized hit collapses the
// cloud to the mallet's purgatory and splits it back to N, as in play. A ball that ends in a goal
// is spread again outside the timed region.
void step_scene(benchmark::State& state, bool box2d, bool brownian = true, bool audible_walls = true) {
  Field field = airhockey();
  if (!brownian) field.brownian = 0;
  if (!audible_walls) field.audible_bounce = 1000;
  const uint32_t n = uint32_t(state.range(0));
  WorldConfig config;
  config.particles = n;
  World world(field, config, box2d ? make_box2d_backend(field) : nullptr);
  world.set_cloud(tools::spread_cloud(field, n, 7));
  std::vector<Event> events;
  const float dt = 1.0f / 60;
  int64_t particle_steps = 0, realized = 0;
  for (auto _ : state) {
    realized += int64_t(events.size());
    events.clear();
    particle_steps += int64_t(world.cloud().size());
    world.step(dt, tools::scripted_mallets(field, world.time() + dt), events);
    if (!world.live()) {
      state.PauseTiming();
      world.set_cloud(tools::spread_cloud(field, n, world.steps()));
      state.ResumeTiming();
    }
  }
  state.counters["particle_steps/s"] = benchmark::Counter(double(particle_steps), benchmark::Counter::kIsRate);
  // How often a decision realized an outcome (each one collapses and re-splits the cloud).
  state.counters["events/step"] = benchmark::Counter(double(realized), benchmark::Counter::kAvgIterations);
}

void BM_Step(benchmark::State& state) { step_scene(state, false); }
// The same scene with every wall bounce silent: in this cloud, spread over the table in every
// direction, about 3 % of the particles meet a wall each step, and each is a decision.
void BM_StepSilentWalls(benchmark::State& state) { step_scene(state, false, true, false); }
void BM_Box2DStep(benchmark::State& state) { step_scene(state, true); }
// Box2D's best case: without Brownian motion no particle is teleported, so its broadphase only
// re-pairs the bodies that left their fattened boxes. The speed ratio is taken against this.
void BM_Box2DStepQuiet(benchmark::State& state) { step_scene(state, true, false); }

// Fields with height: a jump shot from 6 m on the basketball half court, with a person's scatter,
// six players standing (two under the basket). Each step moves the whole arc-flying cloud; near
// the ring, the board and the floor particles take the exact search, and the rim, the board, the
// floor and the players draw decisions as in play. A shot that ended is thrown again untimed.
struct Shot {
  Field field = lua::load_field("basketball");
  std::vector<BodyInput> players;
  Shot() {
    for (size_t k = 0; k < field.bodies.size(); ++k) players.push_back({field.bodies[k].start, {0, 0}});
    players[0].position = {-4, 5.6f};                                   // the shooter
    players[1].position = {1.2f, 2.3f}, players[3].position = {-1.2f, 2.4f};  // under the basket
  }
  // A world on this court with the players placed, for clouds of n particles.
  std::unique_ptr<World> world(uint32_t n) const {
    WorldConfig config;
    config.particles = n;
    auto w = std::make_unique<World>(field, config);
    w->place_bodies(players);
    return w;
  }
  void shoot(World& world) const {
    std::vector<Event> events;
    world.give(0);
    const Goal& ring = field.goals[0];
    const Vec2 arm = field.release_point(0, players[0].position, ring.a);
    const Vec3 hand{arm.x, arm.y, world.reach(0)};
    world.release(0, field.arc_velocity(hand, {ring.a.x, ring.a.y, ring.rim_height}, kShotElevation),
                  ThrowSpread{0.03f, 0.04f, 0.04f}, events);
  }
};

void BM_Step3D(benchmark::State& state) {
  const Shot shot;
  const std::unique_ptr<World> court = shot.world(uint32_t(state.range(0)));
  World& world = *court;
  shot.shoot(world);
  std::vector<Event> events;
  int64_t particle_steps = 0, realized = 0;
  for (auto _ : state) {
    realized += int64_t(events.size());
    events.clear();
    particle_steps += int64_t(world.cloud().size());
    world.step(1.0f / 60, shot.players, events);
    if (!world.live()) {
      state.PauseTiming();
      shot.shoot(world);
      state.ResumeTiming();
    }
  }
  state.counters["particle_steps/s"] = benchmark::Counter(double(particle_steps), benchmark::Counter::kIsRate);
  state.counters["events/step"] = benchmark::Counter(double(realized), benchmark::Counter::kAvgIterations);
}

// The vectorized part of the 3D step alone: a cloud in free flight high over the court, where
// nothing is near enough to need the exact search.
void BM_Step3DFlight(benchmark::State& state) {
  const Shot shot;
  const uint32_t n = uint32_t(state.range(0));
  const std::unique_ptr<World> court = shot.world(n);
  World& world = *court;
  auto toss = [&] {
    DecisionRng rng(world.steps());
    Cloud c;
    c.reserve(n, true);
    for (uint32_t i = 0; i < n; ++i)
      c.push(Vec3{float(-2 + 4 * rng.uniform()), float(9 + 2 * rng.uniform()), 4.0f},
             Vec3{float(rng.uniform() - 0.5), float(rng.uniform() - 0.5), 6.0f}, 1.0 / n, 1.0 / n);
    world.set_cloud(std::move(c));
  };
  toss();
  std::vector<Event> events;
  int64_t particle_steps = 0;
  for (auto _ : state) {
    particle_steps += int64_t(world.cloud().size());
    world.step(1.0f / 60, shot.players, events);
    if (world.cloud().z[0] < 4.0f) {
      state.PauseTiming();
      toss();
      state.ResumeTiming();
    }
  }
  state.counters["particle_steps/s"] = benchmark::Counter(double(particle_steps), benchmark::Counter::kIsRate);
  state.counters["events"] = double(events.size());
}

// The 3D fate report of that shot as it leaves the hand: every particle traced through its arcs,
// bounces and catches for 3 s, on state.range(1) threads. Timed by the wall clock.
void BM_FateReport3D(benchmark::State& state) {
  const Shot shot;
  WorldConfig config;
  config.particles = uint32_t(state.range(0));
  config.threads = uint32_t(state.range(1));
  World world(shot.field, config);
  world.place_bodies(shot.players);
  shot.shoot(world);
  FateReport report;
  for (auto _ : state) {
    world.predict(report, 3.0f);
    benchmark::DoNotOptimize(report.groups.data());
  }
  state.counters["groups"] = double(report.groups.size());
}

// The flat fate report of a spread cloud with the mallets in motion, on state.range(1) threads.
// Timed by the wall clock.
void BM_FateReport(benchmark::State& state) {
  const Field& field = airhockey();
  const uint32_t n = uint32_t(state.range(0));
  WorldConfig config;
  config.particles = n;
  config.threads = uint32_t(state.range(1));
  World world(field, config);
  world.set_cloud(tools::spread_cloud(field, n, 7));
  std::vector<Event> events;
  // Mallets in motion, so prediction extrapolates them.
  world.step(1.0f / 60, tools::scripted_mallets(field, 1.0 / 60), events);
  FateReport report;
  for (auto _ : state) {
    world.predict(report, 3.0f);
    benchmark::DoNotOptimize(report.groups.data());
  }
  state.counters["particles"] = double(world.cloud().size());
  state.counters["groups"] = double(report.groups.size());
}

// The memory-bandwidth limit of a step: a plain streaming pass over the arrays the step's fast
// pass must read and write (x and y read and written, vx and vy read: 24 bytes a particle),
// with nothing else in it. No step over this cloud can run faster than this on one core.
void BM_CloudStream(benchmark::State& state) {
  const size_t n = size_t(state.range(0));
  const Cloud cloud = tools::spread_cloud(airhockey(), uint32_t(n), 7);
  std::vector<float> x = cloud.x, y = cloud.y;
  const float* vx = cloud.vx.data();
  const float* vy = cloud.vy.data();
  const float dt = 1.0f / 60;
  for (auto _ : state) {
    float* px = x.data();
    float* py = y.data();
    for (size_t i = 0; i < n; ++i) px[i] += vx[i] * dt, py[i] += vy[i] * dt;
    benchmark::ClobberMemory();
  }
  state.counters["particle_steps/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes/s"] = benchmark::Counter(24.0 * double(n), benchmark::Counter::kIsIterationInvariantRate,
                                                 benchmark::Counter::kIs1024);
}

// A match of Quantum air hockey between simulated players that the benchmark never sees end,
// as fast as it goes unless a benchmark asks for the clock.
runtime::SessionOptions endless_match() {
  runtime::SessionOptions o;
  o.sport = "airhockey";
  o.seconds = 86400;  // the longest a match may be
  o.pacing = runtime::SessionOptions::Pacing::Fast;
  return o;
}

// One second of Quantum air hockey between two simulated players, through the session every
// front end uses: 60 frames of stepping, a fate prediction and tweak every frame, the Lua rules
// and the bots (no sound, no log). Each iteration is 1 s of play, so its time is the share of
// real time a live match needs.
void BM_MatchSecond(benchmark::State& state) {
  runtime::SessionOptions o = endless_match();
  o.particles = uint32_t(state.range(0));
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  for (auto _ : state)
    for (int frame = 0; frame < 60; ++frame) session.frame();
  if (!errors.str().empty()) state.SkipWithError(errors.str().c_str());
}

// BM_MatchSecond with its logs written as `quantum play --events --decisions` writes them: every
// frame's whole lines handed to the files (plain, or gzip-compressed with state.range(1) = 1), and
// synced within 100 ms by the engine's syncing thread. Side by side with BM_MatchSecond at 1000
// particles: what a crash-safe log costs (docs/reliability.md, "Faults").
void BM_MatchSecondLogged(benchmark::State& state) {
  runtime::SessionOptions o = endless_match();
  o.particles = uint32_t(state.range(0));
  const std::string suffix = state.range(1) ? ".jsonl.gz" : ".jsonl";
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quantum_bench_logs_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  o.events = (dir / ("events" + suffix)).string();
  o.decisions = (dir / ("decisions" + suffix)).string();
  std::ostringstream errors;
  {
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    for (auto _ : state)
      for (int frame = 0; frame < 60; ++frame) session.frame();
    session.finish();
  }
  state.counters["log_bytes_per_s"] = benchmark::Counter(
      double(std::filesystem::file_size(o.events) + std::filesystem::file_size(o.decisions)) / double(state.iterations()));
  std::filesystem::remove_all(dir);
  if (!errors.str().empty()) state.SkipWithError(errors.str().c_str());
}

// One frame of a running match of Quantum air hockey between two simulated players, through the
// session as `quantum play` runs it (step, decisions, prediction, tweak, the Lua rules, the bots;
// sound and log off): state.range(0) particles on state.range(1) threads, timed by the wall clock.
// The match plays 2 s before timing starts, so the cloud has grown to N and been hit; every run
// replays the same seeded frames (fixed iteration counts).
void BM_MatchFrame(benchmark::State& state) {
  runtime::SessionOptions o = endless_match();
  o.particles = uint32_t(state.range(0));
  o.threads = uint32_t(state.range(1));
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  for (int frame = 0; frame < 120; ++frame) session.frame();
  double longest = 0, particles = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    session.frame();
    longest = std::max(longest, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    particles += double(session.match().world().cloud().size());
  }
  state.counters["longest_ms"] = longest;
  // Between a goal and the next drop there is no cloud, and a new one grows from one particle.
  state.counters["mean_particles"] = benchmark::Counter(particles, benchmark::Counter::kAvgIterations);
  if (!errors.str().empty()) state.SkipWithError(errors.str().c_str());
}

// A match of `sport` with 10,000 particles, played until its cloud is in flight with all of
// them and predicted (a shot, a throw, a puck between the mallets): the busy frame a live view
// draws. The announcer's ticker is filled as the desk fills it.
struct DeskScene {
  std::ostringstream errors;
  runtime::Session session;
  runtime::Ticker ticker;
  bool busy = false;
  explicit DeskScene(const std::string& sport) : session(desk_match(sport), tools::lua_sport, nullptr, errors) {
    session.watch([&](const runtime::News& news) { ticker.hear(news); });
    for (int frame = 0; frame < 60 * 60 && !busy; ++frame) {
      session.frame();
      const World& world = session.match().world();
      busy = world.live() && world.cloud().size() >= 9'000 && session.match().report().group_of.size() == world.cloud().size();
    }
  }
  static runtime::SessionOptions desk_match(const std::string& sport) {
    runtime::SessionOptions o = endless_match();
    o.sport = sport;
    o.particles = 10'000;
    return o;
  }
};

// The desk's drawing of one busy frame of `sport` (runtime/desk/picture.h), the same frame again and
// again, in a picture state.range(0) pixels wide and state.range(1) high (0: as the field needs;
// 1100 x 0 is a video's and a snapshot's): what the live view, a video and a snapshot pay for a
// picture. Its yardstick is BM_DeskFrameStep of the same sport in the same run: a live view keeps
// real time at 60 Hz while the two together take less than 16.7 ms.
void BM_DeskDraw(benchmark::State& state, const std::string& sport) {
  DeskScene scene(sport);
  if (!scene.busy) return state.SkipWithError("the cloud never flew with 10,000 particles");
  runtime::Picture picture(scene.session.match().field(), {.width = int(state.range(0)), .height = int(state.range(1))});
  const runtime::Overlay overlay{scene.session.sport().name, "", "space pause   q quit", &scene.ticker, "0:01.00  last draw"};
  cv::Mat image;
  for (auto _ : state) picture.draw(scene.session.match(), overlay, image);
  state.counters["particles"] = double(scene.session.match().world().cloud().size());
  state.counters["pixels"] = double(image.total());
}

// The frames of the match BM_DeskDraw draws, from its busy frame on: step, decisions,
// prediction, tweak, rules and bots, on the session's two threads.
void BM_DeskFrameStep(benchmark::State& state, const std::string& sport) {
  DeskScene scene(sport);
  if (!scene.busy) return state.SkipWithError("the cloud never flew with 10,000 particles");
  for (auto _ : state) scene.session.frame();
}

// A new picture of `sport`'s field for a full-HD window, as a window makes one whenever it is
// resized (runtime/desk/picture.h): the layout and the layer of what every frame draws alike.
void BM_DeskResize(benchmark::State& state, const std::string& sport) {
  const Field field = lua::load_field(sport);
  for (auto _ : state) {
    const runtime::Picture picture(field, {.width = 1920, .height = 1080});
    benchmark::DoNotOptimize(picture.field_height());
  }
}

// What reusing the last frame's traces could save at best (docs/PERFORMANCE.md, "Reusing traces
// has a floor"), on one thread. A particle is followed from one frame to the next at its index when
// nothing happened to it: its velocity is the same (within friction) and it moved by a frame's
// flight, give or take the step's Brownian offset (uniform, at most `amplitude` per axis). A frame
// in which fewer than a tenth of the cloud is followed had its cloud rebuilt (a shot, a heard
// bounce, a drop): every trace in it is new. Counters, as shares of all particles over the timed
// frames: `rebuilt`; `followed`; `changed`, followed but with another fate than the last frame's;
// and `must_trace`, rebuilt or changed: the floor of what any reuse must trace again, generous in
// that it counts every particle not followed in the other frames (one that met something, or took
// a removed particle's place) as reusable. The time is not a match frame's: it includes the
// following.
void BM_FateTurnover(benchmark::State& state) {
  runtime::SessionOptions o = endless_match();
  o.particles = uint32_t(state.range(0));
  o.threads = 1;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  for (int frame = 0; frame < 120; ++frame) session.frame();
  const float dt = float(1.0 / session.match().fps());
  const float amplitude = noise_amplitude(session.match().world().field().brownian, dt);
  const auto fates_of = [&](std::vector<uint64_t>& keys) {
    const FateReport& report = session.match().report();
    keys.resize(report.group_of.size());
    for (size_t i = 0; i < keys.size(); ++i) keys[i] = report.groups[report.group_of[i]].fate.key();
  };
  Cloud before = session.match().world().cloud();
  std::vector<uint64_t> fate_before, fate_now;
  fates_of(fate_before);
  const auto moved_by_a_flight = [&](float p1, float p0, float v0) {
    return std::fabs(p1 - p0 - v0 * dt) <= amplitude + 0.02f * std::fabs(v0) * dt + 1e-3f;
  };
  double particles = 0, rebuilt = 0, followed = 0, changed = 0;
  for (auto _ : state) {
    session.frame();
    const Cloud& now = session.match().world().cloud();
    fates_of(fate_now);
    double frame_followed = 0, frame_changed = 0;
    for (size_t i = 0; i < std::min(now.size(), before.size()); ++i) {
      const float slack = 0.02f * std::hypot(before.vx[i], before.vy[i]) + 1e-3f;
      if (std::fabs(now.vx[i] - before.vx[i]) < slack && std::fabs(now.vy[i] - before.vy[i]) < slack &&
          moved_by_a_flight(now.x[i], before.x[i], before.vx[i]) && moved_by_a_flight(now.y[i], before.y[i], before.vy[i])) {
        ++frame_followed;
        frame_changed += fate_now[i] != fate_before[i];
      }
    }
    particles += double(now.size());
    if (frame_followed < 0.1 * double(now.size())) rebuilt += double(now.size());
    else followed += frame_followed, changed += frame_changed;
    before = now;
    std::swap(fate_before, fate_now);
  }
  if (particles > 0) {
    state.counters["rebuilt"] = rebuilt / particles;
    state.counters["followed"] = followed / particles;
    state.counters["changed"] = changed / particles;
    state.counters["must_trace"] = (rebuilt + changed) / particles;
  }
  if (!errors.str().empty()) state.SkipWithError(errors.str().c_str());
}

// One frame of a match at the sport's 1000 particles during which the sport reloads, as in
// `quantum play`: between two frames the reloader loads sport.lua again into a fresh sandbox
// (with its field), hands the match to it, carries the state over, and loads the power-up in use
// again; then the frame itself. Longest iteration reported as well: a reload must fit in one
// 60 Hz frame (16.7 ms) with the frame.
void BM_FrameWithReload(benchmark::State& state) {
  runtime::SessionOptions o = endless_match();
  o.watch = true;
  std::ostringstream errors;
  runtime::Session session(o, tools::lua_sport, nullptr, errors);
  for (int frame = 0; frame < 60; ++frame) session.frame();
  tools::scripted_rules(session).grant(session.match(), 1, "penalty", {});
  const std::string powerup = tools::scripted_rules(session).folders().powerups.back() / "penalty.lua";
  // Where the sport was found (o.sport is its name): the reloader knows its files by that path.
  const std::string sport = std::filesystem::path(session.sport().folder) / "sport.lua";
  double longest = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    session.reload(sport);
    session.reload(powerup);
    session.frame();
    longest = std::max(longest, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  state.counters["longest_ms"] = longest;
  // Each reload says so in a line; anything else is an error.
  std::istringstream lines(errors.str());
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("quantum: reloaded ", 0) != 0) return state.SkipWithError(line.c_str());
}

// `work` called again and again in the sandbox (arg 0), from this thread to the sandbox's lane
// and back, each call arming the frame's budget, or in a plain LuaJIT state with its own
// libraries (arg 1). Both run with the JIT off, as rules do.
void lua_work(benchmark::State& state, const char* work) {
  const bool sandboxed = state.range(0) == 0;
  const lua::Sandbox::Ptr sandbox = lua::Sandbox::make(lua::Limits{}, false);
  lua_State* L = sandboxed ? sandbox->L() : luaL_newstate();
  if (!sandboxed) {
    luaL_openlibs(L);
    luaJIT_setmode(L, 0, LUAJIT_MODE_ENGINE | LUAJIT_MODE_OFF);
  }
  luaL_loadstring(L, work);
  if (sandboxed) {
    sandbox->push_environment();
    lua_setfenv(L, -2);
  }
  const int function = luaL_ref(L, LUA_REGISTRYINDEX);
  for (auto _ : state) {
    sandbox->new_period();
    lua_rawgeti(L, LUA_REGISTRYINDEX, function);
    std::string error;
    if (sandboxed ? !sandbox->call(0, 1, error) : lua_pcall(L, 0, 1, 0) != 0) state.SkipWithError("the work failed");
    benchmark::DoNotOptimize(lua_tonumber(L, -1));
    lua_pop(L, 1);
  }
  if (!sandboxed) lua_close(L);
}

// What a call into the scripts costs by itself: a function that returns at once. In the sandbox
// that is the budget armed and the trip to the lane and back.
void BM_LuaCall(benchmark::State& state) { lua_work(state, "return 1"); }

// What the sandbox's bounds cost a rule: the same string work (an announcer's phrase taken apart
// and put together again) in the sandbox, where the pattern functions are the engine's counted
// ones (arg 0), and in a plain LuaJIT state with LuaJIT's own (arg 1).
void BM_LuaStrings(benchmark::State& state) {
  lua_work(state, R"lua(
    local said = "Goal for Blue, 3 to 2"
    local n = 0
    for i = 1, 20 do
      local team, a, b = said:match("for (%a+), (%d+) to (%d+)")
      local words = said:gsub("%s+", " ")
      for w in said:gmatch("%a+") do n = n + #w end
      if said:find("to", 1, true) then n = n + tonumber(a) + tonumber(b) end
    end
    return n
  )lua");
}

// Real-time pacing without a sound card: 2 s of a match (120 frames) paced by the session's own
// clock, as `quantum play --pace realtime` runs it. The counter is match seconds per wall second:
// 1 is real time.
void BM_RealTimePacing(benchmark::State& state) {
  double ratio = 0;
  for (auto _ : state) {
    runtime::SessionOptions o = endless_match();
    o.pacing = runtime::SessionOptions::Pacing::RealTime;
    std::ostringstream errors;
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    const auto start = std::chrono::steady_clock::now();
    for (int frame = 0; frame < 120; ++frame) session.frame();
    ratio = session.match().time() / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["match_s_per_wall_s"] = ratio;
}

// From an event's phrase to its first samples in the output buffer, for a phrase said before
// (cached): the speech cache look-up, the announcer starting it (cutting off the one before),
// and OpenAL mixing the first 64 frames. The sound card's own buffer comes on top of this.
void BM_AnnounceLatency(benchmark::State& state) {
  audio::Speech speech;
  const audio::Voice voice;
  speech.say("Goal for Blue!", voice);  // the cache is warm, as it is from the second goal on
  auto mixer = audio::Mixer::open_loopback(44100);
  audio::Announcer announcer(*mixer);
  std::vector<int16_t> out;
  int priority = 0;
  int16_t loudest = 0;
  for (auto _ : state) {
    announcer.say(speech.say("Goal for Blue!", voice), ++priority, 0.0);  // each outranks the last
    announcer.update(0.0);
    mixer->render(64, out);
    for (int16_t s : out) loudest = std::max<int16_t>(loudest, int16_t(std::abs(s)));
  }
  if (loudest == 0) state.SkipWithError("the phrase was not in the output");
}

// One 640x480 depth frame through the air hockey pipeline (background subtraction, arms, mallets,
// hover test, Kalman filters), two players reaching in; the camera 1.3 m above a synthetic table.
// Arg 0: the small table (0.9 m, camera 1.3 m up); 1: a full-size one at the far end of the range
// (2.2 m, camera 2.4 m up, tilted 3 degrees, 2 raw units of noise, 3 % holes): the most noise and
// the smallest arms in pixels.
void BM_DepthFrame(benchmark::State& state) {
  const std::string dir = (std::filesystem::temp_directory_path() / "quantum_bench_depth").string();
  tools::DepthSceneOptions scene;
  scene.frames = 60;
  if (state.range(0) == 1) {
    scene.length = 2.2f, scene.width = 1.1f, scene.height = 2.4f, scene.tilt = 3, scene.tilt_toward = 90;
    scene.noise = 2, scene.holes = 0.03f;
    state.SetLabel("2.2 m table, camera 2.4 m up");
  } else {
    state.SetLabel("0.9 m table, camera 1.3 m up");
  }
  tools::write_depth_recording(dir, scene);
  tracking::FakenectReader reader(dir);
  std::vector<tracking::RecordedFrame> frames;
  for (tracking::RecordedFrame f; reader.next(f);) frames.push_back(f);
  std::filesystem::remove_all(dir);
  tracking::DepthTracker tracker(tracking::tracked_field(airhockey()));
  size_t k = 0;
  for (; k < size_t(scene.background_frames); ++k) tracker.feed(frames[k]);
  size_t players = 0;
  for (auto _ : state) {
    const auto seen = tracker.feed(frames[k]);
    players += seen ? seen->players.size() : 0;
    k = k + 1 < frames.size() ? k + 1 : size_t(scene.background_frames);
  }
  state.counters["players/frame"] = benchmark::Counter(double(players), benchmark::Counter::kAvgIterations);
}

}  // namespace

// Fixed iteration counts: every run replays the same seeded match (about 10 s of play per size,
// 2 s at 1M), so runs differ only by the machine, not by how far into the game they got.
BENCHMARK(BM_Step)->Arg(1'000)->Iterations(3000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step)->Arg(10'000)->Iterations(1200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step)->Arg(100'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step)->Arg(1'000'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepSilentWalls)->Arg(100'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepSilentWalls)->Arg(1'000'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FateReport)->Args({1'000, 1})->Args({10'000, 1})->Args({100'000, 1})->Args({100'000, 2})
    ->Args({1'000'000, 1})->Args({1'000'000, 2})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CloudStream)->Arg(100'000)->Arg(1'000'000)->Arg(16'000'000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step3D)->Arg(1'000)->Iterations(3000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step3D)->Arg(100'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step3DFlight)->Arg(10'000)->Arg(100'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FateReport3D)->Args({1'000, 1})->Args({100'000, 1})->Args({100'000, 2})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MatchSecond)->Arg(1'000)->Arg(10'000)->Iterations(60)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MatchSecondLogged)->Args({1'000, 0})->Args({1'000, 1})->Iterations(60)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MatchFrame)->Args({100'000, 1})->Args({100'000, 2})->Iterations(300)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MatchFrame)->Args({1'000'000, 1})->Args({1'000'000, 2})->Iterations(120)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FateTurnover)->Arg(100'000)->Arg(1'000'000)->Iterations(600)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnnounceLatency)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RealTimePacing)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameWithReload)->Iterations(200)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LuaCall)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LuaStrings)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DepthFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Box2DStep)->Arg(1'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Box2DStep)->Arg(10'000)->Iterations(20)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Box2DStepQuiet)->Arg(1'000)->Iterations(600)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Box2DStepQuiet)->Arg(10'000)->Iterations(60)->Unit(benchmark::kMicrosecond);
// Every shipped sport (tests/shipped_sports.h), drawing and its yardstick side by side.
#define DESK_BENCHMARKS(sport)                                                                                          \
  BENCHMARK_CAPTURE(BM_DeskDraw, sport, #sport)                                                                       \
      ->Args({1100, 0})                                                                                                 \
      ->Args({1920, 1080})                                                                                              \
      ->Iterations(120)                                                                                                 \
      ->UseRealTime()                                                                                                   \
      ->Unit(benchmark::kMillisecond);                                                                                  \
  BENCHMARK_CAPTURE(BM_DeskFrameStep, sport, #sport)->Iterations(120)->UseRealTime()->Unit(benchmark::kMillisecond);
DESK_BENCHMARKS(airhockey)
DESK_BENCHMARKS(handball)
DESK_BENCHMARKS(basketball)
DESK_BENCHMARKS(keepaway)
DESK_BENCHMARKS(practice)
DESK_BENCHMARKS(soccer)
DESK_BENCHMARKS(volleyball)
BENCHMARK_CAPTURE(BM_DeskResize, basketball, "basketball")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
