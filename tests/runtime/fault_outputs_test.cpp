// What a match's outputs promise under faults (docs/reliability.md, "Faults"): a process killed at
// any moment leaves every file whole up to its last 100 ms of play, a signal ends a match cleanly,
// outputs that are not plain files or are one file are refused before the match, a failing
// standard output is told and costs nothing else, and logs are read back compressed or cut short.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <algorithm>
#include <fstream>
#include <mutex>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "output_files.h"

namespace {
namespace fs = std::filesystem;
using quantum::runtime::LineReader;

extern "C" char** environ;

// A folder of the test's own, gone with it: CTest runs tests side by side.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name)
      : dir(fs::temp_directory_path() / ("quantum_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string operator/(const std::string& file) const { return (dir / file).string(); }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Every whole line of a log, plain or compressed: what a reader of it gets.
std::vector<std::string> lines_of(const std::string& path, std::string* torn = nullptr) {
  std::vector<std::string> lines;
  LineReader reader(path);
  for (std::string line; reader.next(line);) lines.push_back(line);
  if (torn) *torn = reader.torn();
  return lines;
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

struct Outcome {
  int status = -1;  // the exit code, or 128 + the signal that ended it
  std::string out, err;
};

int status_of(int wait_status) {
  return WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : WIFSIGNALED(wait_status) ? 128 + WTERMSIG(wait_status) : -1;
}

// `quantum ARGS` run by bash after `shell` (a ulimit, `timeout`), its stderr caught, and its stdout
// unless `stdout` says where it goes instead (" >/dev/full", " | head -c 300"): the status is
// quantum's own, also in a pipeline.
Outcome run(const Scratch& scratch, const std::string& args, const std::string& shell = "", const std::string& stdout = "") {
  const std::string out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  fs::remove(out);
  const std::string redirect = stdout.empty() ? " >" + out : stdout;
  const std::string script =
      shell + " " + QUANTUM_BINARY + " " + args + " 2>" + err + redirect + "; exit ${PIPESTATUS[0]}";
  const std::string command = "bash -c '" + script + "'";
  Outcome o;
  o.status = status_of(std::system(command.c_str()));
  o.out = slurp(out), o.err = slurp(err);
  return o;
}

// A match started in the background, its transcript piped to the test, so that the test can
// signal or kill it.
class Running {
 public:
  Running(const std::vector<std::string>& args, const std::string& err_file) {
    int fds[2];
    EXPECT_EQ(pipe(fds), 0);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> all{QUANTUM_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    EXPECT_EQ(posix_spawn(&pid_, QUANTUM_BINARY, &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    out_ = fds[0];
    // The pipe is read as the match writes, as a terminal or `tee` would.
    reader_ = std::thread([this] {
      std::array<char, 4096> buf;
      for (ssize_t n; (n = read(out_, buf.data(), buf.size())) > 0;) {
        std::lock_guard lock(mutex_);
        transcript_.append(buf.data(), size_t(n));
      }
    });
  }
  // Waits until the match plays: the transcript's first phrase has come (a signal before would
  // find a process still starting, whose default is to end). False after a minute without.
  bool playing() {
    for (int k = 0; k < 6000; ++k) {
      {
        std::lock_guard lock(mutex_);
        if (std::count(transcript_.begin(), transcript_.end(), '\n') >= 2) return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  ~Running() {
    if (pid_ > 0) kill(pid_, SIGKILL), wait();
  }
  void signal(int s) { kill(pid_, s); }
  // The exit status (128 + a signal that ended it), once the transcript's pipe is closed.
  int wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    if (reader_.joinable()) reader_.join();
    close(out_);
    return status_of(status);
  }
  const std::string& transcript() const { return transcript_; }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::thread reader_;
  std::mutex mutex_;
  std::string transcript_;
};

// "   0:03.42  Blue shoots" -> 3.42; a line without a time (the first, the final score) -> -1.
double time_of(const std::string& line) {
  static const std::regex stamp(R"(^\s*(\d+):(\d+\.\d+)\s)");
  std::smatch m;
  return std::regex_search(line, m, stamp) ? 60 * std::stod(m[1]) + std::stod(m[2]) : -1;
}

// `part` is `whole`'s first part, line for line.
void expect_prefix(const std::vector<std::string>& part, const std::vector<std::string>& whole, const std::string& what) {
  ASSERT_LE(part.size(), whole.size()) << what;
  for (size_t k = 0; k < part.size(); ++k) ASSERT_EQ(part[k], whole[k]) << what << ", line " << k + 1;
}

// Lines of `whole` at or before `t` ("t" of a JSON line, or a transcript's time stamp).
size_t lines_until(const std::vector<std::string>& whole, double t, bool json) {
  size_t n = 0;
  for (const std::string& line : whole) {
    const double at = json ? nlohmann::json::parse(line).value("t", -1.0) : time_of(line);
    if (at <= t) ++n;
    else if (at > 0) break;
  }
  return n;
}

// A real-time match killed (SIGKILL) at a random moment: every file it wrote holds whole lines
// only, the same lines as the same seed played to its end, all of them up to 100 ms of play before
// the kill; the recording replays.
TEST(FaultKills, AKilledMatchKeepsEveryLineUpToItsLast100MsOfPlay) {
  struct Case {
    const char* sport;
    int seed;
    const char* decisions;  // the decision log's name: one case compressed
  };
  const Case cases[] = {{"airhockey", 1, "d.jsonl"}, {"handball", 2, "d.jsonl.gz"}, {"airhockey", 3, "d.jsonl"}};
  std::mt19937 rng(43);
  for (const Case& c : cases) {
    Scratch s("fault_kill");
    const std::string match = std::string(c.sport) + " --seed " + std::to_string(c.seed) + " --seconds 30 --audio none";
    const Outcome whole = run(s, "play " + match + " --pace fast --events " + (s / "whole.jsonl") + " --decisions " +
                                     (s / "whole_d.jsonl"));
    ASSERT_EQ(whole.status, 0) << whole.err;
    const std::vector<std::string> whole_events = lines_of(s / "whole.jsonl"), whole_draws = lines_of(s / "whole_d.jsonl"),
                                   whole_transcript = split(whole.out);

    const double kill_after = std::uniform_real_distribution<double>(0.2, 3.0)(rng);
    Running killed({"play", c.sport, "--seed", std::to_string(c.seed), "--seconds", "30", "--audio", "none", "--pace",
                    "realtime", "--events", s / "e.jsonl", "--decisions", s / c.decisions, "--record", s / "rec"},
                   s / "err.txt");
    ASSERT_TRUE(killed.playing()) << slurp(s / "err.txt");
    std::this_thread::sleep_for(std::chrono::duration<double>(kill_after));
    killed.signal(SIGKILL);
    ASSERT_EQ(killed.wait(), 128 + SIGKILL);
    const std::string what = std::string(c.sport) + " seed " + std::to_string(c.seed) + " killed after " +
                             std::to_string(kill_after) + " s";

    // How far the match got: its recording replays up to its last frame, and says when that was.
    const Outcome replay = run(s, "replay " + (s / "rec") + " --pace fast --audio none --events " + (s / "r.jsonl"));
    ASSERT_EQ(replay.status, 0) << what << ": " << replay.err;
    const std::vector<std::string> replayed = split(replay.out);
    double reached = -1;
    for (const std::string& line : replayed)
      if (line.find("(the recording is over)") != std::string::npos) reached = time_of(line);
    ASSERT_GT(reached, 0) << what << ": " << replay.out;
    const double complete_to = reached - 0.1;

    std::string torn;
    const std::vector<std::string> events = lines_of(s / "e.jsonl", &torn);
    EXPECT_EQ(torn, "") << what << ": the event log ends at a line boundary";
    const std::string raw = slurp(s / "e.jsonl");
    EXPECT_TRUE(raw.empty() || raw.back() == '\n') << what;
    expect_prefix(events, whole_events, what + ", events");
    EXPECT_GE(events.size(), lines_until(whole_events, complete_to, true)) << what << ": events up to " << complete_to;
    expect_prefix(events, lines_of(s / "r.jsonl"), what + ", the replay's events");

    const std::vector<std::string> draws = lines_of(s / c.decisions, &torn);
    if (std::string(c.decisions).ends_with(".gz")) EXPECT_EQ(slurp(s / c.decisions).substr(0, 2), "\x1f\x8b") << what;
    else EXPECT_EQ(torn, "") << what << ": the decision log ends at a line boundary";
    ASSERT_FALSE(draws.empty()) << what << ": the header is written before the match";
    expect_prefix(std::vector<std::string>(draws.begin() + 1, draws.end()),
                  std::vector<std::string>(whole_draws.begin() + 1, whole_draws.end()), what + ", draws");
    EXPECT_GE(draws.size(), lines_until(std::vector<std::string>(whole_draws.begin() + 1, whole_draws.end()), complete_to, true) + 1)
        << what << ": draws up to " << complete_to;

    const std::vector<std::string> transcript = split(killed.transcript());
    EXPECT_TRUE(killed.transcript().empty() || killed.transcript().back() == '\n') << what;
    expect_prefix(transcript, whole_transcript, what + ", the transcript");
    EXPECT_GE(transcript.size(), lines_until(whole_transcript, complete_to, false)) << what << ": the piped transcript";
  }
}

// SIGINT (Ctrl-C) and SIGTERM end a match as its time limit would: every file completed, the
// transcript's final lines written, and an exit code that says a signal ended it.
TEST(FaultKills, ASignalEndsAMatchCleanly) {
  std::mt19937 rng(7);
  for (const int sig : {SIGINT, SIGTERM, SIGINT}) {
    Scratch s("fault_signal");
    const double after = std::uniform_real_distribution<double>(0.5, 2.0)(rng);
    Running match({"play", "handball", "--seconds", "30", "--audio", "none", "--pace", "realtime", "--events",
                   s / "e.jsonl", "--decisions", s / "d.jsonl", "--record", s / "rec"},
                  s / "err.txt");
    ASSERT_TRUE(match.playing()) << slurp(s / "err.txt");
    std::this_thread::sleep_for(std::chrono::duration<double>(after));
    match.signal(sig);
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    ASSERT_EQ(match.wait(), 128 + sig) << name << ": " << slurp(s / "err.txt");
    const std::vector<std::string> transcript = split(match.transcript());
    ASSERT_GE(transcript.size(), 3u) << match.transcript();
    EXPECT_NE(transcript[transcript.size() - 3].find("(ended by " + name + ")"), std::string::npos) << match.transcript();
    EXPECT_NE(transcript[transcript.size() - 2].find("final score:"), std::string::npos) << match.transcript();
    EXPECT_NE(transcript[transcript.size() - 2].find("not finished"), std::string::npos) << match.transcript();
    EXPECT_EQ(transcript.back().rfind("rallies ", 0), 0u) << match.transcript();
    std::string torn;
    const std::vector<std::string> events = lines_of(s / "e.jsonl", &torn);
    EXPECT_EQ(torn, "");
    for (const std::string& line : lines_of(s / "d.jsonl", &torn)) EXPECT_NO_THROW(std::ignore = nlohmann::json::parse(line));
    EXPECT_EQ(torn, "");
    // The recording is complete: it says how many frames it has, and replays to the same events.
    const nlohmann::json recording = nlohmann::json::parse(slurp(s / "rec/recording.json"));
    EXPECT_GT(recording.at("frames").get<int>(), 30) << name;
    const Outcome replay = run(s, "replay " + (s / "rec") + " --pace fast --audio none --quiet --events " + (s / "r.jsonl"));
    ASSERT_EQ(replay.status, 0) << replay.err;
    EXPECT_EQ(slurp(s / "r.jsonl"), slurp(s / "e.jsonl")) << name;
  }
}

// An output that is no regular file is refused before the match, naming the option: a FIFO
// would hold the match until someone reads it (it hung before), a device would take the lines.
TEST(FaultOutputs, OutputsThatAreNotRegularFilesAreRefusedBeforeTheMatch) {
  Scratch s("fault_fifo");
  const std::string fifo = s / "fifo";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::pair<std::string, std::string> cases[] = {
      {"--events " + fifo, "--events " + fifo + ": is a FIFO"},
      {"--decisions " + fifo, "--decisions " + fifo + ": is a FIFO"},
      {"--audio wav:" + fifo, "--audio " + fifo + ": is a FIFO"},
      {"--events /dev/null", "--events /dev/null: is a character device"},
      {"--decisions /dev/full", "--decisions /dev/full: is a character device"},
  };
  for (const auto& [option, said] : cases) {
    // timeout: a hang fails the case, not the suite.
    const Outcome r = run(s, "play airhockey --seconds 5 --audio none " + option, "timeout 60");
    EXPECT_EQ(r.status, 1) << option << ": " << r.err;
    EXPECT_NE(r.err.find(said), std::string::npos) << option << ": " << r.err;
    EXPECT_EQ(r.out, "") << option << ": nothing played";
  }
}

// One file named for two outputs is refused before the match, naming both; the file is untouched.
TEST(FaultOutputs, OneFileForTwoOutputsIsRefusedBeforeTheMatch) {
  Scratch s("fault_same");
  const std::string log = s / "log.jsonl";
  {
    std::ofstream(log) << "kept\n";
  }
  fs::create_symlink(log, s / "link.jsonl");
  const std::pair<std::string, std::string> cases[] = {
      {"--events " + log + " --decisions " + log, "is the same file as --events " + log},
      {"--events " + log + " --decisions " + (s / "link.jsonl"), "is the same file as --events " + log},
      {"--events " + log + " --audio wav:" + (s.dir / "." / "log.jsonl").string(), "is the same file as --events " + log},
      {"--events - --decisions -", "--decisions - and --events - both write to standard output"},
      {"--record " + (s / "rec") + " --events " + (s / "rec/e.jsonl"), "--record " + (s / "rec") + ": holds --events"},
  };
  for (const auto& [options, said] : cases) {
    const Outcome r = run(s, "play airhockey --seconds 5 --audio none " + options);
    EXPECT_EQ(r.status, 1) << options;
    EXPECT_NE(r.err.find(said), std::string::npos) << options << ": " << r.err;
    EXPECT_EQ(slurp(log), "kept\n") << options;
    EXPECT_FALSE(fs::exists(s / "rec")) << options;
  }
#if QUANTUM_WITH_DESK
  // The desk's own outputs are checked with the session's.
  const Outcome r = run(s, "play airhockey --seconds 5 --audio none --events " + (s / "x.png") + " --snapshot " + (s / "x.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--snapshot " + (s / "x.png") + ": is the same file as --events"), std::string::npos) << r.err;
#endif
}

// Standard output full or closed early: told on stderr, the other files completed, exit 1 (not
// a process killed by SIGPIPE with its files half written).
TEST(FaultOutputs, AFailingStandardOutputIsToldAndTheOtherFilesAreCompleted) {
  Scratch s("fault_stdout");
  const std::string match = "play airhockey --seconds 20 --audio none --pace fast --events " + (s / "e.jsonl") +
                            " --decisions " + (s / "d.jsonl");
  struct Case {
    std::string args, stdout, said;
  };
  const Case cases[] = {
      {match, " >/dev/full", "cannot write to the transcript"},
      {match, " | head -c 300 >/dev/null", "cannot write to the transcript"},
      {match, " >&-", "cannot write to the transcript"},
      {"play airhockey --seconds 20 --audio none --pace fast --decisions " + (s / "d.jsonl") + " --events -", " >/dev/full",
       "cannot write to stdout"},
  };
  for (const Case& c : cases) {
    fs::remove(s / "e.jsonl");
    fs::remove(s / "d.jsonl");
    const Outcome r = run(s, c.args, "", c.stdout);
    EXPECT_EQ(r.status, 1) << c.args << c.stdout << ": " << r.err;
    EXPECT_NE(r.err.find(c.said), std::string::npos) << c.args << c.stdout << ": " << r.err;
    std::string torn;
    EXPECT_GT(lines_of(s / "d.jsonl", &torn).size(), 10u) << c.args << c.stdout;
    EXPECT_EQ(torn, "") << "the decision log was completed";
    if (c.args == match) {
      EXPECT_NE(slurp(s / "e.jsonl").find("\"type\":\"match_end\""), std::string::npos) << c.stdout << ": the event log was completed";
    }
  }
}

// A file that fails (a full disk: here the shell's file size limit) costs the transcript nothing:
// the final score and the figures are still told, and the exit code says a file was lost.
TEST(FaultOutputs, AFailingFileNeverCostsTheTranscriptItsFinalLines) {
  Scratch s("fault_file");
  // bash's ulimit counts KiB: each file's limit is past the sport's files (a recording copies them)
  // and short of 30 s of handball's (decisions about 100 KiB, events 9 KiB, frames 185 KiB).
  const std::pair<std::string, int> cases[] = {
      {"--decisions " + (s / "d.jsonl"), 64}, {"--events " + (s / "e.jsonl"), 4}, {"--record " + (s / "rec"), 64}};
  for (const auto& [option, kib] : cases) {
    fs::remove_all(s / "rec");
    const Outcome r = run(s, "play handball --seconds 30 --audio none --pace fast " + option, "ulimit -f " + std::to_string(kib) + ";");
    EXPECT_EQ(r.status, 1) << option << ": " << r.err;
    EXPECT_NE(r.err.find("cannot write to"), std::string::npos) << option << ": " << r.err;
    EXPECT_NE(r.out.find("final score:"), std::string::npos) << option << ": " << r.out;
    EXPECT_NE(r.out.find("30 s played"), std::string::npos) << option << ": " << r.out;
  }
}

// Readers take a log cut short by a kill: the whole lines, and a warning naming the cut.
TEST(FaultReaders, ALogCutShortIsReadToItsLastWholeLineWithAWarning) {
  Scratch s("fault_torn");
  {
    std::ofstream(s / "plain.jsonl") << "{\"t\":1}\n{\"t\":2}\n{\"t\":3,\"ty";
  }
  std::string torn;
  EXPECT_EQ(lines_of(s / "plain.jsonl", &torn), (std::vector<std::string>{"{\"t\":1}", "{\"t\":2}"}));
  EXPECT_NE(torn.find("plain.jsonl:3: the last line is cut short after 10 bytes"), std::string::npos) << torn;

  // A compressed log cut anywhere reads up to where its stream stops.
  std::string text;
  for (int k = 0; k < 2000; ++k) text += "{\"t\":" + std::to_string(k) + ",\"type\":\"bounce\"}\n";
  {
    gzFile gz = gzopen((s / "whole.jsonl.gz").c_str(), "wb");
    gzwrite(gz, text.data(), unsigned(text.size() / 2));
    gzflush(gz, Z_SYNC_FLUSH);
    gzwrite(gz, text.data() + text.size() / 2, unsigned(text.size() - text.size() / 2));
    gzclose(gz);
  }
  const std::string packed = slurp(s / "whole.jsonl.gz");
  EXPECT_EQ(lines_of(s / "whole.jsonl.gz", &torn).size(), 2000u);
  EXPECT_EQ(torn, "");
  std::ofstream(s / "cut.jsonl.gz", std::ios::binary) << packed.substr(0, packed.size() * 2 / 3);
  const std::vector<std::string> cut = lines_of(s / "cut.jsonl.gz", &torn);
  EXPECT_GE(cut.size(), 900u);
  EXPECT_LT(cut.size(), 2000u);
  for (size_t k = 0; k < cut.size(); ++k) EXPECT_EQ(cut[k] + '\n', split(text)[k] + '\n');
  EXPECT_NE(torn, "");

  // Not a file: refused at once, not waited on.
  ASSERT_EQ(mkfifo((s / "fifo").c_str(), 0600), 0);
  EXPECT_THROW(LineReader{s / "fifo"}, std::runtime_error);
  EXPECT_THROW(LineReader{s.dir.string()}, std::runtime_error);
}

// The audit reads a decision log compressed, or cut short by a killed match (with a warning).
TEST(FaultReaders, TheAuditReadsCompressedAndCutShortLogs) {
  Scratch s("fault_audit");
  const std::string match = "play airhockey --seconds 60 --audio none --pace fast --seed 5 ";
  ASSERT_EQ(run(s, match + "--decisions " + (s / "d.jsonl") + " --events " + (s / "e.jsonl")).status, 0);
  ASSERT_EQ(run(s, match + "--decisions " + (s / "d.jsonl.gz") + " --events " + (s / "e.jsonl.gz")).status, 0);
  // The same lines, a quarter of the bytes or less.
  EXPECT_EQ(lines_of(s / "d.jsonl.gz"), lines_of(s / "d.jsonl"));
  EXPECT_EQ(lines_of(s / "e.jsonl.gz"), lines_of(s / "e.jsonl"));
  EXPECT_LT(fs::file_size(s / "d.jsonl.gz") * 4, fs::file_size(s / "d.jsonl"));
  const Outcome packed = run(s, "audit " + (s / "d.jsonl.gz") + " " + (s / "e.jsonl.gz"));
  EXPECT_EQ(packed.status, 0) << packed.out << packed.err;
  EXPECT_NE(packed.out.find("audit: passed"), std::string::npos) << packed.out;

  // A line half written at the end: the whole ones are audited, the cut one named.
  const std::string plain = slurp(s / "d.jsonl");
  const std::vector<std::string> lines = split(plain);
  std::ofstream(s / "cut.jsonl", std::ios::binary) << plain << lines.back().substr(0, lines.back().size() / 2);
  const Outcome cut = run(s, "audit " + (s / "cut.jsonl"));
  EXPECT_EQ(cut.status, 0) << cut.out << cut.err;
  EXPECT_NE(cut.err.find("the last line is cut short"), std::string::npos) << cut.err;
  EXPECT_NE(cut.out.find(std::to_string(lines.size() - 1) + " draws"), std::string::npos) << cut.out;
}

}  // namespace
