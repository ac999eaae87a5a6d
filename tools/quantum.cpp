// The `quantum` command. Exit codes: 0 done, 1 bad input (a mistyped command or option, a bad
// value, a file or sport that cannot be read or written, standard output full or closed), 2 rule
// specs that failed (quantum test), 128 + N a match ended early by signal N (130: Ctrl-C).
// `quantum audit` answers for the logs it checks instead: 1 a log that fails, 2 a file that is no
// log it can read.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

#include "lua_reader.h"
#include "output_files.h"
#include "progress.h"
#include "version.h"

#include "audit.h"
#include "balance.h"
#include "desk.h"
#include "interrupts.h"
#include "listen.h"
#include "play.h"
#include "quantum/fate.h"
#include "quantum/limits.h"
#include "simulate.h"
#include "spec.h"
#include "sports.h"
#include "track.h"

namespace {

// The engine's own checks of option values. CLI11's word their errors their own way ("Value 3 not
// in range 1 to 2"), and its ranges let "nan" through, since no comparison with NaN is true. A
// check's description names the value it takes, in --help and in "needs a value".

// A number in `range` (limits.h), e.g. "SECONDS in (0, 86400]".
CLI::Validator number_in(const std::string& name, const quantum::limits::Range& range) {
  const std::string interval = quantum::limits::interval(range);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        const bool number = CLI::detail::lexical_cast(text, v);
        if (number && range.contains(v)) return {};
        return "expected a number in " + interval + ", got '" + text + "'";
      },
      name + " in " + interval);
}

// A whole number in [lo, hi], in decimal digits only: "-1" and "18446744073709551616" are not
// seeds (CLI11 would wrap the one and clamp the other).
CLI::Validator whole_in(const std::string& name, uint64_t lo, uint64_t hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        errno = 0;
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        const uint64_t v = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
        if (digits && errno == 0 && v >= lo && v <= hi) return {};
        return "expected a whole number in " + range + ", got '" + text + "'";
      },
      name + " in " + range);
}

// One of a few words, e.g. "fast|box2d".
CLI::Validator one_of(const std::vector<std::string>& words) {
  std::string listed, choices;
  for (size_t k = 0; k < words.size(); ++k) {
    listed += (k == 0 ? "" : k + 1 == words.size() ? " or " : ", ") + words[k];
    choices += (k == 0 ? "" : "|") + words[k];
  }
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (std::find(words.begin(), words.end(), text) != words.end()) return {};
        return "expected " + listed + ", got '" + text + "'";
      },
      choices);
}

// The check's description becomes the value's name: CLI11 would show it after the C++ type's
// ("FLOAT:FLOAT in [0, 10]").
CLI::Option* checked(CLI::Option* option, CLI::Validator check) {
  option->type_name(check.get_description());
  return option->check(check.description(""));
}

namespace limits = quantum::limits;
const CLI::Validator kSeed = whole_in("SEED", 0, UINT64_MAX);
const CLI::Validator kParticles = whole_in("N", uint64_t(limits::kParticles.lo), uint64_t(limits::kParticles.hi));
// A match time (--snapshot-at): from its start to the longest match's end.
constexpr limits::Range kMatchTime{"match time", 0, limits::kMatchSeconds.hi, false, false, "s"};
// The table's ranges as the help words them.
const std::string kSkillHelp = "simulated players' skills in " + limits::interval(limits::kSkill) + ", one per player: BLUE,RED";
const std::string kHandicapHelp = "handicaps in " + limits::interval(limits::kHandicap) + ", 1 is even, one per player: BLUE,RED";

