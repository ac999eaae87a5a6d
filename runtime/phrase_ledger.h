// The event log and the transcript say what became of every phrase (spoken, cut off, dropped),
// and that is known only once the announcer has had its say, seconds after the event. A frame's
// events and phrases wait here until each of its phrases is settled, then are written in the
// order they happened. Without sound every phrase is settled at once (silent).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <span>
#include <vector>

#include "audio/audio.h"
#include "game/game.h"

namespace quantum::runtime {

class PhraseLedger {
 public:
  // Holds a frame's news; its phrases are numbered from next_id(), in order.
  void hold(std::span<const game::GameEvent> events, std::span<const game::Said> said);
  uint64_t next_id() const { return next_id_; }
  void settle(std::span<const audio::PhraseFate> fates);
  // Writes, oldest first, the frames whose phrases are all settled (every frame held, when
  // `all`: the match is over and nothing more will be).
  void write(std::ostream* log, std::ostream* transcript, bool all = false);

 private:
  struct Frame {
    size_t events, said;  // how many of each, in order after the frames before
  };
  // Slots are reused from frame to frame: a running match allocates nothing here.
  std::vector<Frame> frames_;
  std::vector<game::GameEvent> events_;
  std::vector<game::Said> said_;
  std::vector<audio::PhraseFate> fates_;  // one per said_, id 0 while unsettled
  size_t n_frames_ = 0, n_events_ = 0, n_said_ = 0;
  uint64_t next_id_ = 1, first_id_ = 1;  // first_id_: the id of said_[0]
};

}  // namespace quantum::runtime
