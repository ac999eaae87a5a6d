#include <algorithm>

#include "audio/audio.h"

namespace quantum::audio {

// Room for a busy stretch of play: phrases waiting, and stale ones to report, keep their slots
// (and their text's room) once made.
Announcer::Announcer(Mixer& mixer, double stale_after) : mixer_(mixer), stale_after_(stale_after) {
  queue_.resize(16);
  dropped_.resize(16);
  cut_.resize(16);
}

void Announcer::say(const Clip& clip, int priority, double now, std::string_view text) {
  mixer_.prepare(clip);
  if (n_waiting_ == queue_.size()) queue_.emplace_back();
  Waiting& w = queue_[n_waiting_++];
  w.clip = &clip, w.priority = priority, w.at = now;
  w.text.assign(text);
}

void Announcer::update(double now) {
  // Stale phrases go first: news that is old by the time it could be spoken is no news. Slots
  // are swapped, never copied, so every string keeps its room.
  for (size_t k = 0; k < n_waiting_;) {
    if (now - queue_[k].at <= stale_after_) {
      ++k;
      continue;
    }
    if (n_dropped_ == dropped_.size()) dropped_.emplace_back();
    dropped_[n_dropped_++].assign(queue_[k].text);
    std::rotate(queue_.begin() + long(k), queue_.begin() + long(k) + 1, queue_.begin() + long(n_waiting_));
    --n_waiting_;
  }
  if (n_waiting_ == 0) {
    if (current_ && !mixer_.playing(current_)) current_ = 0, current_text_.clear();
    return;
  }
  // The most urgent, and among equals the oldest.
  const auto end = queue_.begin() + long(n_waiting_);
  const auto next = std::min_element(queue_.begin(), end, [](const Waiting& a, const Waiting& b) {
    return a.priority != b.priority ? a.priority > b.priority : a.at < b.at;
  });
  const bool busy = current_ && mixer_.playing(current_);
  if (busy && next->priority <= current_priority_) return;
  if (busy) {  // outranked: cut off mid-phrase
    mixer_.stop(current_);
    if (n_cut_ == cut_.size()) cut_.emplace_back();
    cut_[n_cut_++].assign(current_text_);
  }
  current_ = mixer_.play_at_listener(*next->clip);
  current_priority_ = next->priority;
  current_text_.assign(next->text);
  std::rotate(next, next + 1, end);
  --n_waiting_;
}

}  // namespace quantum::audio
