// Readers of the pipeline's own sections (internal to config/): each records its problems in the
// Checker and fills the Pipeline.
#pragma once
#include <yaml-cpp/yaml.h>

#include "config/pipeline.hpp"
#include "config/yaml_reader.hpp"

namespace gdsmc::host {

void parse_run(Checker& c, const YAML::Node& run, Pipeline& p);
void parse_system(Checker& c, const YAML::Node& sys, Pipeline& p);
void parse_output(Checker& c, const YAML::Node& out, Pipeline& p);
void parse_sweep(Checker& c, const YAML::Node& sw, Pipeline& p);

}  // namespace gdsmc::host
