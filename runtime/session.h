// One match session: where the players come from, the match and its sport, its sound, hot
// reload, the event log, the transcript and the pacing. frame() is the one frame loop of the
// engine: `quantum play`, `quantum balance`, the rule specs' scenarios, the benchmarks and the
// tests all run matches through it.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "game/game.h"
#include "output_files.h"
#include "phrase_ledger.h"
#include "players.h"
#include "progress.h"
#include "sport_source.h"

namespace quantum::runtime {

class MatchAudio;
class LineFile;
class Recorder;

struct SessionOptions {
  std::string sport = "airhockey";
  std::string input = "bots";   // or a tracking source: fakenect:DIR, kinect, video:FILE, camera:N, tuio:PORT
  std::string accel;            // with a tracking source: accelerometer throws, FILE (CSV) or udp:PORT
  float fov = 82;               // with video or camera: its horizontal field of view, degrees
  std::optional<Vec2> field_size;   // with a Kinect: the field between the markers, instead of what it measures
  tracking::SetupOptions setup;     // with a Kinect: a table that is not the sport's field stops (strict) or is fitted
  std::vector<std::string> params;  // NAME=VALUE for the sport's scripts (param(), bindings/params.h)
  uint64_t seed = 1;
  double seconds = 0;           // 0: the sport's own time limit
  uint32_t particles = 0;       // 0: the sport's own
  uint32_t threads = 2;         // threads a large cloud's fate prediction shares: 1 or 2
  std::vector<double> skills;   // per player, 0..1; empty: 0.6 each
  std::vector<double> handicaps;  // per player; empty: the sport's
  double auto_balance = -1;       // handicap boost per goal behind; < 0: the sport's (docs/lua-api.md)
  std::map<std::string, double> factors;  // overrides of the sport's factors by fate kind
  std::string audio = "none";   // "" the sound card, "none", "wav:FILE" (see MatchAudio)
  std::string events;           // JSON lines: "" none, "-" stdout, or a file
  std::string decisions;        // every draw as a JSON line (docs/decisions.md): "" none, "-" stdout, or a file
  bool watch = false;           // reload the sport's and power-ups' scripts when they change
  std::string record;           // a folder to record the match into, for `quantum replay` ("" none)
  std::string command;          // the command line that started it, kept in a recording
  std::string replay;           // a recording to play again: its players, files and reloads ("" none)
  double until = 0;             // stop the session at this match time (> 0), whatever the match's limit
  // Real time: each frame waits for the clock. Automatic: real time when someone listens (a sound
  // card), plays (a live tracking source) or watches (a front end says so: see watched), as fast
  // as possible otherwise.
  enum class Pacing { Automatic, RealTime, Fast } pacing = Pacing::Automatic;
  bool watched = false;         // a person watches the match (a live view): automatic pacing is real time
  // A moment of the match a front end must reach (--snapshot-at), or < 0: one past the session's
  // end (Session::planned_end()) is refused before any file is opened.
  double must_reach = -1;
};

// The files (and standard output) a session with these options writes, for check_distinct():
// a front end adds its own (--video, --snapshot) before the session starts.
std::vector<Output> outputs_of(const SessionOptions& options);

// What a frame told, for whoever watches the session (a rule spec, a test, a view).
struct News {
  std::span<const game::GameEvent> events;
  std::span<const game::Said> said;     // Said::event indexes `events`
  std::span<const std::string> errors;  // rule errors
  uint64_t first_phrase = 0;            // the id of said[0] (then said[1]'s is one more...), as in fates()
};

class Session {
 public:
  // Loads the sport (through `sports`, which also reloads it; tools/lua_sport.h for the sports
  // written in Lua) and opens the outputs: the transcript to `transcript` (null for none), rule
  // errors and warnings to `errors`. Players come from `players`, or when null from
  // options.replay (a recording's: then the sport, the seed and the match's settings are the
  // recording's too) or options.input. Throws on bad options, a sport that does not load, a bad
  // field, an event log, WAV file or recording that cannot be written, or a tracking source or
  // recording that cannot be opened, or two outputs that are one file (check_distinct).
  Session(const SessionOptions& options, const SportLoader& sports, std::ostream* transcript, std::ostream& errors,
          std::unique_ptr<PlayerSource> players = nullptr);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // One frame: scripts that changed are reloaded, the players are brought up to the frame's
  // end, the match steps, and what it told goes to the players, the sound, the transcript, the
  // event log and the watcher; then the frame waits for the clock if the session runs in real
  // time. A live source that lost the players pauses the match (paused and resumed events)
  // until they are back. Every file gets the frame's whole lines before it returns (a kill loses
  // none of them). Returns false once the session is over: the match finished, its recording
  // ended, or a signal asked it to end (interrupts.h).
  bool frame();
  // Frames until the session is over, then finish().
  void run();
  // Lets the last phrase ring out and completes every file the match writes (once). Throws when
  // one of them (event or decision log, WAV, recording, the transcript) could not be written whole.
  void finish();

  // Real-time pacing: `speed` match seconds per wall second (0.25 is slow motion). resync()
  // takes the clock up from now, after a pause or a single step.
  void set_speed(double speed);
  void resync();

