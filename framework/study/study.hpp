// A study: every case of a pipeline's sweep, each run for all its realizations, averaged, with
// steady-state averages, gathered into one output.
#pragma once
#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/decomposition.hpp"
#include "engine/engine.hpp"
#include "output/provenance.hpp"
#include "output/records.hpp"
#include "study/cases.hpp"
#include "study/checkpoint.hpp"
#include "study/statistics.hpp"

namespace gdsmc::host {

struct StudyProgress {
  std::size_t run = 0, runs = 1;  // current run (case x realization), total
  std::string label;              // case label, realization
  Progress progress;              // of the current run
  double fraction = 0;            // of the whole study (every case and realization)
  double elapsed_seconds = 0;     // since the study began (progress.elapsed_seconds: this run only)
  double remaining_seconds = -1;  // of the whole study; -1 while unknown
};

struct StudyResult {
  StudyOutput output;
  std::vector<std::string> summary;  // lines for stdout
  double collisions = 0, wall_seconds = 0;
  std::uint64_t steps = 0;
  std::uint32_t threads = 1;  // runs that ran at once
  // An MPI job's rank 0: the runs received from the other ranks (study/ranks.hpp), their bytes, and
  // the seconds spent receiving, reading and gathering them (0 without MPI).
  std::size_t received_runs = 0;
  double received_bytes = 0, received_seconds = 0;
};

// A run failed on another rank of an MPI job; the message is that rank's ("rank R: ...").
struct RankFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Another rank of an MPI job ended without a word (killed by a signal, crashed): the message names
// it and the runs it had under way.
struct RankLost : RankFailure {
  using RankFailure::RankFailure;
};

// Runs every case and realization, study_threads() at a time; the output (every dataset and value,
// the summary lines) is the same for any number of threads. The first run that fails (in study
// order) is rethrown once the others have stopped; an interrupt throws Engine::Interrupted.
// With `checkpoints`, every run resumes from its saved state where there is one and saves its
// state as its pipeline's run.checkpoint says (at an interrupt and when it finishes in any case).
// In an MPI job (study/ranks.hpp) every rank calls it: each runs its share of the runs, balanced by
// their expected cost, and rank 0 returns the study's result, the same bits as a serial study
// (the other ranks return an empty one); a failure on any rank stops every rank, and rank 0
// throws it (RankFailure for another rank's, RankLost for a rank that died, Engine::Interrupted
// when a rank was interrupted). `particles`, when given, takes realization 0's final particles
// (output.particles) as each case's run ends (OutputFile::stager); without it they are copied.
// With `ranks` (`gdsmc run --decompose`, engine/decomposition.hpp) every rank takes part in every
// run, one run after the other, each slab decomposed over the ranks by layers; rank 0 returns the
// result (the serial bits), the others an empty one. A failure on any rank ends the job
// (job::abort_job): the other ranks would wait for it in their next collective.
StudyResult run_study(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                      double report_interval, const std::atomic<bool>* interrupt,
                      const CheckpointStore* checkpoints = nullptr, const ParticleStager* particles = nullptr,
                      Decomposition* ranks = nullptr);

}  // namespace gdsmc::host
