// The designer's desk: `quantum play` and `quantum replay` with a live view (--view: a window
// that fits the screen, a time bar to seek in, an error screen), a video (--video FILE.mp4), a
// picture of one moment (--snapshot FILE.png, --snapshot-at T) and play by mouse
// (--input mouse[:PLAYER]). docs/desk.md shows it.
#pragma once

#include <iosfwd>
#include <string>

#include "play.h"
#include "session.h"

namespace quantum::tools {

struct DeskOptions {
  bool view = false;         // a window, at 60 Hz, with keys
  std::string video;         // a video file (its container by its ending: video.h), rendered at `video_fps`, headless
  double video_fps = 30;
  std::string snapshot;      // a PNG of the moment `snapshot_at` (< 0: the end)
  double snapshot_at = -1;
  bool hand = false;         // a person moves a player with the mouse (needs the view)...
  std::string hand_player;   // ...this one ("": the first)
  std::string view_log;      // what the view shows, in words: JSON lines (needs the view)

  bool wanted() const { return view || !video.empty() || !snapshot.empty() || hand; }
};

// Plays the session's match at the desk: frames as the view (if any) lets them run, each one
// drawn for the window, the video and the snapshot; with `telling`, a progress line while it
// plays faster than the clock (play.h). Returns the match's result, with the video and the
// snapshot among its files written.
PlayResult play_at_desk(runtime::SessionOptions options, const DeskOptions& desk, std::ostream& out,
                        std::ostream& errors, bool transcript, const Telling* telling = nullptr);

}  // namespace quantum::tools
