#include "engine/call_sites.hpp"

#include "plugins/kinds.hpp"

namespace gdsmc::host {

// texts_ is sized first, so that no string moves after a site points into it.
CallSites::CallSites(const Pipeline& p, const std::uint64_t* step) : run_name_(thread_run_name()) {
  std::vector<const PluginUse*> uses{&p.initial_state, &p.collision};
  for (const auto& u : p.forcings) uses.push_back(&u);
  for (std::size_t s = 0; s < p.boundaries.size() && s < 2; ++s) uses.push_back(&p.boundaries[s]);
  for (const auto& u : p.diagnostics) uses.push_back(&u);
  texts_.reserve(uses.size());
  sites_.reserve(uses.size());
  for (const PluginUse* u : uses) {
    texts_.push_back(u->path + ", " + u->where.str());
    PluginCallSite site;
    site.plugin = u->plugin ? u->plugin->descriptor->name.c_str() : "?";
    const PluginKindInfo* kind = u->plugin ? find_kind(u->plugin->descriptor->kind) : nullptr;
    site.role = kind ? kind->role : "plugin";
    site.where = texts_.back().c_str();
    site.step = step;
    site.run = run_name_.c_str();
    sites_.push_back(site);
    uses_.push_back(u);
  }
}

const PluginCallSite& CallSites::of(const PluginUse& use) const {
  for (std::size_t k = 0; k < uses_.size(); ++k)
    if (uses_[k] == &use) return sites_[k];
  static const PluginCallSite unknown{};
  return unknown;
}

}  // namespace gdsmc::host
