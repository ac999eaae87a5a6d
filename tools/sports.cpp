#include "sports.h"

#include <ostream>

#include "engine_paths.h"
#include "scripted_rules.h"

namespace quantum::tools {

int list_sports(std::ostream& out) {
  out << "Sports by name (the current folder first, then QUANTUM_PATH, then the engine's in "
      << lua::engine_rules_folder().string() << "):\n";
  int broken = 0;
  for (const lua::SportPlace& place : lua::sports_in_reach()) {
    out << "\n" << place.name << "  (" << place.folder.string() << ")";
    if (place.shadowed) {
      out << "\n  shadowed: the name plays the one listed before; play this one by its folder\n";
      continue;
    }
    try {
      const lua::ScriptedRules sport(place.folder.string());
      out << "\n  " << sport.spec().name << "\n  players:";
      // Grouped by team, in field order: the names --input mouse:PLAYER and --handicap take.
      const std::vector<BodySpec>& bodies = sport.spec().field.bodies;
      for (size_t k = 0; k < bodies.size(); ++k) {
        const bool new_team = k == 0 || bodies[k].team != bodies[k - 1].team;
        out << (k == 0 ? " " : new_team ? "; " : ", ");
        if (new_team) out << (bodies[k].team.empty() ? "no team" : bodies[k].team) << ": ";
        out << bodies[k].name;
      }
      out << "\n  params:";
      if (sport.params().read().empty()) out << " none";
      for (const auto& [name, default_text] : sport.params().read()) out << " " << name << "=" << default_text;
      out << '\n';
    } catch (const std::exception& e) {
      out << "\n  does not load: " << e.what() << '\n';
      ++broken;
    }
  }
  return broken;
}

}  // namespace quantum::tools