// Real command lines, each with what it does: the end of each command's --help (under "" the
// command's own), and the first one completes "FIELD is missing".
struct Example {
  std::string line, what;
};
const std::map<std::string, std::vector<Example>> kExamples = {
    {"",
     {{"quantum play handball --view --input mouse:Ben", "play Ben in a handball match: the mouse runs, a click throws"},
      {"quantum simulate basketball --snapshot shot.png", "a shooting practice, drawn from above and from the side"},
      {"quantum balance airhockey --matches 100", "win rates and gameflow over 100 seeded matches"}}},
    {"simulate",
     {{"quantum simulate airhockey --seconds 30 --events -", "30 s of air hockey, every event a JSON line on stdout"},
      {"quantum simulate basketball --snapshot shot.png", "a shooting practice, drawn from above and from the side"}}},
    {"play",
     {{"quantum play handball --view --input mouse:Ben", "play Ben: the mouse runs, a click throws"},
      {"quantum play airhockey --seconds 60 --audio wav:match.wav", "a minute of air hockey, its sound to match.wav"},
      {"quantum play soccer --seed 7 --record match", "a match kept in the new folder match, for quantum replay"}}},
    {"replay",
     {{"quantum replay match --view", "the match recorded by quantum play ... --record match, again in a window"},
      {"quantum replay match --until 30 --snapshot match.png", "its picture at 0:30"}}},
    {"balance",
     {{"quantum balance airhockey --matches 100", "win rates and gameflow over seeds 1 to 100"},
      {"quantum balance airhockey --matches 40 --handicap 1.5,1 --csv matches.csv",
       "blue's mallet with handicap 1.5, every match a CSV row"}}},
    {"test",
     {{"quantum test", "every spec under rules (outside a checkout: those of the engine's sports)"},
      {"quantum test airhockey", "air hockey's specs, found by its name"},
      {"quantum test rules/airhockey/spec", "the specs in a folder"}}},
    {"sports",
     {{"quantum sports", "every sport a name reaches, with its folder, players and parameters"},
      {"quantum play handball --input mouse:Ben --view", "a sport by its name, a player by one of the names listed"}}},
    {"track",
     {{"quantum track fakenect:table --fit-field", "a Kinect recording of a small table (quantum-synth table writes one)"},
      {"quantum track camera:0 --field handball --accel udp:9000",
       "hats seen from above by camera 0, throws from the players' accelerometers"}}},
    {"listen",
     {{"quantum listen match.wav match.jsonl", "which of the phrases in match.wav a listener would miss"},
      {"quantum play handball --seconds 40 --audio wav:match.wav --events match.jsonl", "a match that writes the two"}}},
    {"audit",
     {{"quantum audit decisions.jsonl events.jsonl", "check a match's draws, and its events against them"},
      {"quantum play airhockey --decisions decisions.jsonl --events events.jsonl", "a match that writes the two"}}},
};

std::string examples_footer(const std::vector<Example>& examples) {
  std::string text = "Examples:";
  for (const Example& e : examples) text += "\n  # " + e.what + "\n  " + e.line;
  return text;
}

const std::string& first_example(const CLI::App& command) {
  return kExamples.at(command.get_parent() ? command.get_name() : "").front().line;
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* c : app.get_subcommands({})) names.push_back(c->get_name());
  return names;
}

// One form for every bad command line: "quantum play: --threads: expected 1 or 2, got '3'".
std::string said(const CLI::App& command, const std::string& what) {
  return "quantum" + (command.get_parent() ? " " + command.get_name() : "") + ": " + what;
}

std::string names_of(const std::set<CLI::Option*>& options) {
  std::vector<std::string> names;
  for (const CLI::Option* o : options) names.push_back(o->get_name());
  return CLI::detail::join(names, " and ");
}

// The option a CLI11 error is about: the first one its message names as a whole word
// ("--snapshot-at requires --snapshot" is about --snapshot-at).
const CLI::Option* named_in(const std::string& message, const CLI::App& command) {
  const auto in_name = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.'; };
  const CLI::Option* first = nullptr;
  size_t first_at = std::string::npos;
  for (const CLI::Option* o : command.get_options()) {
    const std::string name = o->get_name();
    for (size_t at = message.find(name); at != std::string::npos && at < first_at; at = message.find(name, at + 1)) {
      const size_t end = at + name.size();
      if ((at > 0 && in_name(message[at - 1])) || (end < message.size() && in_name(message[end]))) continue;
      first = o, first_at = at;
    }
  }
  return first;
}

