#include "desk.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <ostream>

#include "lua_reader.h"
#include "picture.h"
#include "interrupts.h"
#include "video.h"
#include "window.h"

namespace quantum::tools {
namespace {

constexpr const char* kHelp = "space pause   s step   m slow motion   p paths   r restart   q quit";
constexpr const char* kHandHelp = "click or t throw   space pause   s step   m slow   p paths   r restart   q quit";

// Keys of the live view. highgui gives the character's code (or -1).
enum Key : int {
  kPause = ' ', kStep = 's', kSlow = 'm', kPaths = 'p', kRestart = 'r', kQuit = 'q', kThrow = 't', kEscape = 27
};

// The player a person plays with the mouse: `name`, or the first when "".
int hand_body(const Field& field, const std::string& name) {
  std::vector<std::string> names;
  for (size_t k = 0; k < field.bodies.size(); ++k) {
    if (name.empty() || field.bodies[k].name == name) return int(k);
    names.push_back(field.bodies[k].name);
  }
  throw std::invalid_argument("--input mouse:" + name + ": " + lua::unknown_key(name, names, "player"));
}

// The snapshot's confirmation: "1100x880, the match at 2.5 s".
runtime::Written snapshot_written(const std::string& path, const cv::Mat& image, double t) {
  char what[96];
  std::snprintf(what, sizeof what, "%dx%d, the match at %.1f s", image.cols, image.rows, t);
  return {path, what};
}

}  // namespace

PlayResult play_at_desk(runtime::SessionOptions o, const DeskOptions& desk, std::ostream& out, std::ostream& errors,
                        bool transcript, const Telling* telling) {
  if (desk.hand && !desk.view) throw std::invalid_argument("--input mouse needs --view: the mouse moves over the view");
  if (!desk.snapshot.empty()) runtime::check_snapshot_file(desk.snapshot);
  if (!desk.video.empty()) runtime::check_video_file(desk.video);
  if (!desk.snapshot.empty()) o.must_reach = desk.snapshot_at;
  std::vector<runtime::Output> outputs = runtime::outputs_of(o);
  outputs.push_back({"--video", desk.video});
  outputs.push_back({"--snapshot", desk.snapshot});
  runtime::check_distinct(outputs);
  // Someone watches: the match runs in real time unless asked otherwise.
  o.watched = desk.view;
  std::optional<runtime::Window> window;
  runtime::Hand hand;
  const std::string wav = o.audio.rfind("wav:", 0) == 0 ? o.audio.substr(4) : "";
  bool quit = false;
  PlayResult result;
  // Restart (the r key) plays the match again from the start, as a new session.
  for (bool again = true; again && !quit;) {
    again = false;
    std::unique_ptr<runtime::PlayerSource> players;
    if (desk.hand) {
      const lua::Sport sport(o.sport, lua::engine_rules_folder(), lua::Params(o.params));
      const Field& field = sport.field();
      std::vector<double> skills = o.skills.empty() ? std::vector<double>(field.bodies.size(), 0.6) : o.skills;
      players = std::make_unique<runtime::HandPlayers>(field, skills, o.seed, sport.throw_speed(),
                                                       hand_body(field, desk.hand_player), hand);
    }
    runtime::Session session(o, transcript ? &out : nullptr, errors, std::move(players));
    runtime::end_matches_on_signals();
    if (desk.view && !window) window.emplace("Quantum games: " + session.sport().name());
    runtime::Picture picture(session.match().field());
    runtime::Ticker ticker;
    session.watch([&](const runtime::News& news) { ticker.hear(news); });
    runtime::Overlay overlay{session.sport().name(), "", desk.view ? (desk.hand ? kHandHelp : kHelp) : "", &ticker, ""};
    cv::Mat image;
    picture.draw(session.match(), overlay, image);
    std::optional<runtime::VideoFile> video;
    if (!desk.video.empty()) video.emplace(desk.video, image.cols, image.rows, desk.video_fps);
    const auto progress = match_progress(session, telling, errors, desk.video.empty() ? "match" : "video " + desk.video);
    bool paused = false, slow = false, step = false, snapped = false, restart_refused = false;
    runtime::Written snapshot;
    double next_video_frame = 0;
    for (bool playing = true; playing && !quit;) {
      if (window) {
        const runtime::Session::Drawing showing(session);
        const int key = window->show(image, paused ? 30 : 1);
        if (window->closed() || key == kQuit || key == kEscape) quit = true;
        if (key == kPause) paused = !paused, session.resync();
        if (key == kStep) paused = true, step = true;
        if (key == kSlow) slow = !slow, session.set_speed(slow ? 0.25 : 1.0);
        if (key == kPaths) picture.set_paths(!picture.options().paths);
        if (key == kRestart && o.record.empty()) again = true, playing = false;
        if (key == kRestart && !o.record.empty()) restart_refused = true;
        const runtime::Window::Mouse m = window->mouse();
        hand.throws += m.clicks + (key == kThrow ? 1 : 0);
        hand.over = m.over && m.y >= 0 && m.y < picture.field_height() && m.x >= 0 && m.x < image.cols;
        if (hand.over) hand.at = picture.to_field(m.x, m.y);
      }
      if (!paused || step) {
        if (paused) session.resync();  // a single step is due a frame from now, however long the pause
        playing = playing && session.frame();
        if (progress) (*progress)(session.match().time());
        ticker.mark(session.fates());
        // The last draw that realized something: "why did that happen?" at a glance.
        if (const Decision* d = session.match().decision(); d && d->realized >= 0)
          overlay.last_draw = runtime::describe_draw(*d, session.match().field());
        step = false;
      }
      const runtime::Session::Drawing drawing(session);
      overlay.status = restart_refused ? "no restart while recording: the recording is of one match"
                       : paused            ? "paused"
                       : slow              ? "slow motion (1/4)"
                                           : "";
      if (window || video || !snapped) picture.draw(session.match(), overlay, image);
      // The video takes the picture of every moment it has a frame for, in match time; the
      // moment the match ends closes it (a 4 s match at 30 frames a second is 120 frames).
      while (video && playing && session.match().time() + 1e-9 >= next_video_frame) {
        video->add(image);
        next_video_frame = video->frames() / video->fps();
      }
      if (!desk.snapshot.empty() && !snapped && desk.snapshot_at >= 0 && session.match().time() + 1e-9 >= desk.snapshot_at) {
        runtime::write_snapshot(desk.snapshot, image);
        snapped = true;
        snapshot = snapshot_written(desk.snapshot, image, session.match().time());
      }
    }
    if (progress) progress->clear();
    finish_and_keep(session, result);
    if (!desk.snapshot.empty() && !snapped) {
      runtime::write_snapshot(desk.snapshot, image);
      snapshot = snapshot_written(desk.snapshot, image, session.match().time());
      // A match that ends itself (a score reached) can end before the moment asked for.
      if (desk.snapshot_at >= 0) errors << "quantum: --snapshot-at: the match ended before it: the snapshot is its end\n";
    }
    if (video) video->finish(wav);
    if (video) result.written.push_back({desk.video, video->describe()});
    if (!snapshot.path.empty()) result.written.push_back(snapshot);
  }
  return result;
}

}  // namespace quantum::tools
