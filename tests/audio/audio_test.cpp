// Sound, rendered to memory through OpenAL Soft's loopback device: assertions are on samples.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "audio/audio.h"

namespace quantum::audio {
namespace {

constexpr int kRate = 44100;

struct Levels {
  double left = 0, right = 0;
};

Levels rms(const std::vector<int16_t>& stereo) {
  Levels l;
  const size_t frames = stereo.size() / 2;
  for (size_t i = 0; i < frames; ++i) {
    l.left += double(stereo[2 * i]) * stereo[2 * i];
    l.right += double(stereo[2 * i + 1]) * stereo[2 * i + 1];
  }
  l.left = std::sqrt(l.left / frames) / 32768, l.right = std::sqrt(l.right / frames) / 32768;
  return l;
}

Clip sound(const std::string& name) { return load_clip(QUANTUM_SOURCE_DIR "/sounds/" + name); }

// Air hockey's listener: the table's centre, facing Red's end, so "left wall" (y > 0) is left.
Levels render_at(Vec2 at) {
  auto mixer = Mixer::open_loopback(kRate);
  mixer->set_listener({{0, 0}, {1, 0}});
  mixer->play(sound("wall.wav"), at);
  std::vector<int16_t> out;
  mixer->render(kRate / 10, out);
  return rms(out);
}

TEST(Audio, SoundsArePlacedWhereTheyHappen) {
  const Levels left = render_at({0.2f, 0.5f}), right = render_at({0.2f, -0.5f});
  EXPECT_GT(left.left, 0.01);
  EXPECT_GT(left.left, 3 * left.right) << left.left << " " << left.right;
  EXPECT_GT(right.right, 3 * right.left) << right.left << " " << right.right;
}

TEST(Audio, GameSoundsLoadAsShortMonoClips) {
  for (const char* name : {"hit.wav", "wall.wav", "goal.wav", "whistle.wav"}) {
    const Clip c = sound(name);
    EXPECT_EQ(c.rate, 22050) << name;
    EXPECT_GT(c.seconds(), 0.02) << name;
    EXPECT_LT(c.seconds(), 2.0) << name;
  }
}

TEST(Audio, MissingFileIsNamed) {
  try {
    load_clip("/nonexistent/horn.wav");
    FAIL() << "no error";
  } catch (const AudioError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/horn.wav"), std::string::npos) << e.what();
  }
}

TEST(Audio, WavFilesRoundTrip) {
  const std::string path = (std::filesystem::temp_directory_path() / "quantum_audio_test.wav").string();
  std::vector<int16_t> stereo;
  for (int i = 0; i < 2205; ++i) stereo.push_back(int16_t(i)), stereo.push_back(int16_t(-i));
  write_wav(path, stereo, 22050);
  const Clip back = load_clip(path);  // mixed down to mono: the channels cancel
  EXPECT_EQ(back.rate, 22050);
  ASSERT_EQ(back.samples.size(), 2205u);
  for (int16_t s : back.samples) EXPECT_LE(std::abs(int(s)), 1);
  EXPECT_THROW(write_wav("/nonexistent/dir/x.wav", stereo, 22050), AudioError);
}

class SpeechTest : public ::testing::Test {
 protected:
  static Speech& speech() {
    static Speech s;  // espeak-ng has global state: one per process
    return s;
  }
};

TEST_F(SpeechTest, AGoalIsSpokenAudiblyForAPlausibleTime) {
  const Clip& c = speech().say("Goal for Blue!", Voice{});
  // About a second and a half at 175 words per minute; espeak-ng varies slightly between calls.
  EXPECT_GT(c.seconds(), 0.5);
  EXPECT_LT(c.seconds(), 3.0);
  auto mixer = Mixer::open_loopback(kRate);
  mixer->play_at_listener(c);
  std::vector<int16_t> out;
  mixer->render(int(c.seconds() * kRate), out);
  const Levels l = rms(out);
  EXPECT_GT(l.left, 0.01);
  EXPECT_NEAR(l.left, l.right, 0.1 * l.left);  // spoken at the listener's ears: centred
}

TEST_F(SpeechTest, PhrasesAreCachedAndVoicesMatter) {
  const Clip* first = &speech().say("Red shoots", Voice{});
  EXPECT_EQ(first, &speech().say("Red shoots", Voice{}));
  const Clip& fast = speech().say("Red shoots", Voice{"en", 350, 100});
  EXPECT_LT(fast.seconds(), first->seconds());
}

TEST_F(SpeechTest, UnknownVoiceAndBadSettingsAreNamed) {
  try {
    speech().say("hello", Voice{"klingon-xx", 175, 100});
    FAIL() << "no error";
  } catch (const AudioError& e) {
    EXPECT_NE(std::string(e.what()).find("klingon-xx"), std::string::npos) << e.what();
  }
  EXPECT_THROW(speech().say("hello", Voice{"en", 10, 100}), AudioError);
  EXPECT_THROW(speech().say("hello", Voice{"en", 175, 500}), AudioError);
}

TEST(Announcer, AGoalCutsOffAShotBeingAnnounced) {
  auto mixer = Mixer::open_loopback(kRate);
  Announcer a(*mixer);
  Clip shot{std::vector<int16_t>(kRate, 1000), kRate};  // one second
  Clip goal{std::vector<int16_t>(kRate / 2, 2000), kRate};
  std::vector<int16_t> out;
  a.say(shot, 1, 0.0, "Red shoots");
  a.update(0.0);
  EXPECT_EQ(a.speaking(), "Red shoots");
  mixer->render(kRate / 10, out);
  a.say(goal, 3, 0.1, "Goal!");
  a.update(0.1);
  EXPECT_EQ(a.speaking(), "Goal!");
  mixer->render(kRate / 10, out);
  // Only the goal plays now: the level of the goal alone, not of both together (1.5 times it).
  auto reference = Mixer::open_loopback(kRate);
  reference->play_at_listener(goal);
  std::vector<int16_t> alone;
  reference->render(kRate / 10, alone);
  EXPECT_NEAR(rms(out).left, rms(alone).left, 0.1 * rms(alone).left);
  EXPECT_GT(rms(alone).left, 0.01);
}

TEST(Announcer, EqualPriorityWaitsAndStalePhrasesAreDropped) {
  auto mixer = Mixer::open_loopback(kRate);
  Announcer a(*mixer, 1.5);
  Clip long_phrase{std::vector<int16_t>(3 * kRate, 1000), kRate};  // three seconds
  Clip short_phrase{std::vector<int16_t>(kRate / 4, 1000), kRate};
  std::vector<int16_t> out;
  a.say(long_phrase, 1, 0.0, "a long story");
  a.update(0.0);
  a.say(short_phrase, 1, 0.2, "Blue shoots");
  a.update(0.2);
  EXPECT_EQ(a.speaking(), "a long story");  // same priority: waits its turn
  for (int k = 1; k <= 20; ++k) {  // two seconds pass
    mixer->render(kRate / 10, out);
    a.update(0.2 + 0.1 * k);
  }
  EXPECT_EQ(a.speaking(), "a long story");
  ASSERT_EQ(a.dropped().size(), 1u);  // 1.5 s old by then: dropped, never spoken
  EXPECT_EQ(a.dropped()[0], "Blue shoots");
}

}  // namespace
}  // namespace quantum::audio
