#include "desk.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <memory>
#include <optional>
#include <ostream>

#include "desk_screens.h"
#include "interrupts.h"
#include "lua_reader.h"
#include "output_files.h"
#include "picture.h"
#include "playback.h"
#include "video.h"
#include "window.h"
#include "lua_sport.h"

namespace quantum::tools {
namespace {

using runtime::kKeyEnd, runtime::kKeyEnter, runtime::kKeyEscape, runtime::kKeyHome, runtime::kKeyLeft,
    runtime::kKeyNone, runtime::kKeyRight;

// Keys of the live view: a character's code, or a runtime::SpecialKey.
enum Key : int {
  kPause = ' ', kStep = 's', kStepForward = '.', kStepBack = ',', kSlow = 'm', kSlower = '[', kFaster = ']',
  kPaths = 'p', kRestart = 'r', kQuit = 'q', kThrow = 't', kFullScreen = 'f',
};
constexpr double kSpeeds[] = {0.125, 0.25, 0.5, 1, 2, 4, 8};
constexpr double kArrowSeconds = 5;

// The player a person plays with the mouse: `name`, or the first when "".
int hand_body(const Field& field, const std::string& name) {
  std::vector<std::string> names;
  for (size_t k = 0; k < field.bodies.size(); ++k) {
    if (name.empty() || field.bodies[k].name == name) return int(k);
    names.push_back(field.bodies[k].name);
  }
  throw std::invalid_argument("--input mouse:" + name + ": " + lua::unknown_key(name, names, "player"));
}

// What the mouse does in this sport: what the hand's player does with the ball.
std::string mouse_keys(const Field& field, int body) {
  const BodySpec& b = field.bodies[size_t(body)];
  const std::string moves = "mouse: " + b.name;
  if (b.catches) return moves + ", click or t: throw   ";
  if (b.hits) return moves + " (hits the ball)   ";
  if (b.kicks) return moves + " (kicks the ball)   ";
  return moves + " (the ball bounces off it)   ";
}

std::string view_keys(bool looks_back) {
  return std::string("space pause   s . step   ") + (looks_back ? ", back   left/right 5 s   home end   " : "") +
         "[ ] speed   m slow   p paths   f full screen   r restart   q quit";
}

bool seeks(int key) {
  return key == kStepBack || key == kKeyLeft || key == kKeyRight || key == kKeyHome || key == kKeyEnd;
}

double next_speed(double speed, int step) {
  const auto at = std::find(std::begin(kSpeeds), std::end(kSpeeds), speed);
  const long k = at == std::end(kSpeeds) ? 3 : at - std::begin(kSpeeds);
  return kSpeeds[std::clamp<long>(k + step, 0, long(std::size(kSpeeds)) - 1)];
}

std::string score_line(const PlayResult& result) {
  std::string s = "final score:";
  for (const auto& [team, goals] : result.score) s += " " + team + " " + std::to_string(goals);
  return s + (result.winner.empty() ? "  (a draw)" : "  (" + result.winner + " wins)");
}

// The snapshot's confirmation: "1100x880, the match at 2.5 s".
runtime::Written snapshot_written(const std::string& path, const cv::Mat& image, double t) {
  char what[96];
  std::snprintf(what, sizeof what, "%dx%d, the match at %.1f s", image.cols, image.rows, t);
  return {path, what};
}

// --view-log: what the view shows a person in words, a JSON line each time it changes (a screen
// reader's, or a test's, way into the window).
class ViewLog {
 public:
  explicit ViewLog(const std::string& path) : file_("--view-log", path) {}
  void shows(double t, const std::string& what, const std::string& text) {
    if (!file_.stream() || last_[what] == text) return;
    last_[what] = text;
    *file_.stream() << nlohmann::json{{"t", t}, {"shows", what}, {"text", text}}.dump() << '\n';
    file_.commit();
  }
  void close() { file_.close(); }

