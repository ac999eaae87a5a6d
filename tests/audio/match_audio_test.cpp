// A match's sound through `play`: the sport's audio settings, and what happens when they are wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sndfile.h>

#include "audio/audio.h"
#include "play.h"
#include "session.h"
#include "scripted_rules.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// Air hockey with an `audio` table of our own.
std::string sport_with_audio(const std::string& name, const std::string& audio) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_audio_sport_" + name);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua", fs::copy_options::overwrite_existing);
  std::ifstream in(QUANTUM_SOURCE_DIR "/rules/airhockey/sport.lua");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.rfind("return sport"), 12, "sport.audio = " + audio + "\nreturn sport");
  std::ofstream(dir / "sport.lua") << s;
  return dir.string();
}

tools::PlayResult play_to(const std::string& sport, const std::string& wav, std::ostringstream& errors) {
  runtime::SessionOptions o;
  o.sport = sport;
  o.seconds = 10;
  o.audio = "wav:" + wav;
  std::ostringstream out;
  return tools::play(o, out, errors, false);
}

// Players who stand where the field starts them.
class StillPlayers final : public runtime::PlayerSource {
 public:
  explicit StillPlayers(const Field& f) {
    for (const BodySpec& b : f.bodies) still_.push_back({b.start, {0, 0}});
  }
  Status advance(double, const game::Match&, bool) override { return Status::Ready; }
  std::span<const BodyInput> bodies() const override { return still_; }

 private:
  std::vector<BodyInput> still_;
};

TEST(MatchAudio, AMatchIsHeardInItsWavFile) {
  const std::string wav = (fs::temp_directory_path() / "quantum_match_audio.wav").string();
  std::ostringstream errors;
  play_to(QUANTUM_SOURCE_DIR "/rules/airhockey", wav, errors);
  EXPECT_EQ(errors.str(), "");
  const audio::Clip heard = audio::load_clip(wav);
  EXPECT_EQ(heard.rate, 44100);
  EXPECT_GT(heard.seconds(), 10.0);
  double energy = 0;
  for (int16_t s : heard.samples) energy += double(s) * s;
  EXPECT_GT(std::sqrt(energy / heard.samples.size()) / 32768, 0.01);  // speech and sounds, not silence
}

// The whole path from the core's decision to the speakers: the puck is sent into the left wall
// (y = +0.5, on the listener's left), the core realizes the bounce, the match announces it, and
// the sport's wall sound plays there. Nothing else makes a sound in this scene.
TEST(MatchAudio, ABounceOffTheLeftWallIsHeardOnTheLeft) {
  const std::string wav = (fs::temp_directory_path() / "quantum_bounce_left.wav").string();
  runtime::SessionOptions o;
  o.sport = QUANTUM_SOURCE_DIR "/rules/airhockey";
  o.particles = 200;
  o.audio = "wav:" + wav;
  std::ostringstream warnings;
  const Field field = lua::ScriptedRules(o.sport).spec().field;
  runtime::Session session(o, tools::lua_sport, nullptr, warnings, std::make_unique<StillPlayers>(field));
  int bounces = 0;
  session.watch([&](const runtime::News& news) {
    for (const game::GameEvent& e : news.events) bounces += e.type == game::EventKind::Bounce && e.actor == "left wall";
  });
  Cloud ball;
  ball.push(0.3f, 0.2f, 0.0f, 1.5f, 1, 1);
  session.match().set_scene(session.players().bodies(), ball, 0);
  for (int frame = 0; frame < 30; ++frame) session.frame();  // 0.5 s: the bounce back reaches the right wall at 0.87 s
  session.finish();
  ASSERT_EQ(bounces, 1);  // the whole puck bounced: certain
  EXPECT_EQ(warnings.str(), "");

  SF_INFO info{};
  SNDFILE* f = sf_open(wav.c_str(), SFM_READ, &info);
  ASSERT_NE(f, nullptr) << sf_strerror(nullptr);
  ASSERT_EQ(info.channels, 2);
  std::vector<short> stereo(size_t(info.frames) * 2);
  sf_readf_short(f, stereo.data(), info.frames);
  sf_close(f);
  double left = 0, right = 0;
  for (size_t i = 0; i + 1 < stereo.size(); i += 2) left += double(stereo[i]) * stereo[i], right += double(stereo[i + 1]) * stereo[i + 1];
  EXPECT_GT(std::sqrt(left / info.frames) / 32768, 0.005);  // the bounce is heard at all
  EXPECT_GT(left, 9 * right) << "left " << left << ", right " << right;  // and from the left: 3x in amplitude
}

TEST(MatchAudio, AnUnknownVoiceAndAMissingSoundFallBackWithOneWarningEach) {
  const std::string sport = sport_with_audio("fallback", R"({ voice = "klingon-xx", sounds = { shot = "no-such.wav" } })");
  const std::string wav = (fs::temp_directory_path() / "quantum_match_fallback.wav").string();
  std::ostringstream errors;
  const tools::PlayResult r = play_to(sport, wav, errors);
  const std::string e = errors.str();
  EXPECT_NE(e.find("unknown espeak-ng voice 'klingon-xx'; speaking with the default voice"), std::string::npos) << e;
  EXPECT_NE(e.find("no-such.wav"), std::string::npos) << e;
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 2) << e;  // once each, not once per use
  EXPECT_GT(r.stats.seconds, 9.9);
  EXPECT_TRUE(fs::exists(wav));
}

TEST(MatchAudio, BadAudioSettingsInASportAreNamed) {
  try {
    lua::ScriptedRules s(sport_with_audio("bad", R"({ listener = "centre" })"));
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("audio.listener: expected a point"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace quantum
