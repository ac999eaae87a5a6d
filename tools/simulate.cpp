#include "simulate.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#if QUANTUM_WITH_REFERENCE
#include "box2d_backend.h"
#endif
#include "interrupts.h"
#include "json_lines.h"
#include "output_files.h"
#include "params.h"
#include "field_loader.h"
#include "quantum/limits.h"
#include "quantum/world.h"
#include "scenes.h"
#include "event_log.h"
#include "recording.h"
#include "version.h"
#if QUANTUM_WITH_DESK
#include "picture.h"
#endif

namespace quantum::tools {
namespace {

constexpr double kRespawnDelay = 1.0;     // s between a goal and the next drop
constexpr double kRepredictEvery = 0.5;   // s: fates drift as the cloud spreads and mallets move

// Fates of the current cloud into `report`, and the contacts, weighed with the options' factors
// by kind: each the one term of its factor in `terms`, for the decision log.
void retweak(World& world, const KindFactors& factors, FateReport& report, game::FactorTerms& terms) {
  report.groups.clear();
  terms.clear();
  std::vector<double> weights;
  if (world.live() && !world.cloud().empty()) {
    world.predict(report);
    weights = factors_by_kind(report, factors);
    world.tweak(report, weights);
  }
  std::vector<Fate> contacts;
  world.contact_fates(contacts);
  const std::vector<double> contact_weights = factors_by_kind(contacts, factors);
  world.set_contact_factors(contact_weights);
  weights.insert(weights.end(), contact_weights.begin(), contact_weights.end());
  for (size_t k = 0; k < weights.size(); ++k) terms.add(k, {game::FactorTerm::Source::Sport, 0, -1, {}, 0, false, weights[k]});
}

// The decision log's first line (docs/decisions.md): a scene has no sport, rules or players'
// skills, so it names the field file and the factors by kind.
void write_header(std::ostream& out, const SimulateOptions& o, const Field& field) {
  namespace fs = std::filesystem;
  const fs::path file = fs::is_directory(o.field) ? fs::path(o.field) / "field.lua" : fs::path(o.field);
  const std::optional<std::string> hash = runtime::fingerprint(file);
  nlohmann::json factors = nlohmann::json::object(), players = nlohmann::json::array();
  for (FateKind k : kFateKinds) factors[to_string(k)] = factor_by_kind(k, o.factors);
  for (const BodySpec& b : field.bodies)
    players.push_back({{"name", b.name}, {"team", b.team}, {"skill", nullptr}, {"handicap", 1}});
  const nlohmann::json header = {{"format", "quantum decisions"}, {"version", runtime::kDecisionLogVersion},
                                 {"engine", runtime::engine_version()}, {"sport", ""},
                                 {"field", field.name},
                                 {"files", {{{"path", file.filename().string()}, {"fnv1a", hash ? nlohmann::json(*hash) : nlohmann::json()}}}},
                                 {"seed", o.seed}, {"seconds", o.seconds}, {"fps", o.fps}, {"particles", o.particles},
                                 {"tackle_rate", 0}, {"balance", {{"per_goal", 0}, {"most", 1}}}, {"params", o.params},
                                 {"factor_overrides", nlohmann::json::object()}, {"factors", factors}, {"players", players}};
  out << header.dump() << '\n';
}

// The spot a ball restarts from: the conceding team's after a goal, the nearest after out.
int respawn_spot(const Field& f, const Event& e) {
  if (e.type == EventType::Goal || e.type == EventType::OwnGoal) {
    const int spot = f.spot_of_team(f.goals[e.actor].team);
    if (spot >= 0) return spot;
  }
  int best = 0;
  float best_d = 1e30f;
  for (size_t s = 0; s < f.spots.size(); ++s) {
    const float d = std::hypot(f.spots[s].at.x - e.at.x, f.spots[s].at.y - e.at.y);
    if (d < best_d) best_d = d, best = int(s);
  }
  return best;
}

// Fields with height and a hoop: the shooter, by name (or the first player who catches), or -1.
int shooter_of(const Field& f, const std::string& name) {
  const bool hoop = std::any_of(f.goals.begin(), f.goals.end(), [](const Goal& g) { return g.hoop(); });
  if (!hoop) {
    if (!name.empty()) throw std::invalid_argument("--shooter needs a field with a hoop");
    return -1;
  }
  for (size_t k = 0; k < f.bodies.size(); ++k)
    if (f.bodies[k].catches && (name.empty() || f.bodies[k].name == name)) return int(k);
  throw std::invalid_argument(name.empty() ? "a field with a hoop needs a player who catches, to shoot"
                                           : "--shooter " + name + ": no player of that name catches on this field");
}

// A good shooter's scatter: about a degree and a half of direction and of elevation and 2 % of
// speed (a shot's length is its hardest part; 2 % is 15 cm over 7 m).
constexpr ThrowSpread kShotSpread{0.025f, 0.02f, 0.025f};

// The shooter's jump shot at the first hoop from where it stands: an arc at kShotElevation
// through the ring's centre, scattered as a good shooter's is.
void shoot(World& world, int shooter, std::vector<Event>& events) {
  const Field& f = world.field();
  const Goal& hoop = *std::find_if(f.goals.begin(), f.goals.end(), [](const Goal& g) { return g.hoop(); });
  const Vec2 p = world.body_positions()[size_t(shooter)];
  world.give(shooter);
  const Vec2 arm = f.release_point(shooter, p, hoop.a);
  const Vec3 v = f.arc_velocity({arm.x, arm.y, world.reach(shooter)}, {hoop.a.x, hoop.a.y, hoop.rim_height}, kShotElevation);
  if (v.x == 0 && v.y == 0 && v.z == 0) throw std::invalid_argument("the shooter stands where no arc reaches the hoop");
  world.release(shooter, v, kShotSpread, events);
}

// A team player's throw: from where it stands, at kPassSpeed, toward the middle of the first
// goal its team does not defend, else to the next teammate in the field's order, else to the
// next player (keep-away's lone catcher), else along the field. On a field with height, the
// flattest arc to chest height there.
constexpr float kPassSpeed = 10;     // m/s: a sport's throws.speed when it gives none
constexpr double kHoldSeconds = 0.6;  // how long a scripted player holds a ball it caught

void pass_on(World& world, int thrower, std::vector<Event>& events) {
  const Field& f = world.field();
  const std::vector<Vec2>& at = world.body_positions();
  const std::string& team = f.bodies[size_t(thrower)].team;
  const Vec2 from = at[size_t(thrower)];
  Vec2 to{from.x + 1, from.y};
  const size_t n = f.bodies.size();
  auto next = [&](bool teammate) {
    for (size_t step = 1; step < n; ++step) {
      const size_t k = (size_t(thrower) + step) % n;
      if (!teammate || f.bodies[k].team == team) return int(k);
    }
    return -1;
  };
  const auto goal = std::find_if(f.goals.begin(), f.goals.end(), [&](const Goal& g) { return g.team != team; });
  if (goal != f.goals.end()) to = {0.5f * (goal->a.x + goal->b.x), 0.5f * (goal->a.y + goal->b.y)};
  else if (const int mate = next(true); mate >= 0) to = at[size_t(mate)];
  else if (const int anyone = next(false); anyone >= 0) to = at[size_t(anyone)];
  const float dx = to.x - from.x, dy = to.y - from.y, d = std::hypot(dx, dy);
  // A teammate standing where the thrower stands: a throw along the field instead.
  const Vec2 way = d > 0 ? Vec2{dx / d, dy / d} : Vec2{1, 0};
  Vec3 v{kPassSpeed * way.x, kPassSpeed * way.y, 0};
  if (f.has_height()) {
    const Vec2 arm = f.release_point(thrower, from, to);
    v = f.throw_at({arm.x, arm.y, world.reach(thrower)}, {to.x, to.y, kChestShare * f.reach_of(thrower)}, kPassSpeed);
  }
  world.release(thrower, v, ThrowSpread{}, events);
}

// --backend box2d: the reference (core/reference), in a quantum built with it.
std::unique_ptr<Backend> reference_backend([[maybe_unused]] const Field& field) {
#if QUANTUM_WITH_REFERENCE
  return make_box2d_backend(field);
#else
  throw std::invalid_argument("--backend box2d: " + runtime::built_without(runtime::Module::Reference));
#endif
}

}  // namespace

void write_event(std::ostream& out, const Event& e, const Field& f) {
  const EventActor a = actor_of(e, f);
  runtime::JsonLine line(out);
  line.field("t", e.t).field("type", to_string(e.type)).field("actor", e.type == EventType::Out ? "out" : a.name);
  if (!a.team.empty()) line.field("team", a.team);
  line.field("p", e.p).field("p_newtonian", e.p_newtonian).field("particles", uint64_t(e.particles));
  line.field("x", double(e.at.x)).field("y", double(e.at.y));
  if (e.type == EventType::Hit || e.type == EventType::Bounce)
    line.field("vx", double(e.velocity.x)).field("vy", double(e.velocity.y));
  line.end();
}

void simulate(const SimulateOptions& o, std::ostream& summary) {
  limits::check(limits::kMatchSeconds, o.seconds, "--seconds");
  limits::check(limits::kFps, o.fps, "--fps");
  if (o.backend != "fast" && o.backend != "box2d")
    throw std::invalid_argument("--backend must be fast or box2d, not '" + o.backend + "'");
  if (!o.snapshot.empty()) {
#if QUANTUM_WITH_DESK
    runtime::check_snapshot_file(o.snapshot);
#else
    throw std::invalid_argument("--snapshot: " + runtime::built_without(runtime::Module::Desk));
#endif
  }
  lua::Params params(o.params);
  Field field = lua::load_field(o.field, &params);
  params.check_read(o.field);
  finish_field(field);
  WorldConfig config;
  config.particles = o.particles;
  config.seed = o.seed;
  config.purgatory_frames = o.purgatory;
  World world(field, config, o.backend == "box2d" ? reference_backend(field) : nullptr);
  // With height and a hoop the scene is a shooting practice: the players stand where the field
  // puts them, and the shooter shoots again a second after each shot ends (the paper's Figure 4).
  const int shooter = shooter_of(world.field(), o.shooter);
  // Without a hoop, players who catch play on: each holds a ball it catches for a moment, then
  // throws it on (pass_on); mallets strike it.
  const bool catching = world.field().catching(), team = catching && shooter < 0;
  std::vector<BodyInput> standing;
  for (const BodySpec& b : world.field().bodies) standing.push_back({b.start, {0, 0}});

  const runtime::Output outputs[] = {{"--events", o.events}, {"--decisions", o.decisions}, {"--snapshot", o.snapshot}};
  runtime::check_distinct(outputs);
  runtime::LineFile log("--events", o.events), decisions("--decisions", o.decisions);
  if (decisions.stream()) write_header(*decisions.stream(), o, world.field());
  FateReport report;  // the fates the draws are tweaked by
  game::FactorTerms terms;  // what each of their factors and the contacts' is made of
#if QUANTUM_WITH_DESK
  runtime::Picture picture(world.field());
  cv::Mat image;
  // The picture of the world as it is now, over the one before; its size ("1100x620").
  const auto take_snapshot = [&] {
    picture.draw(world, world.predict(), runtime::Overlay{"quantum simulate: " + world.field().name, "", "", nullptr, ""}, image);
    runtime::write_snapshot(o.snapshot, image);
    return std::to_string(image.cols) + "x" + std::to_string(image.rows);
  };
#else
  const auto take_snapshot = [] { return std::string(); };  // never asked: --snapshot is refused above
#endif
  std::string snapshot_size;

  std::vector<Event> events;
  std::map<std::string, int> counts, conceded;
  double respawn_at = 0.0;  // negative: no respawn pending
  int respawn_to = 0;
  double throw_at = -1;     // team players: when the holder throws; negative: none pending
  int thrower = -1;
  double next_tweak = 0;
  bool have_snapshot_moment = false;
  auto flush = [&]() {
    for (const Event& e : events) {
      if (log.stream()) write_event(*log.stream(), e, world.field());
      ++counts[to_string(e.type)];
      if (e.type == EventType::Goal || e.type == EventType::OwnGoal) ++conceded[world.field().goals[e.actor].name];
      if (e.type == EventType::Goal || e.type == EventType::OwnGoal || e.type == EventType::Out ||
          (shooter >= 0 && e.type == EventType::Catch)) {
        respawn_at = world.time() + kRespawnDelay;
        respawn_to = respawn_spot(world.field(), e);
      }
      if (team && e.type == EventType::Catch) throw_at = world.time() + kHoldSeconds, thrower = e.actor;
    }
  };

  const float dt = float(1.0 / o.fps);
  const uint64_t steps = uint64_t(o.seconds * o.fps + 0.5);
  // From here a signal ends the simulation early, its files completed (runtime/interrupts.h).
  runtime::end_matches_on_signals();
  for (uint64_t s = 0; s < steps && !runtime::interrupting_signal(); ++s) {
    events.clear();
    bool shot = false;
    if (respawn_at >= 0 && world.time() >= respawn_at - 1e-9) {
      if (shooter >= 0) shoot(world, shooter, events), shot = true;
      else world.drop(respawn_to, events);
      respawn_at = -1;
    }
    if (throw_at >= 0 && world.time() >= throw_at - 1e-9) {
      // A ball gone from the thrower's hands meanwhile (a goal, a restart) is not thrown.
      if (world.holder() == thrower) pass_on(world, thrower, events), shot = true;
      throw_at = -1;
    }
    if (shot) retweak(world, o.factors, report, terms);
    // The picture of a shot is taken as it leaves the hand.
    if (shot && !o.snapshot.empty() && !have_snapshot_moment) {
      snapshot_size = take_snapshot();
      have_snapshot_moment = true;
    }
    world.step(dt, shooter >= 0 ? std::span<const BodyInput>(standing) : scripted_mallets(world.field(), world.time() + dt),
               events);
    if (decisions.stream() && world.decision())
      runtime::write_decision(*decisions.stream(), *world.decision(), {terms, report.groups.size(), {}}, world.field());
    const bool decided = !events.empty();
    flush();
    log.commit();
    decisions.commit();
    log.say_failure(std::cerr);
    decisions.say_failure(std::cerr);
    // Every particle crushed, and nobody holds the ball: it is lost, restart it.
    if (!world.in_play() && respawn_at < 0) {
      respawn_at = world.time() + kRespawnDelay;
      respawn_to = 0;
    }
    if (decided || world.time() >= next_tweak) {
      retweak(world, o.factors, report, terms);
      next_tweak = world.time() + kRepredictEvery;
    }
    // The picture is taken right after the last realized hit: a fresh shot fanning out.
    if (!o.snapshot.empty() && world.live() && shooter < 0) {
      bool hit = false;
      for (const Event& e : events) hit |= e.type == EventType::Hit;
      if (hit || (!have_snapshot_moment && s + 1 == steps)) {
        snapshot_size = take_snapshot();
        have_snapshot_moment = true;
      }
    }
  }
  log.close();
  decisions.close();
  // Each file written, on stderr: the summary on `summary` is what other tools read.
  for (const runtime::LineFile* file : {&log, &decisions})
    if (const std::optional<runtime::Written> w = file->written()) runtime::say_written(std::cerr, *w);
  if (have_snapshot_moment) runtime::say_written(std::cerr, {o.snapshot, snapshot_size});

  summary << "simulated " << o.seconds << " s of " << world.field().name << " (" << o.backend << " backend, "
          << o.particles << " particles, seed " << o.seed << ")\n";
  summary << "events:";
  for (const char* type : {"drop", "hit", "goal", "own_goal", "out"}) summary << ' ' << type << ' ' << counts[type];
  if (catching)
    for (const char* type : {"throw", "bounce", "catch"}) summary << ' ' << type << ' ' << counts[type];
  summary << '\n';
  if (!conceded.empty()) {
    summary << "conceded:";
    for (const auto& [goal, n] : conceded) summary << ' ' << goal << ' ' << n << ';';
    summary << '\n';
  }
  if (!o.snapshot.empty())
    summary << (have_snapshot_moment ? "snapshot: " + o.snapshot : "snapshot: none (the ball was never live)") << '\n';
}

}  // namespace quantum::tools
