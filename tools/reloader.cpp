#include "reloader.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <set>
#include <stdexcept>

namespace quantum::tools {
namespace fs = std::filesystem;

RulesReloader::RulesReloader(const std::string& sport_folder, std::map<std::string, double> factors)
    : folder_(sport_folder), factors_(std::move(factors)) {
  fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(std::string("cannot watch the rules: ") + std::strerror(errno));
  // Editors save in place (close after write) or write a new file and rename it over the old.
  const uint32_t mask = IN_CLOSE_WRITE | IN_MOVED_TO;
  fs::path sport = fs::path(sport_folder).lexically_normal();
  if (sport.filename().empty()) sport = sport.parent_path();  // "rules/practice/"
  folder_ = sport.string();
  for (const fs::path& dir : {sport, sport / "powerups", sport.parent_path() / "powerups"}) {
    if (!fs::is_directory(dir)) continue;
    const int wd = inotify_add_watch(fd_, dir.c_str(), mask);
    if (wd >= 0) watches_[wd] = dir.string();
  }
}

RulesReloader::~RulesReloader() {
  if (fd_ >= 0) close(fd_);
}

int RulesReloader::poll(std::unique_ptr<lua::Sport>& sport, game::Match& match, std::ostream& errors) {
  std::set<std::pair<std::string, std::string>> changed;  // folder, file
  alignas(inotify_event) char buf[8192];
  for (ssize_t n; (n = read(fd_, buf, sizeof buf)) > 0;) {
    for (char* p = buf; p < buf + n;) {
      const auto* e = reinterpret_cast<const inotify_event*>(p);
      if (e->len > 0 && watches_.count(e->wd)) changed.insert({watches_[e->wd], e->name});
      p += sizeof(inotify_event) + e->len;
    }
  }
  int reloaded = 0;
  const std::string& sport_dir = folder_;
  for (const auto& [dir, file] : changed) {
    if (fs::path(file).extension() != ".lua") continue;
    const std::string path = (fs::path(dir) / file).string();
    try {
      if (dir == sport_dir && file == "sport.lua") {
        auto fresh = std::make_unique<lua::Sport>(folder_);
        for (const auto& [kind, value] : factors_) fresh->set_factor(kind, value);
        // The new rules hear whatever on_reload sets off; the old ones are still there to read.
        match.set_rules(*fresh);
        fresh->take_over(*sport, match);
        sport = std::move(fresh);
        ++reloaded;
      } else if (dir == sport_dir && file == "field.lua") {
        errors << "quantum: " << path << " changed: a field takes effect in the next match\n";
      } else if (dir != sport_dir) {
        const std::string name = fs::path(file).stem().string();
        if (!sport->has_powerup(name)) continue;  // not in use: it loads as it is when granted
        sport->reload_powerup(name);
        ++reloaded;
      }
    } catch (const std::exception& e) {
      errors << "quantum: reload failed: " << e.what() << " (the previous version goes on)\n";
    }
  }
  return reloaded;
}

}  // namespace quantum::tools
