// What one run (a realization of a case) gives its study, and its bytes: a run finished on another
// MPI rank reaches rank 0 as these bytes (study/ranks.hpp), which it gathers as if the run had
// been its own. Every value crosses bit for bit.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <gdsmc/state.hpp>

#include "engine/engine.hpp"
#include "output/records.hpp"

namespace gdsmc::host {

struct RunResults {
  std::optional<CaseOutput> output;  // realization 0 only (its diagnostics are left out: see below)
  std::vector<std::string> summary;  // realization 0 only
  std::vector<DiagnosticOutput> diagnostics;
  double collisions = 0, wall_seconds = 0;
  StageSeconds stage_seconds{};
  std::uint64_t steps = 0;
  bool steady = false;
};

// The bytes of `r`. output->diagnostics are not written (a study replaces them by the average of
// `diagnostics` over the realizations), nor particle datasets already staged in an open output
// file (only rank 0 has one: it never sends). Throws std::logic_error on a staged dataset.
std::vector<unsigned char> save_run_results(const RunResults& r);
// Throws StateError on bytes that save_run_results did not write.
RunResults load_run_results(const std::vector<unsigned char>& bytes);

}  // namespace gdsmc::host