// A command line CLI11 refused, in the engine's words: the command, the option and what it takes.
// Nothing of CLI11's own wording comes out; the error's kind and the option it names say what
// went wrong.
std::string in_own_words(const CLI::App& app, const CLI::ParseError& e) {
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  const CLI::App& command = chosen.empty() ? app : *chosen.front();
  const std::string kind = e.get_name();
  const CLI::Option* option = named_in(e.what(), command);
  if (!option) {
    if (kind != "RequiredError") return said(command, "cannot read this command line");
    return said(command, "a command is missing (" + CLI::detail::join(command_names(app), ", ") + "; e.g. " +
                             first_example(command) + ")");
  }
  const std::string name = option->get_name(), takes = option->get_type_name();
  // Every check is one of the engine's own above: its message is already in the engine's words.
  if (kind == "ValidationError") return said(command, e.what());
  if (kind == "ArgumentMismatch") return said(command, takes.empty() ? name + " takes no value" : name + " needs a value (" + takes + ")");
  if (kind == "RequiredError")
    return said(command, name + " is missing (" + option->get_description() + "; e.g. " + first_example(command) + ")");
  if (kind == "RequiresError") return said(command, name + " needs " + names_of(option->get_needs()) + " as well");
  if (kind == "ExcludesError") return said(command, name + " cannot go with " + names_of(option->get_excludes()));
  const std::string given = option->results().empty() ? "" : option->results().back();
  if (kind == "ConversionError")
    return said(command, takes.empty() ? name + " takes no value, got '" + given + "'"
                                       : name + ": expected " + takes + ", got '" + given + "'");
  return said(command, name + ": cannot read '" + given + "'");
}

std::vector<std::string> long_options(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* o : command.get_options())
    if (!o->get_lnames().empty()) names.push_back("--" + o->get_lnames().front());
  return names;
}

// The first argument when it is neither a command nor an option of quantum's own (--help,
// --version), named with the nearest one; CLI11 would only say that a command is required.
std::string unknown_first(const CLI::App& app, const std::string& first) {
  if (first[0] == '-') {
    const std::string name = first.substr(0, first.find('='));
    if (app.get_option_no_throw(name)) return {};
    return said(app, quantum::lua::unknown_key(name, long_options(app), "option"));
  }
  const std::vector<std::string> commands = command_names(app);
  if (std::find(commands.begin(), commands.end(), first) != commands.end()) return {};
  return said(app, quantum::lua::unknown_key(first, commands, "command"));
}

// A command of a module this build left out (CMake's QUANTUM_WITH_*), told as a bad command line
// is: "quantum listen: this quantum was built without the speech recognizer
// (-DQUANTUM_WITH_RECOGNIZER=ON)".
[[maybe_unused]] int left_out(const CLI::App& command, quantum::runtime::Module module) {
  std::cerr << said(command, quantum::runtime::built_without(module)) << '\n';
  return 1;
}

// What a command left over, CLI11 knowing no place for it: an unknown option, named with the
// nearest one, or a stray argument.
std::string left_over(const CLI::App& command) {
  const std::vector<std::string> extra = command.remaining();
  if (extra.empty()) return {};
  const std::string& first = extra.front();
  if (first.rfind("--", 0) != 0) return said(command, "unexpected argument '" + first + "'");
  return said(command, quantum::lua::unknown_key(first.substr(0, first.find('=')), long_options(command), "option"));
}

// What play and replay tell on stderr besides warnings: a progress line, unless the transcript is
// on the same terminal (on stderr with `lines_out`), where its own lines say how far the match is.
quantum::tools::Telling told(bool transcript, bool lines_out) {
  const bool terminal = isatty(STDERR_FILENO);
  return {terminal, transcript && isatty(lines_out ? STDERR_FILENO : STDOUT_FILENO)};
}

