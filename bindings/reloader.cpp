#include "reloader.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ostream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace quantum::lua {
namespace fs = std::filesystem;

Reloader::Reloader(const ScriptedRules& sport, std::map<std::string, double> factors, bool watch_files)
    : folder_(fs::path(sport.folders().folder).lexically_normal()), factors_(std::move(factors)) {
  fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(std::string("cannot watch the rules: ") + std::strerror(errno));
  for (const fs::path& f : sport.folders().powerups) powerup_folders_.insert(f.lexically_normal());
  for (const fs::path& f : sport.folders().modules) module_folders_.insert(f.lexically_normal());
  std::set<fs::path> folders = powerup_folders_;
  folders.insert(module_folders_.begin(), module_folders_.end());
  // Editors save in place (close after write) or write a new file and rename it over the old.
  const uint32_t mask = IN_CLOSE_WRITE | IN_MOVED_TO;
  for (const fs::path& dir : folders) {
    if (!watch_files || !fs::is_directory(dir)) continue;
    const int wd = inotify_add_watch(fd_, dir.c_str(), mask);
    if (wd >= 0) watches_[wd] = dir;
  }
}

Reloader::~Reloader() {
  if (fd_ >= 0) close(fd_);
}

void Reloader::changed(const fs::path& file) { changed_.insert(file.lexically_normal()); }

int Reloader::poll(std::unique_ptr<ScriptedRules>& sport, game::Match& match, std::ostream& errors,
                   std::vector<fs::path>* acted_on) {
  alignas(inotify_event) char buf[8192];
  for (ssize_t n; (n = read(fd_, buf, sizeof buf)) > 0;) {
    for (char* p = buf; p < buf + n;) {
      const auto* e = reinterpret_cast<const inotify_event*>(p);
      if (e->len > 0 && watches_.count(e->wd)) changed(watches_[e->wd] / e->name);
      p += sizeof(inotify_event) + e->len;
    }
  }
  if (changed_.empty()) return 0;
  const std::set<fs::path> files = std::exchange(changed_, {});
  bool sport_changed = false;
  std::vector<std::string> powerups;
  for (const fs::path& file : files) {
    if (file.extension() != ".lua") continue;
    const fs::path dir = file.parent_path();
    // Whatever changed may be read later (a power-up granted for the first time, a field in the
    // next match): a recording keeps it all.
    if (acted_on) acted_on->push_back(file);
    if (file == sport->spec().field_file) {
      field_waits(file, errors);
      continue;
    }
    const bool module = module_folders_.count(dir) > 0;  // sport.lua, or a module it may require
    const bool powerup = !module && powerup_folders_.count(dir) && sport->has_powerup(file.stem().string());
    sport_changed |= module;
    if (powerup) powerups.push_back(file.stem().string());
  }
  if (sport_changed) {
    // A new sport loads the power-ups in use afresh when it first needs them.
    try {
      auto fresh = ScriptedRules::reload(*sport);
      for (const auto& [kind, value] : factors_) fresh->set_factor(kind, value);
      // The new rules hear whatever on_reload sets off; the old ones are still there to read.
      match.set_rules(*fresh);
      fresh->take_over(*sport, match);
      if (fresh->spec().field_file != sport->spec().field_file) field_waits(fresh->spec().field_file, errors);
      sport = std::move(fresh);
      errors << "quantum: reloaded " << (folder_ / "sport.lua").string() << '\n';
      // The new sport loads the power-ups afresh: an old failure of theirs is its to repeat.
      failures_.clear();
      return 1 + int(powerups.size());
    } catch (const std::exception& e) {
      match.set_rules(*sport);
      errors << "quantum: reload failed: " << e.what() << " (the previous version goes on)\n";
      failures_["sport.lua"] = e.what();
    }
  }
  if (powerups.empty()) return 0;
  const std::vector<std::string> failed = sport->reload_powerups(powerups, match);
  int reloaded = 0;
  for (size_t k = 0; k < powerups.size(); ++k) {
    if (failed[k].empty()) {
      errors << "quantum: reloaded power-up " << powerups[k] << '\n';
      failures_.erase(powerups[k]);
      ++reloaded;
    } else {
      errors << "quantum: reload failed: " << failed[k] << " (the previous version goes on)\n";
      failures_[powerups[k]] = failed[k];
    }
  }
  return reloaded;
}

void Reloader::field_waits(const fs::path& file, std::ostream& errors) {
  if (std::exchange(field_told_, true)) return;
  errors << "quantum: " << file.string() << " changed: the new field takes effect at the next match\n";
}

}  // namespace quantum::lua
