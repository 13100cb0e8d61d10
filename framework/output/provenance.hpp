// Provenance written with the results: the file-level record of a pipeline (versions, resolved
// pipeline text, seed, units) and the per-plugin record of each case.
#pragma once
#include <vector>

#include "config/pipeline.hpp"
#include "output/records.hpp"

namespace gdsmc::host {

// Every plugin of the pipeline: role, instance, plugin name, version, library and parameters.
std::vector<PluginProvenance> plugin_provenance(const Pipeline& p);

// File-level provenance of a pipeline: versions, the resolved pipeline text, seed, units.
void describe_provenance(const Pipeline& p, StudyOutput& out);

}  // namespace gdsmc::host
