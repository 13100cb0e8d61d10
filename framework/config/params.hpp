// Plugin entries of a pipeline: the plugin they name, their parameters checked against the
// plugin's ParamSpec list (type, range, unit) and converted to reduced units.
#pragma once
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

// Check one plugin entry (a bare name or {plugin: NAME, ...}) and test-construct the plugin.
// Returns nullopt after recording every problem in `c`.
std::optional<PluginUse> check_plugin(Checker& c, Pipeline& p, const YAML::Node& node, const std::string& path,
                                      PluginKind kind);

}  // namespace gdsmc::host
