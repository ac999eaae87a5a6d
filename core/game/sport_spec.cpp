#include "game/sport_spec.h"

namespace quantum::game {

std::string SportSpec::team_name(std::string_view team) const {
  const auto it = team_names.find(team);
  return std::string(it == team_names.end() ? team : std::string_view(it->second));
}

void say_host(const SportSpec& sport, Match& match, std::string_view key, std::string_view fallback) {
  const auto phrase = sport.phrases.find(key);
  if (phrase == sport.phrases.end()) return match.say(fallback);
  const auto recorded = sport.audio.recorded.find(key);
  match.say(phrase->second, recorded == sport.audio.recorded.end() ? std::string_view() : std::string_view(recorded->second));
}

}  // namespace quantum::game
