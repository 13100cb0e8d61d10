// The host's own keys that hold one value -- run.seed, run.particles, run.sampling, system.density,
// output.plots, ... -- declared as a plugin declares its parameters (gdsmc::ParamSpec: type, range,
// choices, default, doc) and read by the same read_value (config/params.hpp), so that they get the
// same units, ranges and did-you-mean. Keys with a grammar of their own (run.time_step, run.stop,
// run.checkpoint, run.average_after, run.subpopulation, system.domain, system.box, system.layers,
// output.file) are read by their sections and only named here.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <gdsmc/params.hpp>

#include "config/pipeline.hpp"
#include "config/yaml_reader.hpp"

namespace gdsmc::host {

struct HostKey {
  ParamSpec spec;
  std::function<void(Pipeline&, const ParamValue&)> apply;  // stores the value (reduced units) read
};

struct HostSection {
  std::string name;                      // "run", "system", "output"
  std::vector<HostKey> values;           // the keys of one value
  std::vector<std::string> other_keys;   // the keys read by their own grammar
  std::vector<std::string> keys() const;  // every key of the section
};

const HostSection& run_section();
const HostSection& system_section();
const HostSection& output_section();

// Read every key of `section.values` that `node` gives (its default otherwise, when it has one).
void read_host_values(Checker& c, const YAML::Node& node, const HostSection& section, Pipeline& p);

}  // namespace gdsmc::host
