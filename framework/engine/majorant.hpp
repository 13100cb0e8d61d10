// The majorant of the hard-sphere acceptance rate used by the collision stage (engine), the
// conformance harness and the benchmark: one definition.
#pragma once
#include <cmath>

namespace gdsmc::host {

// Initial majorant of the hard-sphere acceptance rate |g| in units of sqrt(T/m): for a Maxwellian
// |g| / sqrt(T/m) is sqrt(2) chi_3, which exceeds 6 sqrt(2) with probability ~1e-7 per candidate.
// Exceedances are counted and raise the ratio (see CellCollision::majorant_exceeded).
constexpr double kInitialMajorantRatio = 6.0 * M_SQRT2;
// Factor over the largest rate seen when the majorant was exceeded.
constexpr double kMajorantHeadroom = 1.05;

}  // namespace gdsmc::host
