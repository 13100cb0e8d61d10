// The cases of a study: every point of the pipeline's sweep, each a checked pipeline.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "config/pipeline.hpp"
#include "engine/memory_estimate.hpp"

namespace gdsmc::host {

struct StudyCase {
  std::string label;                                          // "collision.alpha=0.5, model=EHS"
  std::vector<std::pair<std::string, std::string>> axis_values;  // axis name -> value label
  Pipeline pipeline;
};

// Told how far a long check is: `done` of `total` cases through `stage` ("loaded", "set up").
// Called about every 2 s once a stage has taken 2 s; not at all for a quick check.
using CheckProgress = std::function<void(const char* stage, std::size_t done, std::size_t total)>;

// Load and check every case of the sweep (the base pipeline alone when there is no sweep), in time
// linear in the number of cases (SweepCaseLoader). Every case is resolved against the base pipeline's
// plugins: no library is loaded again. The first case carries the base's source and resolved
// text and --set overrides (the study's provenance); the others' texts are empty. Throws
// PipelineError before anything runs, each problem once, located where its value was given (a
// sweep value at its entry in the sweep) and naming the cases it occurs in.
// A sweep of more than kMaxSweepCases cases (the product of its axes' sizes, counted before
// anything is expanded) is refused naming the axes and the count.
inline constexpr double kMaxSweepCases = 100000;
double sweep_case_count(const Pipeline& p);
std::vector<StudyCase> expand_cases(const LoadedPipeline& base, const CheckProgress& progress = {});

// How many runs (case x realization) the study runs at once: run.threads of the first case (0:
// every core), at most the number of runs, at least 1.
// With `runs`: for that many of the study's runs (an MPI rank's share).
std::uint32_t study_threads(const std::vector<StudyCase>& cases);
std::uint32_t study_threads(const std::vector<StudyCase>& cases, std::size_t runs);
// The threads inside each run: what run.threads leaves over when fewer runs than threads go at
// once (a single run with run.threads 2 spreads its layers or sub-populations over 2 threads).
std::uint32_t threads_per_run(const std::vector<StudyCase>& cases);
std::uint32_t threads_per_run(const std::vector<StudyCase>& cases, std::size_t runs);

// Set up every case's plugins as validate does (Engine::check_setup) and estimate the study's
// memory from what they declared (study_threads() runs at once). Throws PipelineError naming the case(s) on a setup problem, and
// when the estimate exceeds the memory available (both figures, and what drives the estimate).
// A slab case with more sampling bins than kProbeBins is set up with kProbeBins first (plugins
// may allocate per bin), its estimate scaled to its bins, and set up for real only if it fits.
inline constexpr std::size_t kProbeBins = 4096;
MemoryEstimate check_cases(const std::vector<StudyCase>& cases, const CheckProgress& progress = {});

}  // namespace gdsmc::host
