// The `quantum` command. Exit codes: 0 done, 1 bad input (a mistyped command or option, a bad
// value, a file or sport that cannot be read or written), 2 rule specs that failed (quantum test).
// `quantum audit` answers for the logs it checks instead: 1 a log that fails, 2 a file that is no
// log it can read.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include "lua_reader.h"
#include "output_files.h"
#include "recording.h"

#include "audit.h"
#include "balance.h"
#include "desk.h"
#include "listen.h"
#include "play.h"
#include "quantum/fate.h"
#include "simulate.h"
#include "spec.h"
#include "sports.h"
#include "track.h"

namespace {

// A number in [lo, hi] (or (lo, hi] with `open`): CLI11's own ranges let "nan" through, since no
// comparison with NaN is true.
CLI::Validator number_in(double lo, double hi, bool open = false) {
  std::ostringstream range;
  range << (open ? "(" : "[") << lo << ", " << hi << "]";
  const std::string interval = range.str();
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        const bool number = CLI::detail::lexical_cast(text, v);
        if (number && std::isfinite(v) && (open ? v > lo : v >= lo) && v <= hi) return {};
        return "expected a number in " + interval + ", got '" + text + "'";
      },
      "FLOAT in " + interval);
}

// Seeds are 64-bit: "-1" and "18446744073709551616" are not seeds (CLI11 would wrap the one and
// clamp the other).
const CLI::Validator kSeed(
    [](std::string& text) -> std::string {
      errno = 0;
      const bool digits = !text.empty() && text.size() <= 20 && text.find_first_not_of("0123456789") == std::string::npos;
      if (digits) std::strtoull(text.c_str(), nullptr, 10);
      if (digits && errno == 0) return {};
      return "expected a whole number from 0 to 18446744073709551615, got '" + text + "'";
    },
    "UINT64");

constexpr double kLongest = 24 * 3600;  // seconds: the longest match

}  // namespace

