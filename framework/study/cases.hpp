// The cases of a study: every point of the pipeline's sweep, each a checked pipeline.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "config/pipeline.hpp"

namespace gdsmc::host {

struct StudyCase {
  std::string label;                                          // "collision.alpha=0.5, model=EHS"
  std::vector<std::pair<std::string, std::string>> axis_values;  // axis name -> value label
  Pipeline pipeline;
};

// Load and check every case of the sweep (the base pipeline alone when there is no sweep).
// Every case shares the base pipeline's plugin registry: no library is loaded again.
// Throws PipelineError naming the case on any problem, before anything runs.
std::vector<StudyCase> expand_cases(const Pipeline& base, const std::vector<std::string>& overrides,
                                    const std::vector<std::filesystem::path>& extra_plugin_paths);

}  // namespace gdsmc::host
