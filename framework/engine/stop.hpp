// When a run stops: the collisions-per-particle and time limits, and the steady-state test on a
// diagnostic series.
#pragma once
#include <optional>

#include <gdsmc/context.hpp>

#include "config/pipeline.hpp"
#include "config/work_limits.hpp"
#include "output/diagnostic_output.hpp"

namespace gdsmc::host {


// Whether the run has reached its stop condition (or is steady).
bool finished(const Pipeline& p, const StepContext& ctx, bool steady);

// Fraction of the stop condition reached, in [0, 1].
double stop_fraction(const Pipeline& p, const StepContext& ctx);

// The steady-state test on the series of `out` named by `st`: the means over the windows
// (s - 2W, s - W] and (s - W, s] of the last record differ by at most tolerance x the newer.
// Returns nullopt while there are too few records to tell; throws if the series does not exist.
std::optional<bool> is_steady(const SteadyStop& st, const DiagnosticOutput& out);

}  // namespace gdsmc::host