// A match a signal ended early exits as the shell reports a process the signal ended (130 for
// Ctrl-C), its files complete.
int interrupted(const quantum::tools::PlayResult& result) { return result.interrupted ? 128 + result.interrupted : 0; }

}  // namespace

int main(int argc, char** argv) {
  // A file past the shell's size limit (ulimit -f) is a failed write, told and counted as a full
  // disk is, not the end of the process.
  std::signal(SIGXFSZ, SIG_IGN);
  // A reader that went away (`quantum play | head`) is a failed write to standard output, told
  // and exited with 1 once every file is complete, not a process killed with its files half written.
  std::signal(SIGPIPE, SIG_IGN);
  CLI::App app{"Quantum games engine: ball games played with a ball that exists only in the players' imagination"};
  app.require_subcommand(1);
  // Before the commands are added: each takes the help flag from here.
  app.set_help_flag("-h,--help", "show this help, with examples, and exit");
  app.set_version_flag("--version", quantum::runtime::version_line() + "\n" + quantum::runtime::modules_line(),
                       "show the version, the commit, the build's options and its modules");
  app.get_formatter()->label("SUBCOMMAND", "COMMAND");
  // The last of a repeated option counts: `tools/play.sh --seconds 5` overrides the script's own.
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);

  quantum::tools::SimulateOptions sim;
  CLI::App* simulate = app.add_subcommand("simulate", "run a field with two scripted mallets (on a field with a hoop: a shooting practice) and report every event");
  simulate->add_option("FIELD", sim.field, "a field file, or a sport: its name (quantum sports) or its folder")->required();
  checked(simulate->add_option("--seconds", sim.seconds, "simulated time")->capture_default_str(),
          number_in("SECONDS", limits::kMatchSeconds));
  checked(simulate->add_option("--particles", sim.particles, "particles in the cloud")->capture_default_str(), kParticles);
  checked(simulate->add_option("--seed", sim.seed, "seed of every random choice")->capture_default_str(), kSeed);
  checked(simulate->add_option("--backend", sim.backend, "fast, or box2d (the reference: one Box2D body per particle)")
              ->capture_default_str(),
          one_of({"fast", "box2d"}));
  simulate->add_option("--events", sim.events, "write one JSON object per event to FILE (- for stdout)")->type_name("FILE");
  simulate->add_option("--snapshot", sim.snapshot, "draw the cloud and its predicted fates to a PNG")->type_name("PNG");
  simulate->add_option("--decisions", sim.decisions, "write every draw the core makes as a JSON line to FILE "
                                                     "(- for stdout; docs/decisions.md)")->type_name("FILE");
  checked(simulate->add_option("--fps", sim.fps, "steps per second")->capture_default_str(), number_in("FPS", limits::kFps));
  simulate->add_option("--shooter", sim.shooter, "on a field with a hoop: the player who shoots (default: the first who catches)")
      ->type_name("NAME");
  checked(simulate->add_option("--purgatory", sim.purgatory, "frames a body keeps the particles it touched")
              ->capture_default_str(),
          whole_in("FRAMES", 1, 600));

  quantum::runtime::SessionOptions game;
  bool quiet = false;
  std::string skills, handicaps;
  CLI::App* play = app.add_subcommand("play", "play a match of a sport between simulated players");
  play->add_option("SPORT", game.sport, "the sport: its name (quantum sports lists them) or its folder")->capture_default_str();
  play->add_option("--input", game.input, "where the players come from: bots (simulated players), mouse[:PLAYER] "
                                         "(you, in the view, against simulated players), or tracking: fakenect:DIR, "
                                         "kinect, video:FILE, camera:N, tuio:PORT")->capture_default_str()->type_name("SOURCE");
  checked(play->add_option("--seed", game.seed, "seed of every random choice")->capture_default_str(), kSeed);
  checked(play->add_option("--seconds", game.seconds, "time limit (default: the sport's)"), number_in("SECONDS", limits::kMatchSeconds));
  checked(play->add_option("--particles", game.particles, "particles in the cloud (default: the sport's)"), kParticles);
  checked(play->add_option("--threads", game.threads, "threads of the quantum core, 1 or 2: a large cloud's prediction "
                                                      "shares its work (the match is the same either way)")
              ->capture_default_str(),
          one_of({"1", "2"}));
  play->add_option("--events", game.events, "write one JSON object per event to FILE (- for stdout)")->type_name("FILE");
  play->add_option("--skill", skills, kSkillHelp)->type_name("BLUE,RED");
  play->add_option("--handicap", handicaps, kHandicapHelp)->type_name("BLUE,RED");
  checked(play->add_option("--auto-balance", game.auto_balance, "automatic balance: each goal behind multiplies a team's "
                                                                "handicaps by 1 + this (default: the sport's)"),
          number_in("X", limits::kBalancePerGoal));
  game.audio = "";  // the command plays sound by default
  play->add_option("--audio", game.audio, "none, or wav:FILE to record the match's sound (default: the sound card)")
      ->type_name("none|wav:FILE");
  play->add_flag("--quiet", quiet, "no transcript");
  std::string pace;
  checked(play->add_option("--pace", pace, "realtime (the match waits for the clock) or fast (as fast as it goes); default: "
                                           "realtime with a view, a sound card or a live input, else fast"),
          one_of({"realtime", "fast"}));
  play->add_option("--decisions", game.decisions, "write every draw the engine makes as a JSON line to FILE "
                                                  "(- for stdout; docs/decisions.md)")->type_name("FILE");
  play->add_option("--record", game.record, "record the match into a new folder DIR, for quantum replay")->type_name("DIR");
  play->add_option("--accel", game.accel, "with a tracking input: accelerometer samples t,player,ax,ay,az from FILE "
                                          "(CSV) or udp:PORT (one per datagram): a player's whip throws the ball")
      ->type_name("FILE|udp:PORT");
  checked(play->add_option("--fov", game.fov, "with video or camera: its horizontal field of view, degrees")->capture_default_str(),
          number_in("DEGREES", limits::kFieldOfView));
  // A Kinect's table against the sport's field, on play and on track alike.
  auto add_setup = [](CLI::App* command, std::string& field_size, quantum::tracking::SetupOptions& setup) {
    command->add_option("--field-size", field_size, "with a Kinect: L,W, the field between the markers' centres in m, "
                                                    "instead of what the Kinect measures")->type_name("L,W");
    command->add_flag("--fit-field", setup.fit, "with a Kinect: stretch the sport's field over a table of another size");
    command->add_flag("--strict", setup.strict, "with a Kinect or a hat camera: stop when the table (the hall) is not "
                                                "the sport's field size");
  };
  std::string play_field_size;
  add_setup(play, play_field_size, game.setup);
  // Each --param adds one: `--param length=40 --param width=20`.
  auto add_params = [](CLI::App* command, std::vector<std::string>& params) {
    command->add_option("--param", params, "NAME=VALUE for the sport's scripts (param(NAME, default) in its "
                                           "field.lua and sport.lua), e.g. --param length=40")
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->type_name("NAME=VALUE");
  };
  add_params(play, game.params);
  add_params(simulate, sim.params);
  quantum::tools::DeskOptions desk;
  // The desk's options, on play and on replay alike.
  auto add_desk = [](CLI::App* command, quantum::tools::DeskOptions& d) {
    command->add_flag("--view", d.view, "show the match in a window (keys: space pause, s step, left/right seek, "
                                        "[ ] speed, p paths, f full screen, r restart, q quit; docs/desk.md)");
    command->add_option("--view-log", d.view_log, "write what the view shows (errors, status, the final whistle) "
                                                  "as JSON lines to FILE")->type_name("FILE");
    command->add_option("--video", d.video, "render the match to a video file, its container by its ending: .mp4, .mov, "
                                            ".mkv, .avi or .webm (with its sound when --audio wav:FILE)")
        ->type_name("FILE.mp4");
    checked(command->add_option("--video-fps", d.video_fps, "the video's frames per second")->capture_default_str(),
            number_in("FPS", limits::kVideoFps));
    CLI::Option* snapshot = command->add_option("--snapshot", d.snapshot, "draw the match to a PNG, at --snapshot-at "
                                                                          "or at the end")->type_name("PNG");
    checked(command->add_option("--snapshot-at", d.snapshot_at, "the match time of the snapshot, in seconds"),
            number_in("SECONDS", kMatchTime))->needs(snapshot);
  };
  add_desk(play, desk);

  quantum::runtime::SessionOptions again;
  bool replay_quiet = false;
  CLI::App* replay = app.add_subcommand("replay", "play a recorded match again (quantum play --record DIR)");
  replay->add_option("DIR", again.replay, "the recording's folder, from quantum play --record DIR")->required();
  checked(replay->add_option("--until", again.until, "stop at this match time, in seconds"), number_in("SECONDS", limits::kMatchSeconds));
  replay->add_option("--events", again.events, "write one JSON object per event to FILE (- for stdout)")->type_name("FILE");
  replay->add_option("--decisions", again.decisions, "write every draw as a JSON line to FILE (- for stdout)")->type_name("FILE");
  replay->add_option("--audio", again.audio, "none (the default), or wav:FILE to render the match's sound")
      ->capture_default_str()->type_name("none|wav:FILE");
  std::string replay_pace;
  checked(replay->add_option("--pace", replay_pace, "realtime or fast; default: realtime with a view, else fast"),
          one_of({"realtime", "fast"}));
  replay->add_flag("--quiet", replay_quiet, "no transcript");
  quantum::tools::DeskOptions replay_desk;
  add_desk(replay, replay_desk);

  quantum::runtime::SessionOptions study;
  std::string study_skills, study_handicaps, study_factors = "sport";
  int matches = 200;
  CLI::App* balance = app.add_subcommand("balance", "play many seeded matches between simulated players and report "
                                                   "win rates and gameflow");
  balance->add_option("SPORT", study.sport, "the sport: its name (quantum sports lists them) or its folder")->capture_default_str();
  checked(balance->add_option("--matches", matches, "how many matches (seeds --seed, --seed + 1, ...)")->capture_default_str(),
          whole_in("N", 1, 100'000));
  checked(balance->add_option("--seed", study.seed, "first seed")->capture_default_str(), kSeed);
  checked(balance->add_option("--seconds", study.seconds, "time limit of each match (default: the sport's)"),
          number_in("SECONDS", limits::kMatchSeconds));
  checked(balance->add_option("--particles", study.particles, "particles in the cloud (default: the sport's)"), kParticles);
  balance->add_option("--skill", study_skills, kSkillHelp)
      ->type_name("BLUE,RED");
  balance->add_option("--handicap", study_handicaps, kHandicapHelp)
      ->type_name("BLUE,RED");
  checked(balance->add_option("--auto-balance", study.auto_balance, "automatic balance: each goal behind multiplies a "
                                                                    "team's handicaps by 1 + this (default: the sport's)"),
          number_in("X", limits::kBalancePerGoal));
  checked(balance->add_option("--factors", study_factors, "sport (its own fate factors) or flat (every factor 1)")
              ->capture_default_str(),
          one_of({"sport", "flat"}));
  std::string balance_csv, balance_plot;
  int sweep_matches = 0;
  balance->add_option("--csv", balance_csv, "write every match as a CSV row to FILE (- for stdout)")->type_name("FILE");
  balance->add_option("--plot", balance_plot, "sweep the first team's handicap and the fate factors' strength and "
                                              "write the CSVs, PNG plots (gnuplot) and summary.md to DIR")->type_name("DIR");
  checked(balance->add_option("--sweep-matches", sweep_matches, "matches per point of a --plot sweep (default: a quarter "
                                                                "of --matches, at least 10)"),
          whole_in("N", 1, 100'000));
  add_params(balance, study.params);

  CLI::App* sports = app.add_subcommand("sports", "list the sports a name reaches (the current folder, QUANTUM_PATH, "
                                                 "the engine's), with their players and parameters");

  std::vector<std::string> spec_paths;
  CLI::App* test = app.add_subcommand("test", "run Lua rule specs (*_spec.lua) with the scenario API");
  test->add_option("PATHS", spec_paths, "spec files or folders, or sports by name (default: rules here, else the "
                                        "engine's sports)");

  quantum::tools::TrackOptions tracking;
  CLI::App* track = app.add_subcommand("track", "print the players a tracking source sees, one JSON object per frame");
  track->add_option("SOURCE", tracking.source, "fakenect:DIR for a Kinect recording, kinect for a live Kinect, "
                                               "video:FILE or camera:N for hats seen from above, tuio:PORT for TUIO 1.1")
      ->required();
  track->add_option("--accel", tracking.accel, "with video, camera or tuio: accelerometer samples t,player,ax,ay,az from FILE "
                                               "(CSV) or udp:PORT (one per datagram)")->type_name("FILE|udp:PORT");
  checked(track->add_option("--fov", tracking.fov, "with video or camera: its horizontal field of view, degrees")
              ->capture_default_str(),
          number_in("DEGREES", limits::kFieldOfView));
  track->add_option("--field", tracking.field, "a field file or a sport (name or folder): its size and who plays from "
                                              "which end")
      ->capture_default_str()->type_name("FIELD");
  add_setup(track, tracking.field_size, tracking.setup);
  checked(track->add_option("--frames", tracking.frames, "stop after this many frames (default, 0: all)"),
          whole_in("N", 0, INT32_MAX));
  add_params(track, tracking.params);

  std::string listen_wav, listen_events;
  CLI::App* listen = app.add_subcommand("listen", "report which of a match's phrases a listener would miss: a speech "
                                                  "recognizer over the played phrases of a WAV and its event log");
  listen->add_option("MATCH.wav", listen_wav, "the match's sound, from quantum play --audio wav:FILE")->required();
  listen->add_option("EVENTS.jsonl", listen_events, "its event log, from quantum play --events FILE")->required();

  std::vector<std::string> audit_files;
  CLI::App* audit = app.add_subcommand("audit", "check decision logs (docs/decisions.md): the draws' arithmetic, their "
                                                "outcomes against their chances, and the events");
  // Not CLI::ExistingFile: a file that cannot be read is the audit's own exit 2.
  audit->add_option("FILES", audit_files, "decision logs from --decisions and their event logs from --events: the "
                                          "first event log goes with the first decision log")
      ->required();

  app.footer(examples_footer(kExamples.at("")));
  for (CLI::App* command : app.get_subcommands({})) {
    command->group("Commands")->footer(examples_footer(kExamples.at(command->get_name())));
    // A positional's name says what it takes (FIELD, DIR): no C++ type after it in --help.
    for (CLI::Option* o : command->get_options())
      if (o->get_positional()) o->type_name("");
  }

  // A bad command line is told in the engine's words, naming the command and the option, and exits
  // 1. Unknown words are left to the commands (allow_extras) so that they can be named with the
  // nearest known one.
  for (CLI::App* command : app.get_subcommands({})) command->allow_extras();
  std::string bad;
  try {
    if (argc > 1) bad = unknown_first(app, argv[1]);
    if (bad.empty()) {
      app.parse(argc, argv);
      for (const CLI::App* command : app.get_subcommands())
        if (bad.empty()) bad = left_over(*command);
    }
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    bad = in_own_words(app, e);
  }
  if (!bad.empty()) {
    std::cerr << bad << "\n(quantum --help lists the commands, quantum COMMAND --help their options)\n";
    return 1;
  }
  std::string command_line = "quantum";
  for (int k = 1; k < argc; ++k) command_line += std::string(" ") + argv[k];
  game.command = command_line;
  int code = 0;
  try {
    if (test->parsed()) code = quantum::tools::run_specs(spec_paths);
    if (sports->parsed()) code = quantum::tools::list_sports(std::cout) == 0 ? 0 : 1;
    if (audit->parsed()) code = quantum::tools::audit(audit_files, std::cout, std::cerr, isatty(STDERR_FILENO));
    if (track->parsed()) {
#if QUANTUM_WITH_TRACKING
      tracking.field_given = track->count("--field") > 0;
      quantum::tools::track(tracking, std::cout);
#else
      return left_out(*track, quantum::runtime::Module::Tracking);
#endif
    }
    if (listen->parsed()) {
#if QUANTUM_WITH_RECOGNIZER
      quantum::tools::report(quantum::tools::listen(listen_wav, listen_events), std::cout);
#else
      return left_out(*listen, quantum::runtime::Module::Recognizer);
#endif
    }
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
      // One progress line for the whole study, its sweeps' matches included.
      const int sweep = sweep_matches ? sweep_matches : std::max(10, matches / 4);
      const int total = matches + (balance_plot.empty() ? 0 : quantum::tools::kSweepPoints * sweep);
      quantum::runtime::ProgressLine progress(std::cerr, isatty(STDERR_FILENO), "balance", total, "matches");
      const quantum::tools::BalanceResult r =
          quantum::tools::balance(study, matches, [&](int done) { progress(done); });
      progress.clear();
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
      std::vector<quantum::runtime::Written> written;
      if (balance_csv == "-") quantum::tools::write_csv(std::cout, r);
      else if (!balance_csv.empty()) {
        quantum::tools::write_csv(csv, r);
        if (!csv.flush()) throw std::runtime_error("--csv " + balance_csv + ": cannot be written");
        csv.close();
        written.push_back({balance_csv, std::to_string(r.matches) + " matches"});
      }
      if (!balance_plot.empty())
        written.push_back(quantum::tools::plot_study(study, r, sweep, balance_plot, &progress, std::cout));
      std::cout.flush();
      for (const quantum::runtime::Written& w : written) quantum::runtime::say_written(std::cerr, w);
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
      // With JSON lines on stdout the transcript moves to stderr, keeping stdout pure JSON lines.
      const bool lines_out = game.events == "-" || game.decisions == "-";
      const quantum::tools::Telling telling = told(!quiet, lines_out);
      code = interrupted(quantum::tools::play(game, lines_out ? std::cerr : std::cout, std::cerr, !quiet, &desk, &telling));
    }
    if (replay->parsed()) {
      if (!replay_pace.empty()) again.pacing = quantum::tools::pacing(replay_pace);
      const bool lines_out = again.events == "-" || again.decisions == "-";
      const quantum::tools::Telling telling = told(!replay_quiet, lines_out);
      code = interrupted(
          quantum::tools::play(again, lines_out ? std::cerr : std::cout, std::cerr, !replay_quiet, &replay_desk, &telling));
    }
    if (simulate->parsed()) {
      // With events on stdout the summary moves to stderr, keeping stdout pure JSON lines.
      quantum::tools::simulate(sim, sim.events == "-" || sim.decisions == "-" ? std::cerr : std::cout);
      if (const int signal = quantum::runtime::interrupting_signal()) code = 128 + signal;
    }
  } catch (const std::exception& e) {
    std::cerr << "quantum: " << e.what() << '\n';
    return 1;
  }
  if (!std::cout.flush()) {
    std::cerr << "quantum: could not write everything to standard output (full, or closed by its reader)\n";
    return 1;
  }
  return code;
}
