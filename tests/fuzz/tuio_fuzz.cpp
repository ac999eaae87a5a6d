// TUIO over OSC, any packet (a message or a bundle), through the same path a live tracker's
// packets take into a match (runtime::tracked_players): the bodies it moves stay finite, within
// a field's size of the field and under its speed limit; a bad packet is dropped.
#include <lo/lo.h>

#include <cmath>

#include "fuzz_support.h"
#include "field_loader.h"
#include "players.h"

namespace quantum {
namespace {

// "/tuio/2Dcur fseq n": the end of a TUIO frame, sent after the input so it is read as one.
std::vector<char> frame_end() {
  lo_message m = lo_message_new();
  lo_message_add_string(m, "fseq");
  lo_message_add_int32(m, 1);
  size_t size = 0;
  void* bytes = lo_message_serialise(m, "/tuio/2Dcur", nullptr, &size);
  std::vector<char> out(static_cast<char*>(bytes), static_cast<char*>(bytes) + size);
  free(bytes);
  lo_message_free(m);
  return out;
}

}  // namespace
}  // namespace quantum

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace quantum;
  static const Field field = lua::load_field(QUANTUM_SOURCE_DIR "/rules/airhockey");
  static fuzz::NoRules rules;
  static game::Match match(field, game::MatchConfig{}, rules);
  static const std::vector<char> end = frame_end();
  const int port = fuzz::free_port();
  const std::unique_ptr<runtime::PlayerSource> players = runtime::tracked_players("tuio:" + std::to_string(port), field);
  fuzz::send_datagram(port, data, size);
  fuzz::send_datagram(port, end.data(), end.size());
  players->advance(0, match, false);
  const float slack = std::max(field.bounds_max.x - field.bounds_min.x, field.bounds_max.y - field.bounds_min.y);
  for (const BodyInput& b : players->bodies()) {
    const bool inside = b.position.x >= field.bounds_min.x - slack && b.position.x <= field.bounds_max.x + slack &&
                        b.position.y >= field.bounds_min.y - slack && b.position.y <= field.bounds_max.y + slack;
    if (!(inside && std::hypot(b.velocity.x, b.velocity.y) < field.max_body_speed)) __builtin_trap();  // NaN fails too
  }
  return 0;
}
