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
  Announcer a(*mixer, {.stale_after = 1.5});
  Clip long_phrase{std::vector<int16_t>(3 * kRate, 1000), kRate};  // three seconds
  Clip short_phrase{std::vector<int16_t>(kRate / 4, 1000), kRate};
  std::vector<int16_t> out;
  a.say(long_phrase, 1, 0.0, "a long story", 1);
  a.update(0.0);
  a.say(short_phrase, 1, 0.2, "Blue shoots", 2);
  a.update(0.2);
  EXPECT_EQ(a.speaking(), "a long story");  // same priority: waits its turn
  std::vector<PhraseFate> fates;
  for (int k = 1; k <= 20; ++k) {  // two seconds pass
    mixer->render(kRate / 10, out);
    a.clear_fates();
    a.update(0.2 + 0.1 * k);
    fates.insert(fates.end(), a.fates().begin(), a.fates().end());
  }
  EXPECT_EQ(a.speaking(), "a long story");
  ASSERT_EQ(fates.size(), 1u);  // 1.5 s old by then: dropped, never spoken
  EXPECT_EQ(fates[0].id, 2u);
  EXPECT_EQ(fates[0].kind, PhraseFate::Kind::Dropped);
  EXPECT_EQ(fates[0].why, PhraseFate::Why::Stale);
  EXPECT_EQ(fates[0].start, -1);
}

// Plays the phrases said at given times through an announcer in 1/60 s frames for `seconds`,
// and gives back every fate, in the order they were settled.
struct Said {
  double t;
  const Clip* clip;
  int priority;
  std::string text;
  bool supersedable = false;
};
std::vector<PhraseFate> announce(const AnnouncerRules& rules, const std::vector<Said>& said, double seconds) {
  auto mixer = Mixer::open_loopback(kRate);
  Announcer a(*mixer, rules);
  std::vector<int16_t> out;
  std::vector<PhraseFate> fates;
  size_t next = 0;
  for (int frame = 0; frame <= int(seconds * 60); ++frame) {
    const double now = frame / 60.0;
    a.clear_fates();
    for (; next < said.size() && said[next].t <= now + 1e-9; ++next)
      a.say(*said[next].clip, said[next].priority, now, said[next].text, next + 1, said[next].supersedable);
    a.update(now);
    mixer->render(kRate / 60, out);
    fates.insert(fates.end(), a.fates().begin(), a.fates().end());
  }
  a.clear_fates();
  a.finish(seconds);
  fates.insert(fates.end(), a.fates().begin(), a.fates().end());
  return fates;
}

const PhraseFate& fate_of(const std::vector<PhraseFate>& fates, uint64_t id) {
  for (const PhraseFate& f : fates)
    if (f.id == id) return f;
  throw std::runtime_error("no fate for phrase " + std::to_string(id));
}

TEST(Announcer, EveryPhraseGetsOneFateWithWhenItSounded) {
  Clip shot{std::vector<int16_t>(kRate, 1000), kRate, new_clip_id()};  // one second
  Clip goal{std::vector<int16_t>(kRate / 2, 2000), kRate, new_clip_id()};
  const std::vector<PhraseFate> fates = announce({}, {{0.0, &shot, 1, "Red shoots"}, {0.5, &goal, 3, "Goal!"},
                                                      {1.5, &shot, 1, "Blue shoots"}}, 1.8);
  ASSERT_EQ(fates.size(), 3u);
  const PhraseFate& cut = fate_of(fates, 1);
  EXPECT_EQ(cut.kind, PhraseFate::Kind::Cut);
  EXPECT_EQ(cut.why, PhraseFate::Why::Outranked);
  EXPECT_EQ(cut.by, "Goal!");
  EXPECT_NEAR(cut.end - cut.start, 0.5, 1e-9);  // heard for half a second of its one
  EXPECT_DOUBLE_EQ(cut.length, 1.0);
  const PhraseFate& spoken = fate_of(fates, 2);
  EXPECT_EQ(spoken.kind, PhraseFate::Kind::Spoken);
  EXPECT_NEAR(spoken.start, 0.5, 1e-9);
  EXPECT_NEAR(spoken.end, 1.0, 1e-9);
  const PhraseFate& ended = fate_of(fates, 3);  // still sounding when the match ended
  EXPECT_EQ(ended.kind, PhraseFate::Kind::Cut);
  EXPECT_EQ(ended.why, PhraseFate::Why::Ended);
}

