// Where the engine finds its data and a sport named on the command line (bindings/engine_paths.h):
// the current folder, then QUANTUM_PATH, then the engine's own sports; a path is a path.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "engine_paths.h"
#include "field_loader.h"
#include "scripted_rules.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;

// An environment variable set for one test, and what it was put back after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { old_ ? setenv(name_, old_->c_str(), 1) : unsetenv(name_); }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// A working folder for one test, and the one before put back after.
class ScopedFolder {
 public:
  explicit ScopedFolder(const fs::path& folder) : old_(fs::current_path()) { fs::current_path(folder); }
  ~ScopedFolder() { fs::current_path(old_); }

 private:
  fs::path old_;
};

// A folder of this test's own, gone after it.
class Scratch {
 public:
  explicit Scratch(const std::string& name)
      : path(fs::temp_directory_path() / ("quantum_sport_search_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Scratch() { fs::remove_all(path); }
  const fs::path path;
};

void sport_at(const fs::path& folder) {
  fs::create_directories(folder);
  std::ofstream(folder / "sport.lua") << "return {}\n";
}

TEST(SportSearch, ANameIsFoundHereThenInQuantumPathThenAmongTheEngines) {
  const Scratch scratch("order");
  const fs::path& root = scratch.path;
  sport_at(root / "here" / "duel");
  fs::create_directories(root / "here" / "photos");  // a folder without sport.lua is no sport
  sport_at(root / "designs" / "duel");                // shadowed by the one here
  sport_at(root / "designs" / "relay");
  sport_at(root / "solo");                            // a QUANTUM_PATH entry that is a sport itself
  sport_at(root / "club" / "handball");               // shadows the engine's
  const ScopedFolder here(root / "here");
  const ScopedEnv path("QUANTUM_PATH", (root / "designs").string() + "::" + (root / "solo").string() + ":" +
                                           (root / "club").string() + ":" + (root / "missing").string());

  EXPECT_TRUE(fs::equivalent(lua::find_sport("duel"), root / "here" / "duel"));
  EXPECT_TRUE(fs::equivalent(lua::find_sport("relay"), root / "designs" / "relay"));
  EXPECT_TRUE(fs::equivalent(lua::find_sport("solo"), root / "solo"));
  EXPECT_TRUE(fs::equivalent(lua::find_sport("handball"), root / "club" / "handball"));
  EXPECT_TRUE(fs::equivalent(lua::find_sport("soccer"), lua::engine_rules_folder() / "soccer"));
  // A folder here of that name and no sport anywhere: the loader says what the folder misses.
  EXPECT_EQ(lua::find_sport("photos"), "photos");
  try {
    lua::ScriptedRules photos("photos");
    FAIL() << "a folder without sport.lua loaded";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("photos/sport.lua"), std::string::npos) << e.what();
  }
  EXPECT_THROW(lua::find_sport("lib"), std::invalid_argument);  // the engine's Lua helpers are no sport

  std::vector<std::string> order, shadowed;
  for (const lua::SportPlace& p : lua::sports_in_reach()) {
    order.push_back(p.name);
    if (p.shadowed) shadowed.push_back(p.name);
  }
  ASSERT_GE(order.size(), 5u);
  EXPECT_EQ(std::vector<std::string>(order.begin(), order.begin() + 5),
            (std::vector<std::string>{"duel", "duel", "relay", "solo", "handball"}));
  EXPECT_EQ(shadowed, (std::vector<std::string>{"duel", "handball"}));
}

TEST(SportSearch, AMisspeltNameGetsTheNearestAndTheKnownOnes) {
  const Scratch empty("typo");
  const ScopedFolder here(empty.path);
  try {
    lua::find_sport("handbal");
    FAIL() << "a misspelt sport was found";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown sport 'handbal' (did you mean 'handball'?)"), std::string::npos) << what;
    EXPECT_NE(what.find("known: airhockey, basketball, handball, keepaway, practice, soccer, volleyball"), std::string::npos)
        << what;
  }
}

TEST(SportSearch, APathIsAPathAndAFieldFileAFile) {
  const fs::path practice = QUANTUM_SOURCE_DIR "/rules/practice";
  EXPECT_EQ(lua::find_sport(practice.string()), practice);
  try {
    lua::find_sport("rules/nosuch");
    FAIL() << "a missing folder was found";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "rules/nosuch: no such sport folder");
  }
  // The field of a sport by name is the one its folder holds.
  EXPECT_EQ(lua::load_field("practice").bodies.size(), lua::load_field(practice.string()).bodies.size());
  EXPECT_EQ(lua::ScriptedRules("practice").spec().name, lua::ScriptedRules(practice.string()).spec().name);
}

TEST(SportSearch, TheDataIsTheCheckoutsInABuildAndQuantumDataMustBeData) {
  EXPECT_TRUE(fs::equivalent(lua::engine_rules_folder(), QUANTUM_SOURCE_DIR "/rules"));
  {
    const ScopedEnv data("QUANTUM_DATA", fs::temp_directory_path().string());
    try {
      lua::engine_data_folder();
      FAIL() << "a folder without rules/lib was taken for the engine's data";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("QUANTUM_DATA=" + fs::temp_directory_path().string() + ": not the engine's data"),
                std::string::npos) << e.what();
    }
  }
  const Scratch scratch("data");
  const fs::path copy = scratch.path / "share";
  fs::create_directories(copy);
  fs::copy(QUANTUM_SOURCE_DIR "/rules", copy / "rules", fs::copy_options::recursive);
  const ScopedEnv data("QUANTUM_DATA", copy.string());
  EXPECT_EQ(lua::engine_rules_folder(), copy / "rules");
  EXPECT_EQ(lua::find_sport("keepaway"), copy / "rules" / "keepaway");
}

}  // namespace
}  // namespace quantum
