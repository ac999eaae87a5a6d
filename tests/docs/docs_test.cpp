// The docs' examples are what the engine does: every Lua example in README.md and docs/*.md is
// either a shipped file (its first line names it; the example must stand in that file as it is,
// parts elided with a "-- ..." line) or a complete sport.lua that loads and plays on the air
// hockey table with no rule error; every C++ example quotes a shipped file the same way; every
// `build/quantum` command line in a shell example uses only options that command has.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "../runtime/desk_support.h"
#include "quantum/limits.h"
#include "session.h"
#include "lua_sport.h"

namespace quantum {
namespace {

namespace fs = std::filesystem;
using test::output_of;

struct Example {
  std::string doc, language, text;
  int line;  // where the example starts in its doc
};

// README.md and docs/*.md.
std::vector<fs::path> docs() {
  std::vector<fs::path> docs = {fs::path(QUANTUM_SOURCE_DIR) / "README.md"};
  for (const auto& entry : fs::directory_iterator(fs::path(QUANTUM_SOURCE_DIR) / "docs"))
    if (entry.path().extension() == ".md") docs.push_back(entry.path());
  return docs;
}

std::vector<Example> examples() {
  std::vector<Example> out;
  for (const fs::path& doc : docs()) {
    std::ifstream in(doc);
    std::string line;
    int n = 0;
    Example* open = nullptr;
    while (std::getline(in, line)) {
      ++n;
      if (line.rfind("```", 0) == 0) {
        if (open) {
          open = nullptr;
        } else {
          out.push_back({fs::relative(doc, QUANTUM_SOURCE_DIR).string(), line.substr(3), "", n + 1});
          open = &out.back();
        }
        continue;
      }
      if (open) open->text += line + "\n";
    }
  }
  return out;
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The shipped file an example names in its first line ("-- rules/practice/sport.lua" in Lua,
// "// tools/play.cpp" in C++), if any.
std::string shipped_file(const std::string& text) {
  std::smatch m;
  const std::string first = text.substr(0, text.find('\n'));
  if (std::regex_match(first, m, std::regex(R"((?:--|//) ([a-z]+/[A-Za-z0-9_./-]+\.(lua|cpp|h)))")) &&
      fs::exists(fs::path(QUANTUM_SOURCE_DIR) / m[1].str()))
    return m[1].str();
  return "";
}

// Whether every part of `example` (split at "-- ..." lines) stands in `file`, in order.
std::string missing_part(const std::string& example, const std::string& file) {
  std::vector<std::string> parts(1);
  std::istringstream lines(example.substr(example.find('\n') + 1));
  for (std::string line; std::getline(lines, line);) {
    if (line.find_first_not_of(' ') != std::string::npos && line.substr(line.find_first_not_of(' ')) == "-- ...")
      parts.emplace_back();
    else
      parts.back() += line + "\n";
  }
  size_t from = 0;
  for (const std::string& part : parts) {
    const size_t at = file.find(part, from);
    if (at == std::string::npos) return part;
    from = at + part.size();
  }
  return "";
}

// Plays the example as a sport on the air hockey table for three seconds; returns what went wrong.
std::string play_as_sport(const Example& e) {
  const fs::path dir = fs::temp_directory_path() / ("quantum_doc_example_" + std::to_string(std::hash<std::string>()(e.text)));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(QUANTUM_SOURCE_DIR "/rules/airhockey/field.lua", dir / "field.lua");
  std::ofstream(dir / "sport.lua") << e.text;
  runtime::SessionOptions o;
  o.sport = dir.string();
  o.seconds = 3;
  o.particles = 300;
  std::ostringstream errors;
  try {
    runtime::Session session(o, tools::lua_sport, nullptr, errors);
    session.run();
  } catch (const std::exception& x) {
    return x.what();
  }
  return errors.str();
}

TEST(Docs, EveryLuaExampleIsAShippedFileOrAPlayableSport) {
  int shipped = 0, played = 0;
  for (const Example& e : examples()) {
    if (e.language != "lua") continue;
    const std::string where = e.doc + ":" + std::to_string(e.line);
    if (const std::string file = shipped_file(e.text); !file.empty()) {
      const std::string part = missing_part(e.text, read(fs::path(QUANTUM_SOURCE_DIR) / file));
      EXPECT_EQ(part, "") << where << ": not as it stands in " << file;
      ++shipped;
    } else {
      EXPECT_EQ(play_as_sport(e), "") << where << ": this example does not play as a sport.lua";
      ++played;
    }
  }
  std::cout << shipped << " examples quote shipped files, " << played << " play as sports\n";
  EXPECT_GT(shipped, 5);
  EXPECT_GT(played, 5);
}

TEST(Docs, EveryCppExampleQuotesAShippedFile) {
  int quoted = 0;
  for (const Example& e : examples()) {
    if (e.language != "cpp") continue;
    const std::string where = e.doc + ":" + std::to_string(e.line);
    const std::string file = shipped_file(e.text);
    ASSERT_NE(file, "") << where << ": a C++ example names the file it comes from in its first line";
    EXPECT_EQ(missing_part(e.text, read(fs::path(QUANTUM_SOURCE_DIR) / file)), "") << where << ": not as it stands in " << file;
    ++quoted;
  }
  EXPECT_GT(quoted, 0);
}

std::string help_of(const std::string& command, const std::string& program = QUANTUM_BINARY) {
  return output_of(program + " " + command + " --help");
}

TEST(Docs, EveryQuantumCommandLineUsesOptionsItHas) {
  int checked = 0;
  const std::regex command(R"((?:^|\s)build/quantum\s+(simulate|play|test|track|balance)\b([^\n#]*))");
  const std::regex option(R"(\s(--[a-z][a-z-]*))");
  for (const Example& e : examples()) {
    if (e.language != "sh") continue;
    for (auto m = std::sregex_iterator(e.text.begin(), e.text.end(), command); m != std::sregex_iterator(); ++m) {
      const std::string sub = (*m)[1], args = (*m)[2];
      std::string help = help_of(sub);
      help.resize(std::min(help.size(), help.find("\nExamples:\n")));  // the examples name options too
      for (auto o = std::sregex_iterator(args.begin(), args.end(), option); o != std::sregex_iterator(); ++o)
        EXPECT_NE(help.find((*o)[1].str()), std::string::npos)
            << e.doc << ":" << e.line << ": `quantum " << sub << "` has no option " << (*o)[1];
      ++checked;
    }
  }
  EXPECT_GT(checked, 5);
}

// What the docs say `quantum` says, it says: "`quantum paly` says `did you mean 'play'?`".
TEST(Docs, EveryQuotedMessageIsWhatQuantumSays) {
  const std::regex quoted(R"(`quantum ([^`]+)` says `([^`]+)`)");
  int checked = 0;
  for (const fs::path& doc : docs()) {
    const std::string text = read(doc);
    for (auto m = std::sregex_iterator(text.begin(), text.end(), quoted); m != std::sregex_iterator(); ++m) {
      const std::string said = output_of(QUANTUM_BINARY " " + (*m)[1].str());
      EXPECT_NE(said.find((*m)[2].str()), std::string::npos) << doc.filename() << ": quantum " << (*m)[1] << " says " << said;
      ++checked;
    }
  }
  EXPECT_GE(checked, 3);
}

// Where the docs state a range a value must lie in, it is the table's (quantum/limits.h): a
// range changed there and not in the docs fails here.
TEST(LimitsDocs, TheDocsStateTheTablesRanges) {
  struct Stated {
    const char* doc;
    std::string before;  // the words that lead to the range in the doc
    const limits::Range& range;
  };
  const Stated stated[] = {
      {"docs/lua-api.md", "fate factor per fate kind, each in ", limits::kFactor},
      {"docs/lua-api.md", "`speed`, m/s of a throw that gives none, in ", limits::kThrowSpeed},
      {"docs/lua-api.md", "`spread`, degrees of direction, in ", limits::kSpreadDegrees},
      {"docs/lua-api.md", "`speed_spread`, a share of the speed, in ", limits::kSpeedSpread},
      {"docs/lua-api.md", "`rate`, per second in ", limits::kTackleRate},
      {"docs/lua-api.md", "per player (body name): in ", limits::kHandicap},
      {"docs/lua-api.md", "sets a player's own handicap (in ", limits::kHandicap},
      {"docs/lua-api.md", "`opts` has `speed` (m/s, in ", limits::kThrowSpeed},
      {"docs/lua-api.md", "`spread` (degrees, in ", limits::kSpreadDegrees},
      {"docs/lua-api.md", "(degrees above the horizontal, in ", limits::kElevationDegrees},
      {"docs/lua-api.md", "`most` times their own (in ", limits::kBalanceMost},
      {"docs/desk.md", "a speed that is not in ", limits::kThrowSpeed},
      {"README.md", "`--handicap` outside ", limits::kHandicap},
      {"README.md", "`--skill` outside ", limits::kSkill},
  };
  for (const Stated& s : stated) {
    const std::string text = read(fs::path(QUANTUM_SOURCE_DIR) / s.doc);
    const size_t at = text.find(s.before);
    ASSERT_NE(at, std::string::npos) << s.doc << ": no \"" << s.before << "\"";
    EXPECT_EQ(text.substr(at + s.before.size(), limits::interval(s.range).size()), limits::interval(s.range))
        << s.doc << ": " << s.before << "... is not " << s.range.name << "'s range " << limits::interval(s.range);
  }
}

// The same for `build/quantum-synth`, which writes the recordings the tracking docs talk about
// (built with tracking).
#if QUANTUM_WITH_TRACKING
TEST(Docs, EverySynthCommandLineUsesOptionsItHas) {
  int checked = 0;
  const std::regex command(R"((?:^|\s)build/quantum-synth\b([^\n#]*))");
  const std::regex option(R"(\s(--[a-z][a-z-]*))");
  const std::string help = help_of("", QUANTUM_BINARY "-synth");
  for (const Example& e : examples()) {
    if (e.language != "sh") continue;
    for (auto m = std::sregex_iterator(e.text.begin(), e.text.end(), command); m != std::sregex_iterator(); ++m) {
      const std::string args = (*m)[1];
      for (auto o = std::sregex_iterator(args.begin(), args.end(), option); o != std::sregex_iterator(); ++o)
        EXPECT_NE(help.find((*o)[1].str()), std::string::npos)
            << e.doc << ":" << e.line << ": `quantum-synth` has no option " << (*o)[1];
      ++checked;
    }
  }
  EXPECT_GE(checked, 2);  // tracking.md: a full-size table, and a rally
}
#endif

}  // namespace
}  // namespace quantum
