#include "phrase_ledger.h"

#include <algorithm>

#include "event_log.h"

namespace quantum::runtime {
namespace {

// A new slot's strings get room for a long phrase: a phrase longer than any before would
// otherwise allocate in the frame that holds it (a string's copy keeps the room it has).
constexpr size_t kPhraseRoom = 128;
void make_room(game::Said& s) { s.text.reserve(kPhraseRoom); }
void make_room(audio::PhraseFate& f) { f.by.reserve(kPhraseRoom); }
template <class T>
void make_room(T&) {}

template <class T>
T& slot(std::vector<T>& v, size_t& n) {
  if (n == v.size()) make_room(v.emplace_back());
  return v[n++];
}

// Drops the first `n` of the first `used` slots, keeping them (and their strings' room) behind.
template <class T>
void forget(std::vector<T>& v, size_t n, size_t& used) {
  std::rotate(v.begin(), v.begin() + long(n), v.begin() + long(used));
  used -= n;
}

}  // namespace

void PhraseLedger::hold(std::span<const game::GameEvent> events, std::span<const game::Said> said) {
  if (events.empty() && said.empty()) return;
  slot(frames_, n_frames_) = {events.size(), said.size()};
  for (const game::GameEvent& e : events) slot(events_, n_events_) = e;
  for (const game::Said& s : said) {
    slot(said_, n_said_) = s;  // a string's copy keeps its room
    if (fates_.size() < n_said_) make_room(fates_.emplace_back());
    fates_[n_said_ - 1].id = 0;  // unsettled
  }
  next_id_ += said.size();
}

void PhraseLedger::settle(std::span<const audio::PhraseFate> fates) {
  for (const audio::PhraseFate& f : fates) {
    if (f.id < first_id_ || f.id >= first_id_ + n_said_) continue;  // not held (a spec's phrase already written)
    fates_[f.id - first_id_] = f;
  }
}

void PhraseLedger::write(std::ostream* log, std::ostream* transcript, bool all) {
  size_t frames = 0, events = 0, said = 0;
  for (; frames < n_frames_; ++frames) {
    const Frame& f = frames_[frames];
    const bool settled = std::all_of(fates_.begin() + long(said), fates_.begin() + long(said + f.said),
                                      [](const audio::PhraseFate& p) { return p.id != 0; });
    if (!settled && !all) break;
    for (size_t k = said; k < said + f.said; ++k) {  // the match ended before the announcer said
      audio::PhraseFate& p = fates_[k];
      if (p.id != 0) continue;
      p = audio::PhraseFate{};
      p.id = first_id_ + k, p.kind = audio::PhraseFate::Kind::Dropped, p.why = audio::PhraseFate::Why::Ended;
    }
    const std::span<const game::GameEvent> e(events_.data() + events, f.events);
    const std::span<const game::Said> s(said_.data() + said, f.said);
    const std::span<const audio::PhraseFate> p(fates_.data() + said, f.said);
    if (log) write_events(*log, e, s, p);
    if (transcript) write_transcript(*transcript, s, p);
    events += f.events, said += f.said;
  }
  forget(frames_, frames, n_frames_);
  forget(events_, events, n_events_);
  size_t held = n_said_;
  forget(said_, said, n_said_);
  forget(fates_, said, held);
  first_id_ += said;
}

}  // namespace quantum::runtime