 private:
  runtime::LineFile file_;
  std::map<std::string, std::string> last_;
};

}  // namespace

PlayResult play_at_desk(runtime::SessionOptions o, const DeskOptions& desk, std::ostream& out, std::ostream& errors,
                        bool transcript, const Telling* telling) {
  if (desk.hand && !desk.view) throw std::invalid_argument("--input mouse needs --view: the mouse moves over the view");
  if (!desk.view_log.empty() && !desk.view) throw std::invalid_argument("--view-log needs --view: it tells what the view shows");
  if (!desk.snapshot.empty()) runtime::check_snapshot_file(desk.snapshot);
  if (!desk.video.empty()) runtime::check_video_file(desk.video);
  if (!desk.snapshot.empty()) o.must_reach = desk.snapshot_at;
  std::vector<runtime::Output> outputs = runtime::outputs_of(o);
  outputs.push_back({"--video", desk.video});
  outputs.push_back({"--snapshot", desk.snapshot});
  outputs.push_back({"--view-log", desk.view_log});
  runtime::check_distinct(outputs);
  // Someone watches: the match runs in real time unless asked otherwise.
  o.watched = desk.view;
  runtime::Hand hand;
  int hand_player = -1;
  Playback::Players players;
  if (desk.hand) {
    const lua::ScriptedRules sport(o.sport, lua::engine_rules_folder(), lua::Params(o.params));
    const Field field = sport.spec().field;
    hand_player = hand_body(field, desk.hand_player);
    const std::vector<double> skills = o.skills.empty() ? std::vector<double>(field.bodies.size(), 0.6) : o.skills;
    players = [field, skills, seed = o.seed, speed = sport.spec().match.throw_speed, hand_player, &hand] {
      return std::make_unique<runtime::HandPlayers>(field, skills, seed, speed, hand_player, hand);
    };
  }
  // A video takes the match's moments in order: no looking back while one is written.
  const bool looks_back = desk.view && desk.video.empty();
  const bool own_record = o.record.empty();
  Playback playback(o, transcript ? &out : nullptr, errors, players, looks_back);
  runtime::end_matches_on_signals();
  ViewLog view_log(desk.view_log);
  runtime::Ticker ticker;
  const auto listen = [&] { playback.shown().watch([&](const runtime::News& news) { ticker.hear(news); }); };
  listen();

  // A copy: going back in a replay opens a new session, and a reload may load another field for
  // the next match; the view draws this match's.
  const Field field = playback.live().match().field();
  runtime::Picture picture(field);
  runtime::Overlay overlay{playback.live().sport().name, "", "", &ticker, "", hand_player};
  cv::Mat image, view;
  picture.draw(playback.shown().match(), overlay, image);
  runtime::TimeBar bar;
  bar.keys = (desk.hand ? mouse_keys(field, hand_player) : "") + view_keys(looks_back);
  view_log.shows(0, "keys", bar.keys);
  // The view draws its picture at the window's size, whatever the person makes it; a video's
  // frames keep the size they started with, and the window scales them.
  const bool follows_window = desk.view && desk.video.empty();
  const auto fit_picture = [&](cv::Size area) {
    runtime::PictureOptions fitted = picture.options();
    fitted.width = area.width, fitted.height = std::max(1, area.height - runtime::TimeBar::kHeight);
    picture = runtime::Picture(field, fitted);
    picture.draw(playback.shown().match(), overlay, image);
  };
  std::optional<runtime::Window> window;
  if (desk.view) {
    window.emplace("Quantum games: " + playback.live().sport().name,
                   follows_window ? cv::Size() : cv::Size(image.cols, image.rows + runtime::TimeBar::kHeight));
    if (follows_window) fit_picture(window->fitting(cv::Size()));
  }
  std::optional<runtime::VideoFile> video;
  if (!desk.video.empty()) video.emplace(desk.video, image.cols, image.rows, desk.video_fps);
  const auto progress = match_progress(playback.live(), telling, errors, desk.video.empty() ? "match" : "video " + desk.video);
  runtime::Written snapshot;

  PlayResult result;
  bool paused = false, step = false, snapped = false, over = false, quit = false, dragging = false;
  std::string refused;  // why the last key could not be done
  double next_video_frame = 0, speed = 1;
  const auto seek = [&](double t) {
    const bool restarts = playback.replay() && t < playback.shown().match().time() - 1e-9;
    playback.seek(t);
    listen();
    if (restarts) over = false;
    view_log.shows(playback.shown().match().time(), "seek", runtime::clock_text(playback.shown().match().time()));
  };
  // The window's picture: the match's, the time bar under it, and over it what a person must see.
  const auto compose = [&] {
    const game::Match& shown = playback.shown().match();
    bar.length = std::max(playback.length(), playback.played());
    bar.played = playback.played(), bar.now = shown.time(), bar.speed = speed;
    bar.note = playback.replay() ? "replay" : playback.looking_back() ? "looking back" : "live";
    view.create(image.rows + runtime::TimeBar::kHeight, image.cols, image.type());
    image.copyTo(view(cv::Rect(0, 0, image.cols, image.rows)));
    cv::Mat strip = view(cv::Rect(0, image.rows, image.cols, runtime::TimeBar::kHeight));
    runtime::draw_time_bar(bar, strip);
    const std::vector<runtime::Session::Problem> problems = playback.live().problems();
    runtime::draw_problems(problems, view);
    for (const runtime::Session::Problem& p : problems) view_log.shows(shown.time(), "problem", p.kind + ": " + p.text);
    if (problems.empty()) view_log.shows(shown.time(), "problem", "");
    view_log.shows(shown.time(), "status", overlay.status);
    if (over && !playback.looking_back()) {
      runtime::draw_final_whistle(score_line(result), view);
      view_log.shows(shown.time(), "final whistle", score_line(result));
    }
  };
  if (window) {
    compose();
    window->show(view);
    playback.shown().resync();  // opening the window took its time, not the match's
  }
  while (!quit) {
    if (window) {
      const runtime::Session::Drawing showing(playback.live());
      const int key = window->show(view, paused || over ? 30 : 1);
      view_log.shows(playback.shown().match().time(), "window", std::to_string(view.cols) + "x" + std::to_string(view.rows));
      quit = window->closed() || key == kQuit || key == kKeyEscape || (over && key != kKeyNone && !seeks(key));
      refused.clear();
      if (key == kPause) paused = !paused, playback.shown().resync();
      if (key == kStep || key == kStepForward) paused = true, step = true;
      if (key == kSlow) speed = speed == 0.25 ? 1 : 0.25;
      if (key == kSlower || key == kFaster) speed = next_speed(speed, key == kFaster ? 1 : -1);
      if (key == kSlow || key == kSlower || key == kFaster) playback.set_speed(speed);
      if (key == kPaths) picture.set_paths(!picture.options().paths);
      if (key == kFullScreen) window->toggle_full_screen();
      if (key == kKeyEnter) playback.live().dismiss_problems();
      if (seeks(key) && !looks_back) refused = "no looking back while a video is written";
      if (seeks(key) && looks_back) {
        const double now = playback.shown().match().time(), frame = 1 / playback.live().match().fps();
        if (key == kStepBack) paused = true;
        seek(key == kStepBack ? now - frame
             : key == kKeyLeft ? now - kArrowSeconds
             : key == kKeyRight ? now + kArrowSeconds
             : key == kKeyHome ? 0
                               : playback.played());
      }
      if (key == kRestart && !own_record) refused = "no restart while recording: the recording is of one match";
      if (key == kRestart && own_record && !playback.replay()) {
        finish_and_keep(playback.live(), result);
        playback.restart();
        listen();
        over = false;
      }
      if (const cv::Size area = window->size(); follows_window && !area.empty() && area != view.size()) fit_picture(area);
      const runtime::Window::Mouse m = window->mouse();
      const bool on_bar = m.over && m.y >= image.rows && m.y < view.rows;
      bar.pointed = on_bar && looks_back ? bar.time_at(m.x, view.cols) : -1;
      // A drag forward plays on at once; back, it goes when the button is let go (going back
      // replays from the start).
      if (bar.pointed >= 0 && (m.clicks > 0 || (m.down && bar.pointed > playback.shown().match().time()) ||
                               (dragging && !m.down)))
        seek(bar.pointed);
      dragging = on_bar && m.down;
      hand.throws += m.clicks * !on_bar + (key == kThrow ? 1 : 0);
      hand.over = !playback.looking_back() && m.over && picture.over_field(m.x, m.y);
      if (hand.over) hand.at = picture.to_field(m.x, m.y);
    }
    if (quit) break;
    bool playing = !over;
    if (!over && (!paused || step)) {
      if (paused) playback.shown().resync();  // a single step is due a frame from now, however long the pause
      const bool looked_back = playback.looking_back();
      playing = playback.frame();
      if (progress) (*progress)(playback.shown().match().time());
      if (looked_back && !playback.looking_back()) listen();
      ticker.mark(playback.shown().fates());
      // The last draw that realized something: "why did that happen?" at a glance.
      if (const Decision* d = playback.shown().match().decision(); d && d->realized >= 0)
        overlay.last_draw = runtime::describe_draw(*d, field);
      step = false;
    }
    const runtime::Session::Drawing drawing(playback.live());
    const game::Match& shown = playback.shown().match();
    overlay.status = !refused.empty()         ? refused
                     : playback.looking_back() ? "looking back: the match waits (end: back to it)"
                     : paused                  ? "paused"
                     : speed != 1              ? "speed " + (std::ostringstream() << speed).str() + "x"
                                               : "";
    if (window || video || !snapped) picture.draw(shown, overlay, image);
    // The video takes the picture of every moment it has a frame for, in match time; the
    // moment the match ends closes it (a 4 s match at 30 frames a second is 120 frames).
    while (video && playing && shown.time() + 1e-9 >= next_video_frame) {
      video->add(image);
      next_video_frame = video->frames() / video->fps();
    }
    if (!desk.snapshot.empty() && !snapped && desk.snapshot_at >= 0 && shown.time() + 1e-9 >= desk.snapshot_at) {
      runtime::write_snapshot(desk.snapshot, image);
      snapped = true;
      snapshot = snapshot_written(desk.snapshot, image, shown.time());
    }
    if (!playing && !over) {
      over = true;
      if (progress) progress->clear();
      finish_and_keep(playback.live(), result);
      // Asked to end (Ctrl-C, SIGTERM): nobody waits at the window for the final whistle.
      if (playback.live().interrupted()) break;
    }
    if (!window) {
      if (over) break;
      continue;
    }
    compose();
  }
  if (progress) progress->clear();
  finish_and_keep(playback.live(), result);
  if (!desk.snapshot.empty() && !snapped) {
    runtime::write_snapshot(desk.snapshot, image);
    snapshot = snapshot_written(desk.snapshot, image, playback.shown().match().time());
    // A match that ends itself (a score reached) can end before the moment asked for.
    if (desk.snapshot_at >= 0) errors << "quantum: --snapshot-at: the match ended before it: the snapshot is its end\n";
  }
  if (video) video->finish(o.audio.rfind("wav:", 0) == 0 ? o.audio.substr(4) : "");
  if (video) result.written.push_back({desk.video, video->describe()});
  if (!snapshot.path.empty()) result.written.push_back(snapshot);
  view_log.close();
  return result;
}

}  // namespace quantum::tools