  // Frames as fast as they run, without the clock, until the match time reaches `t` or the
  // session is over (a desk seeking forward); then the clock is taken up from there. Returns
  // frame()'s last answer.
  bool run_to(double t);

  // What stands in the match's way now, for a view to show until it is fixed or dismissed: a
  // rules error (until a new version of the sport loads), a reload that failed (until that script
  // reloads), players that cannot be seen (until they are back). Oldest first.
  struct Problem {
    std::string kind;  // "rules error", "reload failed", "players lost"
    std::string text;  // FILE:LINE: message, as on the error stream
  };
  std::vector<Problem> problems() const;
  // Hides the problems standing now; a new one, or the same one again after it was fixed, shows.
  void dismiss_problems();

  // Called with each frame's news, and with news made between frames (a spec's grant), before
  // it is forgotten.
  void watch(std::function<void(const News&)> watcher) { watcher_ = std::move(watcher); }
  // Hands what the match told since the last frame to everyone now (a spec acting between frames).
  void tell();

  game::Match& match() { return *match_; }
  const game::Match& match() const { return *match_; }
  // The sport as it is now, and where it comes from: a reload replaces it, so hold no reference
  // across frames.
  const game::SportSpec& sport() const { return sport_->spec(); }
  SportSource& source() { return *sport_; }
  PlayerSource& players() { return *players_; }
  // What became of phrases, settled during the last frame (ids as in News::first_phrase).
  std::span<const audio::PhraseFate> fates() const;
  bool over() const { return over_; }
  int rule_errors() const { return rule_errors_; }
  // The signal that ended the session before its match did (SIGINT, SIGTERM), or 0.
  int interrupted() const { return interrupted_; }
  // Takes `file` as saved: the next frame reloads it as if inotify had seen it (benchmarks).
  void reload(const std::string& file);

  // Where the session ends unless its match ends itself sooner (a score reached, a signal): the
  // match time, and what puts the end there ("--seconds", "the sport's time limit", "--until",
  // "the recording's time limit", "the recording's end").
  struct End {
    double seconds = 0;
    std::string by;
  };
  const End& planned_end() const { return planned_end_; }
  // Whether frames wait for the clock (SessionOptions::pacing).
  bool real_time() const { return real_time_; }
  // The files the session wrote whole, after finish(), each with what it holds ("312 lines"), for
  // their confirmation lines (say_written): the event and decision logs, the WAV file, the recording.
  std::vector<Written> written() const;

  // The front end's drawing between frames (a view, a video): the late-match warning weighs it
  // against the engine's and the sound's time. A Drawing times what it lives through. What is
  // drawn before a resync() (a paused view, drawn again and again) is no frame's.
  void drew(double seconds) { drawn_ += seconds; }
  class Drawing {
   public:
    explicit Drawing(Session& session) : session_(session), from_(clock_seconds()) {}
    ~Drawing() { session_.drew(clock_seconds() - from_); }
    Drawing(const Drawing&) = delete;
    Drawing& operator=(const Drawing&) = delete;

   private:
    Session& session_;
    double from_;
  };

 private:
  void pause_or_resume(bool lost);
  void forget_fixed_problems();  // a problem dismissed, fixed and back shows again
  void report_repeated_errors();
  void write_settled(bool all = false);
  void commit_outputs();  // the frame's whole lines to every file, each failure said once
  void keep_time();  // real-time pacing: waits for the clock, or says once that the match runs late
  std::string late_because() const;  // what took a late match's frames their time

  // What the frames took, their waits for the clock aside: the engine (the match's step, with
  // its rules), the sound (phrases spoken, the mix), the front end's drawing (drew()) and the
  // frames as a whole (frame()'s own time; the drawing is between frames).
  struct Costs {
    double engine = 0, sound = 0, drawing = 0, frames = 0;
    uint64_t count = 0;
  } costs_;
  double drawn_ = 0;  // drew() since the last frame
  End planned_end_;

  std::ostream* transcript_;
  std::ostream& errors_;
  std::unique_ptr<SportSource> sport_;
  std::unique_ptr<game::Match> match_;
  std::unique_ptr<PlayerSource> players_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<MatchAudio> audio_;
  std::unique_ptr<LineFile> log_, decisions_;
  PhraseLedger ledger_;  // the event log's and the transcript's lines until their phrases are settled
  std::map<std::string, int> errors_seen_;  // each rule error once, with how often it came
  std::vector<std::string> rule_problems_;  // rule errors since the sport last loaded, not dismissed
  std::set<std::string> dismissed_;         // reload failures and "players lost" a person has seen
  std::function<void(const News&)> watcher_;
  double wall_start_ = 0;  // the steady clock's seconds at match time 0 (at this speed)
  // Real-time pacing: the clock the frames have taken, pauses left out, counted up to kept_from_.
  double wall_played_ = 0, kept_from_ = 0;
  double speed_ = 1;
  static constexpr double kLateToSay = 1.0;  // s behind the clock before the session says so
  double until_;
  bool real_time_ = false, paused_ = false, over_ = false, finished_ = false, recording_over_ = false, late_said_ = false;
  bool transcript_lost_ = false;
  bool reloads_ = false;  // the sport's scripts reload when they change (SessionOptions::watch, a replay)
  int rule_errors_ = 0, interrupted_ = 0;
};

}  // namespace quantum::runtime
