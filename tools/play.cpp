#include "play.h"

#include "desk.h"
#include "interrupts.h"
#include "lua_sport.h"
#include "quantum/limits.h"
#include "version.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <sstream>

namespace quantum::tools {

runtime::SessionOptions::Pacing pacing(const std::string& pace) {
  if (pace == "realtime") return runtime::SessionOptions::Pacing::RealTime;
  if (pace == "fast") return runtime::SessionOptions::Pacing::Fast;
  throw std::invalid_argument("--pace must be realtime or fast, not '" + pace + "'");
}

std::vector<double> parse_list(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw std::invalid_argument(option + ": '" + item + "' is not a number (expected e.g. 0.3,0.9)");
    out.push_back(v);
  }
  return out;
}

std::vector<double> parse_skills(const std::string& text) {
  std::vector<double> skills = parse_list(text, "--skill");
  for (double s : skills)
    if (!limits::kSkill.contains(s))
      throw std::invalid_argument("--skill: each skill must be in " + limits::interval(limits::kSkill) + ", got " + text);
  return skills;
}

std::optional<Vec2> parse_field_size(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::vector<double> lw = parse_list(text, "--field-size");
  if (lw.size() != 2 || !(lw[0] > 0 && lw[1] > 0 && lw[0] < 1000 && lw[1] < 1000))
    throw std::invalid_argument("--field-size needs L,W in metres, both > 0 (e.g. 2.0,1.0)");
  return Vec2{float(lw[0]), float(lw[1])};
}

namespace {

// " (blue wins)", " (draw)"; a match that stopped before its end (a recording over, --until) is
// no draw: " (not finished: blue ahead)", " (not finished: level)".
std::string outcome(const PlayResult& result) {
  if (result.finished) return result.winner.empty() ? " (draw)" : " (" + result.winner + " wins)";
  std::string ahead;
  int most = 0, level = 0;
  for (const auto& [team, goals] : result.score) {
    if (ahead.empty() || goals > most) ahead = team, most = goals, level = 0;
    if (goals == most) ++level;
  }
  return level > 1 || ahead.empty() ? " (not finished: level)" : " (not finished: " + ahead + " ahead)";
}

}  // namespace

Counted counted(const Field& field) {
  Counted c;
  c.goals = !field.goals.empty();
  if (field.catching()) c.play = Counted::Play::Holds;
  else if (std::any_of(field.bodies.begin(), field.bodies.end(), [](const BodySpec& b) { return b.hits; }))
    c.play = Counted::Play::Hits;
  return c;
}

Figures& Figures::operator+=(const Figures& o) {
  rallies += o.rallies, contacts += o.contacts, goals += o.goals, passes += o.passes;
  possessions += o.possessions, points += o.points, seconds += o.seconds;
  return *this;
}

Figures PlayResult::figures() const {
  int points = 0;
  for (const auto& [team, n] : score) points += n;
  return {stats.rallies, stats.contacts, stats.goals, stats.passes, stats.possessions, points, stats.seconds};
}

std::string describe(const Counted& counted, const Figures& f) {
  const auto per = [](double n, double of) { return of > 0 ? n / of : 0.0; };
  char buf[200];
  switch (counted.play) {
    case Counted::Play::Strikes: std::snprintf(buf, sizeof buf, "contacts per rally %.2f", per(f.contacts, f.rallies)); break;
    case Counted::Play::Hits: std::snprintf(buf, sizeof buf, "touches per rally %.2f", per(f.contacts, f.rallies)); break;
    case Counted::Play::Holds:
      std::snprintf(buf, sizeof buf, "passes per possession %.2f", per(f.passes, f.possessions));
      break;
  }
  std::string text = buf;
  if (counted.goals) {
    std::snprintf(buf, sizeof buf, ", goals per minute %.2f", per(f.goals * 60.0, f.seconds));
    text += buf;
  }
  // A sport whose score is not its goals (basketball's points, volleyball's rallies won) says its own.
  if (!counted.goals || f.points != f.goals) {
    std::snprintf(buf, sizeof buf, ", points per minute %.2f (the sport's score)", per(f.points * 60.0, f.seconds));
    text += buf;
  }
  return text;
}

PlayResult result_of(const runtime::Session& session) {
  const game::Match& match = session.match();
  return {match.score(), match.winner(), match.stats(), session.rule_errors(), match.finished(), counted(match.field()),
          session.interrupted(), nullptr, {}};
}

void finish_and_keep(runtime::Session& session, PlayResult& result) {
  try {
    session.finish();
  } catch (const std::exception&) {
    result.unwritten = std::current_exception();
  }
  const std::exception_ptr unwritten = result.unwritten;
  result = result_of(session);
  result.unwritten = unwritten;
  result.written = session.written();
}

std::unique_ptr<runtime::ProgressLine> match_progress(const runtime::Session& session, const Telling* telling,
                                                      std::ostream& errors, const std::string& what) {
  if (!telling || session.real_time() || (telling->terminal && telling->transcript_there)) return nullptr;
  return std::make_unique<runtime::ProgressLine>(errors, telling->terminal, what, session.planned_end().seconds, "s", 1);
}

PlayResult play(const runtime::SessionOptions& options, std::ostream& out, std::ostream& errors, bool transcript,
                const DeskOptions* desk, const Telling* telling) {
  PlayResult result;
  if (desk && desk->wanted()) {
#if QUANTUM_WITH_DESK
    result = play_at_desk(options, *desk, out, errors, transcript, telling);
#else
    throw std::invalid_argument("--view, --video, --snapshot and --input mouse: " +
                                runtime::built_without(runtime::Module::Desk));
#endif
  } else {
    runtime::Session session(options, tools::lua_sport, transcript ? &out : nullptr, errors);
    runtime::end_matches_on_signals();
    const std::unique_ptr<runtime::ProgressLine> progress = match_progress(session, telling, errors, "match");
    while (session.frame())
      if (progress) (*progress)(session.match().time());
    if (progress) progress->clear();
    finish_and_keep(session, result);
  }
  if (transcript) {
    out << "final score:";
    for (const auto& [team, goals] : result.score) out << ' ' << team << ' ' << goals;
    out << outcome(result) << '\n';
    char played[64];
    std::snprintf(played, sizeof played, ", %.0f s played\n", result.stats.seconds);
    out << "rallies " << result.stats.rallies << ", " << describe(result.counted, result.figures()) << played;
    out.flush();
  }
  if (telling)
    for (const runtime::Written& w : result.written) runtime::say_written(errors, w);
  if (result.unwritten) std::rethrow_exception(result.unwritten);
  return result;
}

}  // namespace quantum::tools
