// Hostile paths: the files a sport names (its field, sounds, recorded phrases, modules and
// power-ups) are found inside its folder and the engine's shared folders only. An absolute path,
// a '..', a symlink out, a device, a FIFO or a directory is refused with the key (or, at run
// time, the script's file and line) named, and never opened: nothing blocks.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "hostile_support.h"
#include "match_audio.h"
#include "reloader.h"
#include "scripted_rules.h"
#include "../shipped_sports.h"

namespace quantum {
namespace {

using namespace hostile;
using namespace std::chrono_literals;

// Longer than any load takes, even under the sanitizers; a load that opened a FIFO nobody writes
// would never end.
constexpr auto kPrompt = 20s;

// Runs `work` on a thread of its own and returns its error ("" for none), or says it blocks: a
// check that let a FIFO or /dev/stdin be opened fails the test instead of hanging it.
template <class Work>
std::string error_within(Work work) {
  auto result = std::make_shared<std::promise<std::string>>();
  std::future<std::string> error = result->get_future();
  std::thread([work, result] {
    try {
      work();
      result->set_value("");
    } catch (const std::exception& e) {
      result->set_value(e.what());
    }
  }).detach();  // a blocked thread cannot be joined; the test reports it and goes on
  if (error.wait_for(kPrompt) != std::future_status::ready) return "blocked: still running after 20 s";
  return error.get();
}

std::string load_error(const std::string& folder) {
  return error_within([folder] { lua::ScriptedRules sport(folder); });
}

// A folder outside every sport, holding a copy of air hockey's field, a sound and a power-up
// and a module that would load: a symlink to them must be refused for where it leads.
fs::path outside() {
  const fs::path dir = fs::temp_directory_path() / "quantum_hostile_paths_outside";
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua", fs::copy_options::overwrite_existing);
  fs::copy_file(QUANTUM_SOURCE_DIR "/sounds/hit.wav", dir / "hit.wav", fs::copy_options::overwrite_existing);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/powerups/attract.lua", dir / "evil.lua", fs::copy_options::overwrite_existing);
  std::ofstream(dir / "util.lua") << "return { x = 1 }\n";
  return dir;
}

// What a case puts at `at` in the sport's folder before it loads. Nothing: the name is refused
// before it is looked for (and `at`, an absolute path or one with '..', is not the sport's).
// Symlink: a symlink to `target`.
enum class Put { Nothing, Fifo, Directory, LinkToStdin, LinkToZero, Symlink };

void put(const fs::path& at, Put what, const fs::path& target = {}) {
  if (what == Put::Nothing) return;
  fs::remove_all(at);
  fs::create_directories(at.parent_path());
  switch (what) {
    case Put::Nothing: break;  // not reached
    case Put::Fifo: ASSERT_EQ(mkfifo(at.c_str(), 0600), 0) << at; break;
    case Put::Directory: fs::create_directories(at); break;
    case Put::LinkToStdin: fs::create_symlink("/dev/stdin", at); break;
    case Put::LinkToZero: fs::create_symlink("/dev/zero", at); break;
    case Put::Symlink: fs::create_symlink(target, at); break;
  }
}

struct PathCase {
  const char* name;
  const char* value;  // the name the script gives
  Put put;            // what is at that name in the sport's folder
  const char* error;  // what the error must say after the key (one of them, between '|')
};

// /dev/stdin is whatever the test runs with: a terminal, /dev/null, a pipe, a file outside.
constexpr const char* kStdinIsNoFileHere =
    "is a character device, not a regular file|is a FIFO, not a regular file|is a socket, not a regular file|"
    "leads out of the folders a sport may read";

const PathCase kRefusedFiles[] = {
    {"empty", "", Put::Nothing, "'' is not a file name"},
    {"absolute_stdin", "/dev/stdin", Put::Nothing, "'/dev/stdin': an absolute path is refused"},
    {"absolute_passwd", "/etc/passwd", Put::Nothing, "'/etc/passwd': an absolute path is refused"},
    {"dotdot_passwd", "../../etc/passwd", Put::Nothing, "'../../etc/passwd': '..' is refused"},
    {"dotdot_sibling", "../quantum_hostile_paths_outside/x", Put::Nothing, "'..' is refused"},
    {"dotdot_inside", "sub/../x", Put::Nothing, "'..' is refused"},
    {"fifo", "pipe", Put::Fifo, "is a FIFO, not a regular file"},
    {"directory", "folder", Put::Directory, "is a directory, not a regular file"},
    {"link_stdin", "stdin", Put::LinkToStdin, kStdinIsNoFileHere},
    {"link_zero", "zero", Put::LinkToZero, "is a character device, not a regular file"},
    {"link_outside", "escape", Put::Symlink, "leads out of the folders a sport may read"},
};

// Every kind of refused name, given at `key` by the Lua that `set` makes of it; `extension` is
// the file's (a sound's, a field's). The error names sport.lua and the key, and comes within
// kPrompt (error_within).
template <class Set>
void expect_refused(const std::string& key, const std::string& extension, const fs::path& outside_file, Set set) {
  for (const PathCase& c : kRefusedFiles) {
    const std::string value = c.value + (c.put == Put::Nothing ? "" : extension);
    const std::string folder = hostile_sport("paths_" + key + "_" + c.name, "", set(value));
    put(fs::path(folder) / value, c.put, outside_file);
    const std::string error = load_error(folder);
    EXPECT_NE(error.find("sport.lua: " + key + ": "), std::string::npos) << key << ", " << c.name << ": " << error;
    EXPECT_TRUE(says_one_of(error, c.error)) << key << ", " << c.name << ": " << error;
  }
}

TEST(HostilePaths, AFieldOutsideTheSportOrNotAFileIsRefusedAtLoad) {
  expect_refused("field", ".lua", outside() / "field.lua",
                 [](const std::string& v) { return "sport.field = '" + v + "'"; });
}

TEST(HostilePaths, ASoundOutsideTheSportOrNotAFileIsRefusedAtLoad) {
  expect_refused("audio.sounds.shot", ".wav", outside() / "hit.wav",
                 [](const std::string& v) { return "sport.audio.sounds.shot = '" + v + "'"; });
}

TEST(HostilePaths, ARecordedPhraseOutsideTheSportOrNotAFileIsRefusedAtLoad) {
  expect_refused("audio.recorded.goal", ".wav", outside() / "hit.wav",
                 [](const std::string& v) { return "sport.audio.recorded = { goal = '" + v + "' }"; });
}

// The engine's own sound names are looked for in the sport's folder first: a FIFO there under
// one of them is refused too, with the key of the event that would play it.
TEST(HostilePaths, AnEngineSoundsNameInTheSportsFolderMustBeAFileToo) {
  const std::string folder = hostile_sport("paths_own_whistle", "");
  put(fs::path(folder) / "whistle.wav", Put::Fifo);
  EXPECT_TRUE(says_one_of(load_error(folder), "sport.lua: audio.sounds.drop: " + folder + "/whistle.wav is a FIFO"));
  fs::remove(fs::path(folder) / "whistle.wav");
}

// require's names are module names (no '/', no '..'); what they find must be a file inside the
// sport's folder or the engine's lib/.
TEST(HostilePaths, AModuleOutsideTheSportOrNotAFileIsRefusedAtLoad) {
  const struct {
    const char* name;
    const char* module;
    Put put;
    const char* error;
  } cases[] = {
      {"absolute", "/etc/passwd", Put::Nothing, "'/etc/passwd' is not a module name"},
      {"dotdot", "../../x", Put::Nothing, "'../../x' is not a module name"},
      {"dots", "..x", Put::Nothing, "'..x' is not a module name"},
      {"fifo", "util", Put::Fifo, "util.lua is a FIFO, not a regular file"},
      {"directory", "util", Put::Directory, "util.lua is a directory, not a regular file"},
      {"link_stdin", "util", Put::LinkToStdin, kStdinIsNoFileHere},
      {"link_zero", "util", Put::LinkToZero, "util.lua is a character device, not a regular file"},
      {"link_outside", "util", Put::Symlink, "util.lua leads out of the folders a sport may read"},
  };
  for (const auto& c : cases) {
    const std::string folder = hostile_sport(std::string("paths_require_") + c.name, "",
                                             "local module = require '" + std::string(c.module) + "'");
    put(fs::path(folder) / "util.lua", c.put, outside() / "util.lua");
    const std::string error = load_error(folder);
    EXPECT_TRUE(std::regex_search(error, std::regex("sport\\.lua:\\d+: require: "))) << c.name << ": " << error;
    EXPECT_TRUE(says_one_of(error, c.error)) << c.name << ": " << error;
  }
}

// game.grant's power-up name is a plain name; what it finds must be a file inside the power-up
// folders. Refused at run time: the grant is an error at its file and line, and the match goes on.
TEST(HostilePaths, APowerUpOutsideItsFoldersOrNotAFileIsAnErrorAndTheMatchGoesOn) {
  const struct {
    const char* name;
    const char* powerup;
    Put put;
    const char* error;
  } cases[] = {
      {"absolute", "/etc/passwd", Put::Nothing, "power-up '/etc/passwd': names are lower-case letters, digits and _"},
      {"dotdot", "../../x", Put::Nothing, "power-up '../../x': names are lower-case letters, digits and _"},
      {"slash", "powerups/evil", Put::Nothing, "power-up 'powerups/evil': names are"},
      {"fifo", "evil", Put::Fifo, "evil.lua is a FIFO, not a regular file"},
      {"directory", "evil", Put::Directory, "evil.lua is a directory, not a regular file"},
      {"link_stdin", "evil", Put::LinkToStdin, kStdinIsNoFileHere},
      {"link_zero", "evil", Put::LinkToZero, "evil.lua is a character device, not a regular file"},
      {"link_outside", "evil", Put::Symlink, "evil.lua leads out of the folders a sport may read"},
  };
  for (const auto& c : cases) {
    const std::string folder = hostile_sport(std::string("paths_grant_") + c.name,
                                             "game.grant(\"Red's mallet\", '" + std::string(c.powerup) + "')");
    put(fs::path(folder) / "powerups" / "evil.lua", c.put, outside() / "evil.lua");
    struct Outcome {
      std::vector<std::string> errors;
      double time = 0;
    };
    auto outcome = std::make_shared<Outcome>();  // a match left blocked must not write to this frame
    const std::string thrown = error_within([outcome, folder] {
      lua::ScriptedRules sport(folder);
      Played played(sport);
      for (int frame = 0; frame < 30; ++frame) played.step();
      outcome->errors.assign(played.match.errors().begin(), played.match.errors().end());
      outcome->time = played.match.time();
    });
    ASSERT_EQ(thrown, "") << c.name;
    const std::vector<std::string>& errors = outcome->errors;
    ASSERT_EQ(errors.size(), 1u) << c.name;
    EXPECT_TRUE(std::regex_search(errors[0], std::regex("sport\\.lua:\\d+: game\\.grant: "))) << c.name << ": " << errors[0];
    EXPECT_TRUE(says_one_of(errors[0], c.error)) << c.name << ": " << errors[0];
    EXPECT_NEAR(outcome->time, 0.5, 1e-6) << c.name << ": the match went on";
  }
}

// sport.lua is named by no script, but a sport folder shared with a FIFO there must not block
// its load (nor a reload while a match runs).
TEST(HostilePaths, ASportFileThatIsNotARegularFileIsRefusedUnopened) {
  const fs::path dir = fs::temp_directory_path() / "quantum_hostile_paths_sport_fifo";
  fs::create_directories(dir);
  put(dir / "sport.lua", Put::Fifo);
  EXPECT_EQ(load_error(dir.string()), (dir / "sport.lua").string() + " is a FIFO, not a regular file");
  put(dir / "sport.lua", Put::LinkToZero);
  EXPECT_EQ(load_error(dir.string()), (dir / "sport.lua").string() + " is a character device, not a regular file");
}

// The reloader loads what was saved through the same checks: a sport.lua that became a FIFO
// while the match ran fails to reload, unopened, and the old version plays on.
TEST(HostilePaths, AReloadOfASportFileThatBecameAFifoFailsAndTheMatchGoesOn) {
  fs::remove_all(fs::temp_directory_path() / "quantum_hostile_paths_reload");  // a FIFO left would block the rewrite
  const fs::path folder = hostile_sport("paths_reload", "");
  auto said = std::make_shared<std::string>();
  const std::string thrown = error_within([folder, said] {
    auto sport = std::make_unique<lua::ScriptedRules>(folder.string());
    Played played(*sport);
    lua::Reloader reloader(*sport, {}, false);
    put(folder / "sport.lua", Put::Fifo);
    reloader.changed(folder / "sport.lua");
    std::ostringstream errors;
    EXPECT_EQ(reloader.poll(sport, played.match, errors, nullptr), 0);
    for (int frame = 0; frame < 30; ++frame) played.step();
    EXPECT_NEAR(played.match.time(), 0.5, 1e-6);
    *said = errors.str();
  });
  EXPECT_EQ(thrown, "");
  EXPECT_EQ(*said, "quantum: reload failed: " + (folder / "sport.lua").string() +
                       " is a FIFO, not a regular file (the previous version goes on)\n");
  fs::remove(folder / "sport.lua");
}

// A sound loads when it first plays, long after the sport's load checked it: one that has become
// a FIFO since is one warning and silence, unopened.
TEST(HostilePaths, ASoundThatBecameAFifoAfterTheLoadStaysSilent) {
  const fs::path dir = fs::temp_directory_path() / "quantum_hostile_paths_late_fifo";
  fs::create_directories(dir);
  put(dir / "shot.wav", Put::Fifo);
  game::SportAudio sounds;
  sounds.sounds["shot"] = (dir / "shot.wav").string();
  auto warned = std::make_shared<std::ostringstream>();
  EXPECT_EQ(error_within([sounds, warned, dir] {
              runtime::MatchAudio audio("wav:" + (dir / "match.wav").string(), sounds, *warned);
              game::GameEvent shot;
              shot.type = game::EventKind::Shot;
              audio.event(shot);
            }),
            "");
  EXPECT_EQ(warned->str(), "quantum: " + (dir / "shot.wav").string() + " is a FIFO, not a regular file; that sound stays silent\n");
}

// A phrase key ending in _start or _over is a power-up's only for a plain power-up name: a key
// that looks like a path is a phrase like any other, never looked for as a file (this one would
// find attract.lua, whose phrases may not say {who}).
TEST(HostilePaths, APhraseKeyThatLooksLikeAPathIsNotLookedForAsAPowerUp) {
  const std::string folder = hostile_sport("paths_phrase_key", "", "sport.phrases['../powerups/attract_start'] = '{who}'");
  EXPECT_EQ(load_error(folder), "");
}

// What the sports ship with keeps working: their fields, the engine's sounds, their modules and
// every shipped power-up are found, and so are a sport's own files reached by a symlink inside
// it and a sport whose folder is itself a symlink.
TEST(HostilePaths, ShippedSportsAndTheirOwnFilesStillResolve) {
  // The build folder's data is the checkout's own (CMakeLists.txt links it).
  ASSERT_TRUE(fs::equivalent(lua::engine_sounds_folder(), QUANTUM_SOURCE_DIR "/sounds"));
  for (const char* name : quantum::test::kShippedSports) {
    const std::string folder = std::string(QUANTUM_SOURCE_DIR "/rules/") + name;
    const lua::ScriptedRules sport(folder);
    for (const auto& [event, file] : sport.spec().audio.sounds) {
      EXPECT_TRUE(fs::is_regular_file(file)) << name << ": " << event << ": " << file;
      EXPECT_EQ(fs::path(file).parent_path(), lua::engine_sounds_folder()) << file;
    }
  }
  lua::ScriptedRules airhockey(QUANTUM_SOURCE_DIR "/rules/airhockey");
  Played played(airhockey);
  for (const char* powerup : {"attract", "black_ice", "goal_seeker", "penalty", "slow_motion", "stun", "wormhole"})
    EXPECT_NO_THROW(airhockey.grant(played.match, 0, powerup, {})) << powerup;

  const std::string folder = hostile_sport("paths_own_files", "",
                                           "sport.field = 'table.lua'\n"
                                           "sport.audio.sounds.shot = 'sounds/own.wav'\n"
                                           "sport.audio.recorded = { goal = 'alias.wav' }\n");
  const fs::path dir(folder);
  put(dir / "table.lua", Put::Symlink, dir / "field.lua");
  fs::create_directories(dir / "sounds");
  fs::copy_file(QUANTUM_SOURCE_DIR "/sounds/hit.wav", dir / "sounds" / "own.wav", fs::copy_options::overwrite_existing);
  put(dir / "alias.wav", Put::Symlink, "sounds/own.wav");  // relative, inside the sport
  const fs::path linked = fs::temp_directory_path() / "quantum_hostile_paths_linked_sport";
  put(linked, Put::Symlink, dir);
  for (const fs::path& sport_folder : {dir, linked}) {
    const lua::ScriptedRules sport(sport_folder.string());
    EXPECT_EQ(sport.spec().audio.sounds.at("shot"), (sport_folder / "sounds" / "own.wav").string());
    EXPECT_EQ(sport.spec().audio.recorded.at("goal"), (sport_folder / "alias.wav").string());
    EXPECT_EQ(sport.spec().field.bodies.size(), 2u);
  }
}

}  // namespace
}  // namespace quantum
