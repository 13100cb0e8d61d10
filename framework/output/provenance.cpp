#include "output/provenance.hpp"

#include <gdsmc/plugin.hpp>

#include "util/content_hash.hpp"

namespace gdsmc::host {

std::vector<PluginProvenance> plugin_provenance(const Pipeline& p) {
  std::vector<PluginProvenance> out;
  auto prov = [&](const std::string& role, const PluginUse& u) {
    PluginProvenance pp{role, u.instance_name, u.plugin->descriptor->name, u.plugin->descriptor->version,
                        u.plugin->file.string(), ContentHash::hex(u.plugin->content_hash), {}};
    for (const auto& [k, e] : u.params.entries()) pp.parameters[k] = value_text(e.value);
    out.push_back(std::move(pp));
  };
  prov("initial_state", p.initial_state);
  prov("collision", p.collision);
  for (const auto& u : p.forcings) prov(u.path, u);
  for (std::size_t s = 0; s < p.boundaries.size() && s < 2; ++s)  // boundaries: {y: ...} gives both planes one path
    prov(s == 0 ? "boundaries.y_min" : "boundaries.y_max", p.boundaries[s]);
  for (const auto& u : p.diagnostics) prov(u.path, u);
  return out;
}

void describe_provenance(const Pipeline& p, StudyOutput& out) {
  out.root_attributes["gdsmc_version"] = version_string;
  out.root_attributes["sdk_abi"] = std::to_string(sdk_abi_major) + "." + std::to_string(sdk_abi_minor);
  out.root_attributes["pipeline"] = p.resolved_text;
  out.root_attributes["pipeline_source"] = p.source_text;
  out.root_attributes["pipeline_file"] = p.file.string();
  std::string sets;
  for (const auto& o : p.overrides) sets += (sets.empty() ? "" : "\n") + o;
  out.root_attributes["overrides"] = sets;
  out.root_attributes["units"] =
      "each dataset's 'unit' attribute names its unit: the host's datasets use tau0 = lambda0 / sqrt(2 T0 / m), "
      "lambda0 = 1 / (sqrt(2) pi n sigma^2), sqrt(2 T0/m) and T0, plugins may use their problem's scales (W, T_w); "
      "the /system attributes are in reduced units (m = 1, k_B = 1, lengths in the unit of sigma)";
  out.root_numbers["seed"] = static_cast<double>(p.seed);
  out.root_numbers["realizations"] = p.realizations;
}

}  // namespace gdsmc::host
