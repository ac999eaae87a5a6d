#include "lua_sport.h"

#include <optional>

#include "engine_paths.h"
#include "reloader.h"

namespace quantum::tools {
namespace {

class LuaSport final : public runtime::SportSource {
 public:
  explicit LuaSport(const runtime::SportRequest& r)
      : rules_(std::make_unique<lua::ScriptedRules>(r.sport, r.engine.empty() ? lua::engine_rules_folder() : r.engine,
                                                    lua::Params(r.params))) {
    for (const auto& [kind, value] : r.factors) rules_->set_factor(kind, value);
    if (r.reloads != runtime::SportRequest::Reloads::None)
      reloader_.emplace(*rules_, r.factors, r.reloads == runtime::SportRequest::Reloads::Watched);
  }

  const game::SportSpec& spec() const override { return rules_->spec(); }
  game::Rules& rules() override { return *rules_; }
  void changed(const std::filesystem::path& file) override { reloader_->changed(file); }
  int reload(game::Match& match, std::ostream& errors, std::vector<std::filesystem::path>* acted_on) override {
    return reloader_->poll(rules_, match, errors, acted_on);
  }
  const std::map<std::string, std::string>& failures() const override { return reloader_->failures(); }

  lua::ScriptedRules& scripted() { return *rules_; }

 private:
  std::unique_ptr<lua::ScriptedRules> rules_;
  std::optional<lua::Reloader> reloader_;
};

}  // namespace

std::unique_ptr<runtime::SportSource> lua_sport(const runtime::SportRequest& request) {
  return std::make_unique<LuaSport>(request);
}

lua::ScriptedRules& scripted_rules(runtime::Session& session) {
  auto* lua = dynamic_cast<LuaSport*>(&session.source());
  if (!lua) throw std::logic_error("this session's sport is not written in Lua (tools::lua_sport)");
  return lua->scripted();
}

}  // namespace quantum::tools
