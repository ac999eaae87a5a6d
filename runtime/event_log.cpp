#include "event_log.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "json_lines.h"

namespace quantum::runtime {
namespace {

void write_phrase(JsonLine& line, const game::Said& s, const audio::PhraseFate& f) {
  line.object().field("text", s.text).field("fate", audio::to_string(f.kind));
  if (f.start >= 0) line.field("start", f.start).field("end", f.end).field("length", f.length);
  if (f.why != audio::PhraseFate::Why::None) line.field("why", audio::to_string(f.why));
  if (!f.by.empty()) line.field("by", f.by);
  line.close();
}

// The phrases of said[from, to) that `belongs` picks: their words, then what became of them.
template <class Belongs>
void write_said(JsonLine& line, std::span<const game::Said> said, std::span<const audio::PhraseFate> fates,
                size_t from, size_t to, Belongs belongs) {
  bool any = false;
  for (size_t i = from; i < to; ++i) {
    if (!belongs(said[i])) continue;
    if (!any) line.array("said"), any = true;
    line.item(said[i].text);
  }
  if (!any) return;
  line.close();
  if (fates.empty()) return;
  line.array("phrases");
  for (size_t i = from; i < to; ++i)
    if (belongs(said[i])) write_phrase(line, said[i], fates[i]);
  line.close();
}

}  // namespace

void write_events(std::ostream& out, std::span<const game::GameEvent> events, std::span<const game::Said> said,
                  std::span<const audio::PhraseFate> fates) {
  for (size_t k = 0; k < events.size(); ++k) {
    const game::GameEvent& e = events[k];
    JsonLine line(out);
    line.field("t", e.t).field("type", game::to_string(e.type)).field("actor", e.actor);
    if (!e.team.empty()) line.field("team", e.team);
    if (!e.by.empty()) line.field("by", e.by);
    if (!e.previous.empty()) line.field("previous", e.previous);
    if (!e.powerup.empty()) line.field("powerup", e.powerup);
    if (!e.holder.empty()) line.field("holder", e.holder);
    line.field("p", e.p).field("p_newtonian", e.p_newtonian).field("particles", uint64_t(e.particles));
    line.field("x", double(e.at.x)).field("y", double(e.at.y));
    write_said(line, said, fates, 0, said.size(), [k](const game::Said& s) { return s.event == int(k); });
    line.end();
  }
  // Phrases of no event (a timer's, on_reload's): those said at one moment share a line.
  for (size_t i = 0; i < said.size(); ++i) {
    if (said[i].event >= 0 || (i > 0 && said[i - 1].event < 0 && said[i - 1].t == said[i].t)) continue;
    size_t j = i;
    while (j < said.size() && said[j].event < 0 && said[j].t == said[i].t) ++j;
    JsonLine line(out);
    line.field("t", said[i].t).field("type", *said[i].cause ? said[i].cause : "said");
    write_said(line, said, fates, i, j, [](const game::Said&) { return true; });
    line.end();
  }
}

namespace {

const char* kind_of(Target t) {
  switch (t.kind) {
    case TargetKind::Body: return "body";
    case TargetKind::Goal: return "goal";
    case TargetKind::Out: return "out";
    case TargetKind::Wall: return "wall";
    case TargetKind::Landing: return "landing";
    case TargetKind::Tackle: return "tackle";
    case TargetKind::Crushed: break;
  }
  return "crushed";
}

}  // namespace

namespace {

const char* source_name(game::FactorTerm::Source s) {
  switch (s) {
    case game::FactorTerm::Source::Sport: return "sport";
    case game::FactorTerm::Source::Modifier: return "modifier";
    case game::FactorTerm::Source::Powerup: return "powerup";
    case game::FactorTerm::Source::Handicap: return "handicap";
  }
  return "?";
}

// "factor" and "factors" of terms.of(k), when the terms cover k.
void write_factor(JsonLine& line, double factor, const DrawTerms& terms, size_t k, const Field& field) {
  line.exact("factor", factor);
  if (k >= terms.terms.fates()) return;
  line.array("factors");
  for (const game::FactorTerm& t : terms.terms.of(k)) {
    line.object().field("source", source_name(t.source));
    switch (t.source) {
      case game::FactorTerm::Source::Sport: break;
      case game::FactorTerm::Source::Modifier: line.field("index", t.index); break;
      case game::FactorTerm::Source::Powerup:
        if (t.index >= 0 && size_t(t.index) < terms.powerups.size()) line.field("name", terms.powerups[size_t(t.index)]);
        if (t.player >= 0) line.field("holder", field.bodies[size_t(t.player)].name);
        if (t.has_strength) line.exact("strength", t.strength);
        break;
      case game::FactorTerm::Source::Handicap:
        if (t.player >= 0) line.field("player", field.bodies[size_t(t.player)].name);
        else line.field("team", t.team);
        break;
    }
    line.exact("value", t.value).close();
  }
  line.close();
}

}  // namespace

void write_decision(std::ostream& out, const Decision& d, const DrawTerms& terms, const Field& field) {
  JsonLine line(out);
  line.exact("t", d.t).exact("u", d.u).array("draw");
  for (size_t k = 0; k < d.options.size(); ++k) {
    const Decision::Option& o = d.options[k];
    line.object().field("kind", kind_of(o.target)).field("actor", target_name(o.target, field))
        .exact("p", o.chance).exact("p_newtonian", o.chance_newtonian).field("particles", uint64_t(o.particles));
    if (o.target.kind == TargetKind::Tackle) {
      write_factor(line, o.factor, terms, k, field);
      line.close();
      continue;
    }
    line.exact("mass", o.mass);
    if (const int c = contact_index(o.target, field); c >= 0)
      write_factor(line, o.factor, terms, terms.contacts_from + size_t(c), field);
    line.exact("weight", o.weight).array("groups");
    for (uint32_t s = o.first_share; s < o.first_share + o.shares; ++s) {
      const Decision::Share& share = d.shares[s];
      line.array().exact(share.fate == Cloud::kNoFate ? -1.0 : double(share.fate)).exact(share.mass)
          .exact(double(share.particles)).close();
    }
    line.close().close();
  }
  line.close();
  const bool tackles = !d.options.empty() && d.options[0].target.kind == TargetKind::Tackle;
  if (!tackles)
    line.object("rest").exact("mass", d.rest_mass).exact("weight", d.rest_weight).close().field("all_met", d.all_met);
  line.field("outcome", d.realized < 0 ? std::string_view("none") : target_name(d.options[size_t(d.realized)].target, field));
  if (terms.terms.skipped()) line.field("factors_skipped", true);
  line.array("fates");
  for (size_t g = 0; g < d.fates.size(); ++g) {
    const FateGroup& group = d.fates[g];
    char via[256];
    const Fate& f = group.fate;
    line.object().field("kind", to_string(f.kind)).field("actor", fate_actor(f, field))
        .field("via", std::string_view(via, write_via(f, field, via, sizeof via)))
        .exact("mass", group.mass).exact("tweaked", group.tweaked_mass).field("particles", uint64_t(group.count));
    write_factor(line, d.fate_factors[g], terms, g < terms.contacts_from ? g : terms.terms.fates(), field);
    line.close();
  }
  line.end();
}

void write_transcript(std::ostream& out, std::span<const game::Said> said, std::span<const audio::PhraseFate> fates) {
  for (size_t i = 0; i < said.size(); ++i) {
    const game::Said& s = said[i];
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%4d:%05.2f", int(s.t / 60), std::fmod(s.t, 60.0));
    out << stamp << "  " << s.text;
    if (!fates.empty()) {
      const audio::PhraseFate& f = fates[i];
      char mark[96] = "";
      if (f.kind == audio::PhraseFate::Kind::Cut)
        std::snprintf(mark, sizeof mark, "  [cut after %.2f of %.2f s, %s", f.end - f.start, f.length, audio::to_string(f.why));
      else if (f.kind == audio::PhraseFate::Kind::Dropped)
        std::snprintf(mark, sizeof mark, "  [dropped, %s", audio::to_string(f.why));
      if (*mark) out << mark << (f.by.empty() ? "" : ": ") << f.by << ']';
    }
    out << '\n';
  }
}

}  // namespace quantum::runtime
