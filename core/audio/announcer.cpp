#include <algorithm>

#include "audio/audio.h"

namespace quantum::audio {

const char* to_string(PhraseFate::Kind kind) {
  switch (kind) {
    case PhraseFate::Kind::Spoken: return "spoken";
    case PhraseFate::Kind::Cut: return "cut";
    case PhraseFate::Kind::Dropped: return "dropped";
    case PhraseFate::Kind::Silent: break;
  }
  return "silent";
}

const char* to_string(PhraseFate::Why why) {
  switch (why) {
    case PhraseFate::Why::None: return "";
    case PhraseFate::Why::Outranked: return "outranked";
    case PhraseFate::Why::Stale: return "stale";
    case PhraseFate::Why::Superseded: return "superseded";
    case PhraseFate::Why::Repeat: return "repeat";
    case PhraseFate::Why::Ended: break;
  }
  return "ended";
}

// Room for a busy stretch of play: phrases waiting and fates to report keep
// their slots (and their text's room) once made, so a running match allocates nothing here.
Announcer::Announcer(Mixer& mixer, AnnouncerRules rules) : mixer_(mixer), rules_(rules) {
  queue_.resize(16);
  fates_.resize(16);
}

PhraseFate& Announcer::settle(uint64_t id, PhraseFate::Kind kind, PhraseFate::Why why, double length,
                              std::string_view by) {
  if (n_fates_ == fates_.size()) fates_.emplace_back();
  PhraseFate& f = fates_[n_fates_++];
  f.id = id, f.kind = kind, f.why = why, f.length = length, f.start = f.end = -1;
  f.by.assign(by);
  return f;
}

void Announcer::end_current(PhraseFate::Kind kind, PhraseFate::Why why, std::string_view by, double end) {
  PhraseFate& f = settle(current_id_, kind, why, current_length_, by);
  f.start = current_start_, f.end = end;
  current_ = 0;
  current_text_.clear();
}

// Slots are rotated, never copied, so every string keeps its room.
void Announcer::drop(size_t k, PhraseFate::Why why, std::string_view by) {
  settle(queue_[k].id, PhraseFate::Kind::Dropped, why, queue_[k].clip->seconds(), by);
  std::rotate(queue_.begin() + long(k), queue_.begin() + long(k) + 1, queue_.begin() + long(n_waiting_));
  --n_waiting_;
}

void Announcer::say(const Clip& clip, int priority, double now, std::string_view text, uint64_t id, bool supersedable) {
  const uint64_t follows = now == last_at_ ? last_id_ : 0;
  last_id_ = id, last_at_ = now;
  // The same words again, just said or still to come, tell a listener nothing new.
  const auto waiting = [&] {
    for (size_t k = 0; k < n_waiting_; ++k)
      if (queue_[k].text == text) return true;
    return false;
  };
  if (rules_.repeat_gap > 0 && ((now - last_started_at_ < rules_.repeat_gap && last_started_ == text) || waiting())) {
    settle(id, PhraseFate::Kind::Dropped, PhraseFate::Why::Repeat, clip.seconds(), text);
    return;
  }
  for (size_t k = 0; k < n_waiting_;)
    if (queue_[k].supersedable && queue_[k].priority <= priority) drop(k, PhraseFate::Why::Superseded, text);
    else ++k;
  mixer_.prepare(clip);
  if (n_waiting_ == queue_.size()) queue_.emplace_back();
  Waiting& w = queue_[n_waiting_++];
  w.clip = &clip, w.priority = priority, w.at = now, w.id = id, w.follows = follows, w.supersedable = supersedable;
  w.text.assign(text);
}

void Announcer::update(double now) {
  if (current_ && !mixer_.playing(current_))
    end_current(PhraseFate::Kind::Spoken, PhraseFate::Why::None, {}, current_start_ + current_length_);
  // Stale phrases go first: news that is old by the time it could be spoken is no news.
  for (size_t k = 0; k < n_waiting_;)
    if (now - queue_[k].at > rules_.stale_after && queue_[k].priority < rules_.keep_from) drop(k, PhraseFate::Why::Stale, {});
    else ++k;
  if (n_waiting_ == 0) return;
  // The most urgent, and among equals the oldest.
  const auto end = queue_.begin() + long(n_waiting_);
  const auto next = std::min_element(queue_.begin(), end, [](const Waiting& a, const Waiting& b) {
    return a.priority != b.priority ? a.priority > b.priority : a.at < b.at;
  });
  if (current_) {
    if (next->priority <= current_priority_) return;
    if (current_start_ + current_length_ - now <= rules_.wait_for) return;  // nearly done: let it finish
    mixer_.stop(current_);
    end_current(PhraseFate::Kind::Cut, PhraseFate::Why::Outranked, next->text, now);
  }
  current_ = mixer_.play_at_listener(*next->clip);
  current_priority_ = next->priority;
  current_id_ = next->id;
  current_start_ = now;
  current_length_ = next->clip->seconds();
  current_text_.assign(next->text);
  for (size_t k = 0; k < n_waiting_; ++k)
    if (queue_[k].follows == current_id_) queue_[k].at = now;
  last_started_.assign(next->text);
  last_started_at_ = now;
  std::rotate(next, next + 1, end);
  --n_waiting_;
}

void Announcer::finish(double now) {
  update(now);
  while (n_waiting_ > 0) drop(0, PhraseFate::Why::Ended, {});
  if (!current_) return;
  mixer_.stop(current_);
  end_current(PhraseFate::Kind::Cut, PhraseFate::Why::Ended, {}, now);
}

}  // namespace quantum::audio
