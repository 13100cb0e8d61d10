// The majorant of the hard-sphere acceptance rate used by the collision stage (engine), the
// conformance harness and the benchmark, and the bounds on the work of one collision stage: one
// definition.
#pragma once
#include <cmath>

namespace gdsmc::host {

// Initial majorant of the hard-sphere acceptance rate |g| in units of sqrt(T/m): for a Maxwellian
// |g| / sqrt(T/m) is sqrt(2) chi_3, which exceeds 6 sqrt(2) with probability ~1e-7 per candidate.
// Exceedances are counted and raise the ratio (see CellCollision::majorant_exceeded).
constexpr double kInitialMajorantRatio = 6.0 * M_SQRT2;
// Factor over the largest rate seen when the majorant was exceeded.
constexpr double kMajorantHeadroom = 1.05;

// The most candidate pairs one collision stage may test (hard-sphere estimate P_c sigma^2 pi w dt
// / V_c summed over the cells), per step and per particle: beyond these a step no longer resolves
// collisions (a particle is tested a hundred times between two flights) and its work is absurd,
// so the run is refused rather than left to spin. At T0 a step of c tau0 tests about
// kInitialMajorantRatio c / 4 = 2.1 c candidates per particle.
constexpr double kMaxCandidatesPerStep = 1e9;
constexpr double kMaxCandidatesPerParticle = 100;
// A cell whose candidates may exceed this (general kernels draw 4 times the hard-sphere estimate)
// is processed in slices of dt, with a check for an interrupt between them: a few milliseconds each.
constexpr double kCandidatesPerSlice = 1 << 20;

}  // namespace gdsmc::host
