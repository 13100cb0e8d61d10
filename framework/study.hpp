// A study: every case of a pipeline's sweep, each run for all its realizations, averaged, with
// steady-state averages, gathered into one output.
#pragma once
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "engine.hpp"
#include "output.hpp"
#include "pipeline.hpp"

namespace gdsmc::host {

struct StudyCase {
  std::string label;                                          // "collision.alpha=0.5, model=EHS"
  std::vector<std::pair<std::string, std::string>> axis_values;  // axis name -> value label
  Pipeline pipeline;
};

// Load and check every case of the sweep (the base pipeline alone when there is no sweep).
// Throws PipelineError naming the case on any problem, before anything runs.
std::vector<StudyCase> expand_cases(const Pipeline& base, const std::vector<std::string>& overrides,
                                    const std::vector<std::filesystem::path>& extra_plugin_paths);

// Average diagnostics over realizations, record by record (truncated to the shortest run):
// every series, scalar and array gets its mean, and with more than one realization a
// "<name>_stderr" companion (standard error of the mean over realizations).
std::vector<DiagnosticOutput> average_realizations(const std::vector<std::vector<DiagnosticOutput>>& runs,
                                                   std::vector<std::string>* summary);

// Steady-state averages: for every series, the mean over the records with s >= after_s (or
// t/tau0 >= after_t) and its batch-means standard error, as scalars "<series>.steady_mean" and
// "<series>.steady_stderr".
void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t);

struct StudyProgress {
  std::size_t run = 0, runs = 1;  // current run (case x realization), total
  std::string label;              // case label, realization
  Progress progress;              // of the current run
  double fraction = 0;            // of the whole study
  double remaining_seconds = -1;
};

struct StudyResult {
  StudyOutput output;
  std::vector<std::string> summary;  // lines for stdout
  double collisions = 0, wall_seconds = 0;
  std::uint64_t steps = 0;
};

StudyResult run_study(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                      double report_interval, const std::atomic<bool>* interrupt);

// File-level provenance of a pipeline: versions, the resolved pipeline text, seed, units.
void describe_provenance(const Pipeline& p, StudyOutput& out);

}  // namespace gdsmc::host
