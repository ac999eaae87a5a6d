#include <algorithm>

#include "audio/audio.h"

namespace quantum::audio {

void Announcer::say(const Clip& clip, int priority, double now, std::string text) {
  queue_.push_back({clip, priority, now, std::move(text)});
}

void Announcer::update(double now) {
  // Stale phrases go first: news that is old by the time it could be spoken is no news.
  for (auto it = queue_.begin(); it != queue_.end();) {
    if (now - it->at > stale_after_) {
      dropped.push_back(it->text);
      it = queue_.erase(it);
    } else {
      ++it;
    }
  }
  if (queue_.empty()) {
    if (current_ && !mixer_.playing(current_)) current_ = 0, current_text_.clear();
    return;
  }
  // The most urgent, and among equals the oldest.
  auto next = std::min_element(queue_.begin(), queue_.end(), [](const Waiting& a, const Waiting& b) {
    return a.priority != b.priority ? a.priority > b.priority : a.at < b.at;
  });
  const bool busy = current_ && mixer_.playing(current_);
  if (busy && next->priority <= current_priority_) return;
  if (busy) mixer_.stop(current_);  // outranked: cut off mid-phrase
  current_ = mixer_.play_at_listener(next->clip);
  current_priority_ = next->priority;
  current_text_ = next->text;
  queue_.erase(next);
}

}  // namespace quantum::audio
