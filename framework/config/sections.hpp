// Readers of the pipeline's own sections (internal to config/): each records its problems in the
// Checker and fills the Pipeline.
#pragma once
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "config/pipeline.hpp"
#include "config/yaml_reader.hpp"

namespace gdsmc::host {

void parse_run(Checker& c, const YAML::Node& run, Pipeline& p);
void parse_system(Checker& c, const YAML::Node& sys, Pipeline& p);
// system.species (config/species_section.cpp).
void parse_species(Checker& c, const YAML::Node& species, Pipeline& p);
// A time in tau0: a bare number or {value: T, unit: tau0}, at `key` (e.g. "run.stop.time").
// A value without its unit is a bare number in tau0 (listed, or refused with units: explicit).
std::optional<double> time_in_tau0(Checker& c, const YAML::Node& t, const std::string& key, Pipeline& p);
void parse_output(Checker& c, const YAML::Node& out, Pipeline& p);
void parse_sweep(Checker& c, const YAML::Node& sw, Pipeline& p);
// units: reference (default) or explicit.
void parse_units(Checker& c, const YAML::Node& u, Pipeline& p);

// A dimensional value written as a bare number (`value`, in the reference unit of `d`) at `path`:
// listed in p.bare_values for the verdict; with units: explicit an error saying how to write it
// with its unit (returns false).
bool read_bare(Checker& c, Pipeline& p, const std::string& path, const YAML::Node& node, double value,
               const Dimensions& d);

}  // namespace gdsmc::host