int main(int argc, char** argv) {
  // A file past the shell's size limit (ulimit -f) is a failed write, told and counted as a full
  // disk is, not the end of the process.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"Quantum games engine: ball games played with a ball that exists only in the players' imagination"};
  app.require_subcommand(1);
  app.set_version_flag("--version", quantum::runtime::engine_version());
  // The last of a repeated option counts: `tools/play.sh --seconds 5` overrides the script's own.
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);

  quantum::tools::SimulateOptions sim;
  CLI::App* simulate = app.add_subcommand("simulate", "run a field with two scripted mallets (on a field with a hoop: a shooting practice) and report every event");
  simulate->add_option("FIELD", sim.field, "a field file, or a sport: its name (quantum sports) or its folder")->required();
  simulate->add_option("--seconds", sim.seconds, "simulated time")->capture_default_str()->check(number_in(0, kLongest, true));
  simulate->add_option("--particles", sim.particles, "particles in the cloud")->capture_default_str()
      ->check(CLI::Range(1u, 10'000'000u));
  simulate->add_option("--seed", sim.seed, "seed of every random choice")->capture_default_str()->check(kSeed);
  simulate->add_option("--backend", sim.backend, "fast, or box2d (the reference: one Box2D body per particle)")
      ->capture_default_str()->check(CLI::IsMember({"fast", "box2d"}));
  simulate->add_option("--events", sim.events, "write one JSON object per event to FILE (- for stdout)");
  simulate->add_option("--snapshot", sim.snapshot, "draw the cloud and its predicted fates to a PNG");
  simulate->add_option("--decisions", sim.decisions, "write every draw the core makes as a JSON line to FILE "
                                                     "(- for stdout; docs/decisions.md)");
  simulate->add_option("--fps", sim.fps, "steps per second")->capture_default_str();
  simulate->add_option("--shooter", sim.shooter, "on a field with a hoop: the player who shoots (default: the first who catches)");
  simulate->add_option("--purgatory", sim.purgatory, "frames a body keeps the particles it touched")
      ->capture_default_str()->check(CLI::Range(1u, 600u));

  quantum::runtime::SessionOptions game;
  bool quiet = false;
  std::string skills, handicaps;
  CLI::App* play = app.add_subcommand("play", "play a match of a sport between simulated players");
  play->add_option("SPORT", game.sport, "the sport: its name (quantum sports lists them) or its folder")->capture_default_str();
  play->add_option("--input", game.input, "where the players come from: bots (simulated players), mouse[:PLAYER] "
                                         "(you, in the view, against simulated players), or tracking: fakenect:DIR, "
                                         "kinect, video:FILE, camera:N, tuio:PORT")->capture_default_str();
  play->add_option("--seed", game.seed, "seed of every random choice")->capture_default_str()->check(kSeed);
  play->add_option("--seconds", game.seconds, "time limit (default: the sport's)")->check(number_in(0, kLongest, true));
  play->add_option("--particles", game.particles, "particles in the cloud (default: the sport's)")
      ->check(CLI::Range(1u, 10'000'000u));
  play->add_option("--threads", game.threads, "threads of the quantum core, 1 or 2: a large cloud's prediction "
                                              "shares its work (the match is the same either way)")
      ->capture_default_str()->check(CLI::Range(1u, 2u));
  play->add_option("--events", game.events, "write one JSON object per event to FILE (- for stdout)");
  play->add_option("--skill", skills, "simulated players' skills in [0, 1], one per player: BLUE,RED");
  play->add_option("--handicap", handicaps, "handicaps in (0, 1000], 1 is even, one per player: BLUE,RED");
  play->add_option("--auto-balance", game.auto_balance, "automatic balance: each goal behind multiplies a team's "
                                                        "handicaps by 1 + this (default: the sport's)")
      ->check(number_in(0, 10));
  game.audio = "";  // the command plays sound by default
  play->add_option("--audio", game.audio, "none, or wav:FILE to record the match's sound (default: the sound card)");
  play->add_flag("--quiet", quiet, "no transcript");
  std::string pace;
  play->add_option("--pace", pace, "realtime (the match waits for the clock) or fast (as fast as it goes); default: "
                                   "realtime with a view, a sound card or a live input, else fast")
      ->check(CLI::IsMember({"realtime", "fast"}));
  play->add_option("--decisions", game.decisions, "write every draw the engine makes as a JSON line to FILE "
                                                  "(- for stdout; docs/decisions.md)");
  play->add_option("--record", game.record, "record the match into a new folder DIR, for quantum replay");
  play->add_option("--accel", game.accel, "with a tracking input: accelerometer samples t,player,ax,ay,az from FILE "
                                          "(CSV) or udp:PORT (one per datagram): a player's whip throws the ball");
  play->add_option("--fov", game.fov, "with video or camera: its horizontal field of view, degrees")
      ->capture_default_str()->check(number_in(1, 179));
  // A Kinect's table against the sport's field, on play and on track alike.
  auto add_setup = [](CLI::App* command, std::string& field_size, quantum::tracking::SetupOptions& setup) {
    command->add_option("--field-size", field_size, "with a Kinect: L,W, the field between the markers' centres in m, "
                                                    "instead of what the Kinect measures");
    command->add_flag("--fit-field", setup.fit, "with a Kinect: stretch the sport's field over a table of another size");
    command->add_flag("--strict", setup.strict, "with a Kinect: stop when the table is not the sport's field size");
  };
  std::string play_field_size;
  add_setup(play, play_field_size, game.setup);
  // Each --param adds one: `--param length=40 --param width=20`.
  auto add_params = [](CLI::App* command, std::vector<std::string>& params) {
    command->add_option("--param", params, "NAME=VALUE for the sport's scripts (param(NAME, default) in its "
                                           "field.lua and sport.lua), e.g. --param length=40")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  };
  add_params(play, game.params);
  add_params(simulate, sim.params);
  quantum::tools::DeskOptions desk;
  // The desk's options, on play and on replay alike.
  auto add_desk = [](CLI::App* command, quantum::tools::DeskOptions& d) {
    command->add_flag("--view", d.view, "show the match in a window (keys: space pause, s step, m slow motion, "
                                        "p paths, r restart, q quit)");
    command->add_option("--video", d.video, "render the match to an MP4 file (with its sound when --audio wav:FILE)");
    command->add_option("--video-fps", d.video_fps, "the video's frames per second")->capture_default_str()
        ->check(number_in(1, 240));
    CLI::Option* snapshot = command->add_option("--snapshot", d.snapshot, "draw the match to a PNG, at --snapshot-at "
                                                                          "or at the end");
    command->add_option("--snapshot-at", d.snapshot_at, "the match time of the snapshot, in seconds")
        ->check(number_in(0, kLongest))->needs(snapshot);
  };
  add_desk(play, desk);

  quantum::runtime::SessionOptions again;
  bool replay_quiet = false;
  CLI::App* replay = app.add_subcommand("replay", "play a recorded match again (quantum play --record DIR)");
  replay->add_option("DIR", again.replay, "the recording's folder")->required();
  replay->add_option("--until", again.until, "stop at this match time, in seconds")->check(number_in(0, kLongest, true));
  replay->add_option("--events", again.events, "write one JSON object per event to FILE (- for stdout)");
  replay->add_option("--decisions", again.decisions, "write every draw as a JSON line to FILE (- for stdout)");
  replay->add_option("--audio", again.audio, "none (the default), or wav:FILE to render the match's sound")
      ->capture_default_str();
  std::string replay_pace;
  replay->add_option("--pace", replay_pace, "realtime or fast; default: realtime with a view, else fast")
      ->check(CLI::IsMember({"realtime", "fast"}));
  replay->add_flag("--quiet", replay_quiet, "no transcript");
  quantum::tools::DeskOptions replay_desk;
  add_desk(replay, replay_desk);

  quantum::runtime::SessionOptions study;
  std::string study_skills, study_handicaps, study_factors = "sport";
  int matches = 200;
  CLI::App* balance = app.add_subcommand("balance", "play many seeded matches between simulated players and report "
                                                   "win rates and gameflow");
  balance->add_option("SPORT", study.sport, "the sport: its name (quantum sports lists them) or its folder")->capture_default_str();
  balance->add_option("--matches", matches, "how many matches (seeds --seed, --seed + 1, ...)")->capture_default_str();
  balance->add_option("--seed", study.seed, "first seed")->capture_default_str()->check(kSeed);
  balance->add_option("--seconds", study.seconds, "time limit of each match (default: the sport's)")
      ->check(number_in(0, kLongest, true));
  balance->add_option("--particles", study.particles, "particles in the cloud (default: the sport's)")
      ->check(CLI::Range(1u, 10'000'000u));
  balance->add_option("--skill", study_skills, "simulated players' skills in [0, 1], one per player: BLUE,RED");
  balance->add_option("--handicap", study_handicaps, "handicaps in (0, 1000], 1 is even, one per player: BLUE,RED");
  balance->add_option("--auto-balance", study.auto_balance, "automatic balance: each goal behind multiplies a "
                                                            "team's handicaps by 1 + this (default: the sport's)")
      ->check(number_in(0, 10));
  balance->add_option("--factors", study_factors, "sport (its own fate factors) or flat (every factor 1)")
      ->capture_default_str()->check(CLI::IsMember({"sport", "flat"}));
  std::string balance_csv, balance_plot;
  int sweep_matches = 0;
  balance->add_option("--csv", balance_csv, "write every match as a CSV row to FILE (- for stdout)");
  balance->add_option("--plot", balance_plot, "sweep the first team's handicap and the fate factors' strength and "
                                              "write the CSVs, PNG plots (gnuplot) and summary.md to DIR");
  balance->add_option("--sweep-matches", sweep_matches, "matches per point of a --plot sweep (default: a quarter of "
                                                        "--matches, at least 10)")->check(CLI::Range(1, 100'000));
  add_params(balance, study.params);

  CLI::App* sports = app.add_subcommand("sports", "list the sports a name reaches (the current folder, QUANTUM_PATH, "
                                                 "the engine's), with their players and parameters");

  std::vector<std::string> spec_paths;
  CLI::App* test = app.add_subcommand("test", "run Lua rule specs (*_spec.lua) with the scenario API");
  test->add_option("PATHS", spec_paths, "spec files or folders, or sports by name (default: rules here, else the "
                                        "engine's sports)");

  quantum::tools::TrackOptions tracking;
  CLI::App* track = app.add_subcommand("track", "print the players a tracking source sees, one JSON object per frame");
  track->add_option("SOURCE", tracking.source, "fakenect:DIR (a Kinect recording), kinect (a live Kinect), "
                                               "video:FILE or camera:N (hats seen from above), tuio:PORT (TUIO 1.1)")
      ->required();
  track->add_option("--accel", tracking.accel, "with video, camera or tuio: accelerometer samples t,player,ax,ay,az from FILE "
                                               "(CSV) or udp:PORT (one per datagram)");
  track->add_option("--fov", tracking.fov, "with video or camera: its horizontal field of view, degrees")
      ->capture_default_str()->check(number_in(1, 179));
  track->add_option("--field", tracking.field, "a field file or a sport (name or folder): its size and who plays from "
                                              "which end")
      ->capture_default_str();
  add_setup(track, tracking.field_size, tracking.setup);
  track->add_option("--frames", tracking.frames, "stop after this many frames (default: all)");
  add_params(track, tracking.params);

  std::string listen_wav, listen_events;
  CLI::App* listen = app.add_subcommand("listen", "report which of a match's phrases a listener would miss: a speech "
                                                  "recognizer over the played phrases of a WAV and its event log");
  listen->add_option("MATCH.wav", listen_wav, "the match's sound (quantum play --audio wav:FILE)")->required();
  listen->add_option("EVENTS.jsonl", listen_events, "its event log (quantum play --events FILE)")->required();

  std::vector<std::string> audit_files;
  CLI::App* audit = app.add_subcommand("audit", "check decision logs (docs/decisions.md): the draws' arithmetic, their "
                                                "outcomes against their chances, and the events");
  // Not CLI::ExistingFile: a file that cannot be read is the audit's own exit 2.
  audit->add_option("FILES", audit_files, "decision logs (--decisions) and their event logs (--events): the first "
                                          "event log goes with the first decision log")
      ->required();

  // A mistyped command or option is named, with the nearest one; any parse error exits 1.
  for (CLI::App* command : app.get_subcommands({})) command->allow_extras();
  try {
    std::vector<std::string> names;
    for (const CLI::App* command : app.get_subcommands({})) names.push_back(command->get_name());
    if (argc > 1 && argv[1][0] != '-' && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      throw CLI::ValidationError(quantum::lua::unknown_key(argv[1], names, "command"));
    }
    app.parse(argc, argv);
    for (CLI::App* command : app.get_subcommands()) {
      const std::vector<std::string> extra = command->remaining();
      if (extra.empty()) continue;
      std::vector<std::string> options;
      for (const CLI::Option* o : command->get_options())
        if (!o->get_lnames().empty()) options.push_back("--" + o->get_lnames().front());
      const std::string& first = extra.front();
      const std::string name = first.substr(0, first.find('='));
      throw CLI::ValidationError(first.rfind("--", 0) == 0
                                     ? quantum::lua::unknown_key(name, options, "option") + " for quantum " + command->get_name()
                                     : "quantum " + command->get_name() + ": unexpected argument '" + first + "'");
    }
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "quantum: " << e.what() << "\n(quantum --help lists the commands, quantum COMMAND --help their options)\n";
    return 1;
  }
  std::string command_line = "quantum";
  for (int k = 1; k < argc; ++k) command_line += std::string(" ") + argv[k];
  game.command = command_line;
  try {
    if (test->parsed()) return quantum::tools::run_specs(spec_paths);
    if (sports->parsed()) return quantum::tools::list_sports(std::cout) == 0 ? 0 : 1;
    if (audit->parsed()) return quantum::tools::audit(audit_files, std::cout, std::cerr, isatty(STDERR_FILENO));
    if (track->parsed()) quantum::tools::track(tracking, std::cout);
    if (listen->parsed()) quantum::tools::report(quantum::tools::listen(listen_wav, listen_events), std::cout);
    if (balance->parsed()) {
      if (!study_skills.empty()) study.skills = quantum::tools::parse_skills(study_skills);
      if (!study_handicaps.empty()) study.handicaps = quantum::tools::parse_list(study_handicaps, "--handicap");
      if (study_factors == "flat")
        for (const std::string& kind : quantum::fate_kind_names()) study.factors[kind] = 1;
      // Where the results go is known before the study plays.
      std::ofstream csv;
      if (!balance_csv.empty() && balance_csv != "-") {
        quantum::runtime::check_output_file("--csv", balance_csv);
        csv.open(balance_csv);
        if (!csv) throw std::runtime_error("--csv " + balance_csv + ": cannot be written");
      }
      if (!balance_plot.empty()) quantum::runtime::make_output_folder("--plot", balance_plot);
      const bool terminal = isatty(STDERR_FILENO);
      quantum::tools::Progress progress(matches, terminal);
      const quantum::tools::BalanceResult r =
          quantum::tools::balance(study, matches, [&](int done) { progress(done); });
      progress.finish();
      std::cout << r.matches << " matches of " << study.sport << " (seeds " << study.seed << " to "
                << study.seed + uint64_t(matches) - 1 << ", skills " << (study_skills.empty() ? "0.6 each" : study_skills)
                << ", handicaps " << (study_handicaps.empty() ? "the sport's" : study_handicaps)
                << (study.auto_balance >= 0 ? ", auto-balance " + std::to_string(study.auto_balance) : "") << ", "
                << study_factors << " factors)\n";
      char figure[160];
      std::cout << "wins:";
      for (const auto& [team, n] : r.wins) {
        std::snprintf(figure, sizeof figure, " %s %d (%.0f %%)", team.c_str(), n, 100.0 * n / r.matches);
        std::cout << figure;
      }
      std::cout << ", draws " << r.draws << '\n' << quantum::tools::describe(r.counted, r.totals);
      // A stall is play the match lost (docs/lua-api.md, match.stall): a study says how often.
      std::snprintf(figure, sizeof figure, "\nstalls %d, in %d of %d matches", r.stalls, r.stalled_matches, r.matches);
      std::cout << figure;
      std::cout << '\n';
      if (balance_csv == "-") quantum::tools::write_csv(std::cout, r);
      else if (!balance_csv.empty()) {
        quantum::tools::write_csv(csv, r);
        if (!csv.flush()) throw std::runtime_error("--csv " + balance_csv + ": cannot be written");
      }
      if (!balance_plot.empty())
        quantum::tools::plot_study(study, r, sweep_matches ? sweep_matches : std::max(10, matches / 4), balance_plot,
                                   terminal, std::cout);
    }
    if (play->parsed()) {
      if (!skills.empty()) game.skills = quantum::tools::parse_skills(skills);
      if (!handicaps.empty()) game.handicaps = quantum::tools::parse_list(handicaps, "--handicap");
      game.watch = true;  // a designer's saved script takes effect between two frames
      if (!pace.empty()) game.pacing = quantum::tools::pacing(pace);
      game.field_size = quantum::tools::parse_field_size(play_field_size);
      if (game.input == "mouse" || game.input.rfind("mouse:", 0) == 0) {
        desk.hand = true;
        desk.hand_player = game.input.size() > 6 ? game.input.substr(6) : "";
        game.input = "bots";
      }
      quantum::tools::play(game, game.events == "-" ? std::cerr : std::cout, std::cerr, !quiet, &desk);
    }
    if (replay->parsed()) {
      if (!replay_pace.empty()) again.pacing = quantum::tools::pacing(replay_pace);
      quantum::tools::play(again, again.events == "-" ? std::cerr : std::cout, std::cerr, !replay_quiet, &replay_desk);
    }
    if (simulate->parsed()) {
      // With events on stdout the summary moves to stderr, keeping stdout pure JSON lines.
      quantum::tools::simulate(sim, sim.events == "-" ? std::cerr : std::cout);
    }
  } catch (const std::exception& e) {
    std::cerr << "quantum: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
