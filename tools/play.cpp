#include "play.h"

#include "desk.h"

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
    if (!(s >= 0 && s <= 1)) throw std::invalid_argument("--skill: each skill must be in [0, 1], got " + text);
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

PlayResult play(const runtime::SessionOptions& options, std::ostream& out, std::ostream& errors, bool transcript,
                const DeskOptions* desk) {
  PlayResult result;
  if (desk && desk->wanted()) {
    result = play_at_desk(options, *desk, out, errors, transcript);
  } else {
    runtime::Session session(options, transcript ? &out : nullptr, errors);
    session.run();
    const game::Match& match = session.match();
    result = {match.score(), match.winner(), match.stats(), session.rule_errors(), match.finished()};
  }
  if (transcript) {
    const game::RallyStats& s = result.stats;
    out << "final score:";
    for (const auto& [team, goals] : result.score) out << ' ' << team << ' ' << goals;
    out << outcome(result) << '\n';
    char buf[200];
    std::snprintf(buf, sizeof buf, "rallies %d, contacts per rally %.2f, goals per minute %.2f, %.0f s played\n",
                  s.rallies, s.rallies ? double(s.contacts) / s.rallies : 0.0, s.seconds > 0 ? s.goals * 60 / s.seconds : 0.0,
                  s.seconds);
    out << buf;
    // A sport whose score is not its goals (basketball's points) says its own too.
    int points = 0;
    for (const auto& [team, n] : result.score) points += n;
    if (points != s.goals && s.seconds > 0) {
      std::snprintf(buf, sizeof buf, "points per minute %.2f (the sport's score)\n", points * 60 / s.seconds);
      out << buf;
    }
  }
  return result;
}

}  // namespace quantum::tools
