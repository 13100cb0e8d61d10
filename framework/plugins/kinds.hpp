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
};

// In the order `gdsmc plugins` lists them.
inline constexpr std::array<PluginKindInfo, 5> kPluginKinds = {{
    {PluginKind::collision_rule, "collision rule", "collision", false},
    {PluginKind::forcing, "forcing", "forcings[0]", false},
    {PluginKind::boundary, "boundary", "boundaries.y", false},
    {PluginKind::initial_state, "initial state", "initial_state", false},
    {PluginKind::diagnostic, "diagnostic", "diagnostics[0]", true},
}};

// The row of `kind` (a kind no row has: a descriptor from a newer SDK; the loader refuses it).
const PluginKindInfo* find_kind(PluginKind kind);
const PluginKindInfo& kind_info(PluginKind kind);  // throws std::logic_error for a kind no row has

// The keys of a pipeline entry that the host reads and a plugin's schema may not use: plugin, name
// and, for a kind that writes output, sample_every and record_every.
const std::vector<std::string>& reserved_keys(PluginKind kind);
const std::vector<std::string>& all_reserved_keys();  // of every kind

}  // namespace gdsmc::host
