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
  queue_.make(16);
  fates_.make(16);
}

PhraseFate& Announcer::settle(uint64_t id, PhraseFate::Kind kind, PhraseFate::Why why, double length,
                              std::string_view by) {
  PhraseFate& f = fates_.next();
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

void Announcer::drop(size_t k, PhraseFate::Why why, std::string_view by) {
  settle(queue_[k].id, PhraseFate::Kind::Dropped, why, queue_[k].clip->seconds(), by);
  queue_.erase(k);
}

void Announcer::say(const Clip& clip, int priority, double now, std::string_view text, uint64_t id, bool supersedable) {
  const uint64_t follows = now == last_at_ ? last_id_ : 0;
  last_id_ = id, last_at_ = now;
  // The same words again, just said or still to come, tell a listener nothing new.
  const auto waiting = [&] {
    return std::any_of(queue_.begin(), queue_.end(), [&](const Waiting& w) { return w.text == text; });
  };
  if (rules_.repeat_gap > 0 && ((now - last_started_at_ < rules_.repeat_gap && last_started_ == text) || waiting())) {
    settle(id, PhraseFate::Kind::Dropped, PhraseFate::Why::Repeat, clip.seconds(), text);
    return;
  }
  for (size_t k = 0; k < queue_.size();)
    if (queue_[k].supersedable && queue_[k].priority <= priority) drop(k, PhraseFate::Why::Superseded, text);
    else ++k;
  mixer_.prepare(clip);
  Waiting& w = queue_.next();
  w.clip = &clip, w.priority = priority, w.at = now, w.id = id, w.follows = follows, w.supersedable = supersedable;
  w.text.assign(text);
}

void Announcer::update(double now) {
  if (current_ && !mixer_.playing(current_))
    end_current(PhraseFate::Kind::Spoken, PhraseFate::Why::None, {}, current_start_ + current_length_);
  // Stale phrases go first: news that is old by the time it could be spoken is no news.
  for (size_t k = 0; k < queue_.size();)
    if (now - queue_[k].at > rules_.stale_after && queue_[k].priority < rules_.keep_from) drop(k, PhraseFate::Why::Stale, {});
    else ++k;
  if (queue_.empty()) return;
  // The most urgent, and among equals the oldest.
  Waiting* next = std::min_element(queue_.begin(), queue_.end(), [](const Waiting& a, const Waiting& b) {
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
  for (Waiting& w : queue_)
    if (w.follows == current_id_) w.at = now;
  last_started_.assign(next->text);
  last_started_at_ = now;
  queue_.erase(next);
}

void Announcer::finish(double now) {
  update(now);
  while (!queue_.empty()) drop(0, PhraseFate::Why::Ended, {});
  if (!current_) return;
  mixer_.stop(current_);
  end_current(PhraseFate::Kind::Cut, PhraseFate::Why::Ended, {}, now);
}

}  // namespace quantum::audio
