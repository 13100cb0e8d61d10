// Plugin entries of a pipeline: the plugin they name, their parameters checked against the
// plugin's ParamSpec list (type, range, unit) and converted to reduced units.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config/pipeline.hpp"
#include "config/yaml_reader.hpp"
#include "plugins/kinds.hpp"

namespace gdsmc::host {

// Keys of a plugin entry that belong to the pipeline, not to the plugin's parameters:
// reserved_keys and all_reserved_keys (plugins/kinds.hpp).

// Check one plugin entry (a bare name or {plugin: NAME, ...}) against the plugins found and
// test-construct the plugin. Returns nullopt after recording every problem in `c`.
std::optional<PluginUse> check_plugin(Checker& c, const std::shared_ptr<const PluginRegistry>& plugins, Pipeline& p,
                                      const YAML::Node& node, const std::string& path, PluginKind kind);

// One value at `sub` read against `spec`, as every plugin parameter and every key of the host's
// own schema (config/host_schema.hpp) is: its type, its unit ({value, unit} or a bare number in
// the reference unit, converted to reduced units), its range and its choices (with the closest
// spellings). `who` names it in errors ("parameter 'alpha' of ...", "run.particles"). Returns
// nullopt after recording the problem in `c`.
std::optional<ParamValue> read_value(Checker& c, Pipeline& p, const ParamSpec& spec, const YAML::Node& v,
                                     const std::string& sub, const std::string& who);

}  // namespace gdsmc::host
