// The plugin kinds, one row each: what the loader, `gdsmc plugins`, the pipeline, the parameter
// checks, the crash handler and conformance know of a kind. A new kind is a new row here (and its
// SDK class); nothing else lists the kinds.
#pragma once
#include <array>
#include <string>
#include <vector>

#include <gdsmc/plugin.hpp>

namespace gdsmc::host {

struct PluginKindInfo {
  PluginKind kind;           // named as gdsmc::to_string names it ("collision", "initial", ...)
  const char* role;         // in messages: "collision rule", "initial state", ...
  const char* first_entry;  // the key path of its first entry in a pipeline: "collision", "forcings[0]", ...
  bool writes_output;       // a diagnostic: it has an output group, and sample_every and record_every
  // Conformance: the pipeline entry (YAML flow text) that fills this kind's required slot in a
  // pipeline built around a plugin of another kind, when the search path has that plugin declaring
  // what the entry sets; nullptr: the slot is optional, or no entry is preferred.
  const char* stand_in;
};

// In the order `gdsmc plugins` lists them.
inline constexpr std::array<PluginKindInfo, 5> kPluginKinds = {{
    // An inelastic gas, so that rules, forcings and diagnostics see dissipation.
    {PluginKind::collision_rule, "collision rule", "collision", false, "{plugin: inelastic_hard_spheres, alpha: 0.8}"},
    {PluginKind::forcing, "forcing", "forcings[0]", false, nullptr},
    {PluginKind::boundary, "boundary", "boundaries.y", false, nullptr},
    {PluginKind::initial_state, "initial state", "initial_state", false, "maxwellian"},
    {PluginKind::diagnostic, "diagnostic", "diagnostics[0]", true, nullptr},
}};

// The row of `kind` (a kind no row has: a descriptor from a newer SDK; the loader refuses it).
const PluginKindInfo* find_kind(PluginKind kind);
const PluginKindInfo& kind_info(PluginKind kind);  // throws std::logic_error for a kind no row has

// The keys of a pipeline entry that the host reads and a plugin's schema may not use: plugin, name
// and, for a kind that writes output, sample_every and record_every.
const std::vector<std::string>& reserved_keys(PluginKind kind);
const std::vector<std::string>& all_reserved_keys();  // of every kind

}  // namespace gdsmc::host