TEST(Announcer, ANearlyFinishedPhraseIsLetFinishBeforeAMoreUrgentOne) {
  Clip shot{std::vector<int16_t>(kRate, 1000), kRate, new_clip_id()};
  Clip goal{std::vector<int16_t>(kRate / 2, 2000), kRate, new_clip_id()};
  const std::vector<Said> said{{0.0, &shot, 1, "Red shoots"}, {0.7, &goal, 3, "Goal!"}};
  // 0.3 s of the shot left when the goal comes: within wait_for 0.5 it finishes, then the goal.
  std::vector<PhraseFate> fates = announce({.wait_for = 0.5}, said, 2.0);
  EXPECT_EQ(fate_of(fates, 1).kind, PhraseFate::Kind::Spoken);
  EXPECT_EQ(fate_of(fates, 2).kind, PhraseFate::Kind::Spoken);
  EXPECT_NEAR(fate_of(fates, 2).start, 1.0, 1.0 / 60 + 1e-9);
  // Without it, the goal cuts the shot off.
  fates = announce({.wait_for = 0}, said, 2.0);
  EXPECT_EQ(fate_of(fates, 1).kind, PhraseFate::Kind::Cut);
  EXPECT_NEAR(fate_of(fates, 2).start, 0.7, 1e-9);
}

TEST(Announcer, NewerPlayByPlaySupersedesWaitingPhrasesAndRepeatsAreSkipped) {
  Clip story{std::vector<int16_t>(kRate, 1000), kRate, new_clip_id()};
  Clip shot{std::vector<int16_t>(kRate / 2, 1000), kRate, new_clip_id()};
  // While a one-second phrase is spoken, four shots come: "Blue shoots" twice, then Red, then Blue.
  const std::vector<Said> said{{0.0, &story, 2, "The puck was dropped"},
                               {0.2, &shot, 1, "Blue shoots", true},
                               {0.4, &shot, 1, "Blue shoots", true},
                               {0.6, &shot, 1, "Red shoots", true},
                               {0.8, &shot, 1, "Blue shoots", true}};
  const std::vector<PhraseFate> fates = announce({.repeat_gap = 2}, said, 3.0);
  EXPECT_EQ(fate_of(fates, 1).kind, PhraseFate::Kind::Spoken);
  EXPECT_EQ(fate_of(fates, 2).why, PhraseFate::Why::Superseded);  // by "Red shoots"
  EXPECT_EQ(fate_of(fates, 2).by, "Red shoots");
  EXPECT_EQ(fate_of(fates, 3).why, PhraseFate::Why::Repeat);  // "Blue shoots" was still waiting
  EXPECT_EQ(fate_of(fates, 4).why, PhraseFate::Why::Superseded);
  EXPECT_EQ(fate_of(fates, 5).kind, PhraseFate::Kind::Spoken);  // the latest news, at 1.0 s
  EXPECT_NEAR(fate_of(fates, 5).start, 1.0, 1.0 / 60 + 1e-9);
  // The same words right after they were spoken are skipped; after the gap they are news again.
  const std::vector<PhraseFate> again = announce(
      {.repeat_gap = 2}, {{0.0, &shot, 1, "Blue shoots"}, {1.0, &shot, 1, "Blue shoots"}, {2.5, &shot, 1, "Blue shoots"}},
      3.5);
  EXPECT_EQ(fate_of(again, 1).kind, PhraseFate::Kind::Spoken);
  EXPECT_EQ(fate_of(again, 2).why, PhraseFate::Why::Repeat);
  EXPECT_EQ(fate_of(again, 3).kind, PhraseFate::Kind::Spoken);
}

TEST(Mixer, GameSoundsDuckUnderTheAnnouncerOnly) {
  auto mixer = Mixer::open_loopback(kRate);
  Clip hit{std::vector<int16_t>(kRate, 1000), kRate, new_clip_id()};
  Clip speech{std::vector<int16_t>(kRate, 1000), kRate, new_clip_id()};
  std::vector<int16_t> out;
  mixer->play(hit, {1, 0});  // straight ahead: both channels alike
  mixer->render(kRate / 10, out);
  const double full = rms(out).left;
  mixer->duck(0.25f);
  mixer->render(kRate / 10, out);
  mixer->render(kRate / 10, out);  // past OpenAL's gain ramp
  EXPECT_NEAR(rms(out).left, 0.25 * full, 0.03 * full);
  mixer->play_at_listener(speech);  // the announcer's own level, whatever the duck
  mixer->render(kRate / 10, out);
  mixer->render(kRate / 10, out);
  const double both = rms(out).left;
  mixer->duck(1);
  mixer->render(kRate / 10, out);
  mixer->render(kRate / 10, out);
  EXPECT_GT(rms(out).left, both);
  EXPECT_GT(full, 0.01);
}

}  // namespace
}  // namespace quantum::audio
