// The limits of a run's work that a pipeline is checked against before anything runs
// (config/run_section.cpp) and that the engine enforces while it runs: one definition, read by
// both.
#pragma once

namespace gdsmc::host {

// The most steps a run may need to reach its stop: beyond this it would not end in any sane time
// (1e12 steps of even a tiny system take weeks), so the pipeline or the run is refused.
constexpr double kMaxSteps = 1e12;

// The majorant of the hard-sphere acceptance rate |g| in units of sqrt(T/m) that a group drawing
// uniform pairs starts from, and that a homogeneous system's groups return to at every moment
// update (as SPARTA resets its vremax): for a Maxwellian |g| / sqrt(T/m) is sqrt(2) chi_3, which
// exceeds 7 with probability 1.9e-5 per candidate, by 4 % on average, so that 2.4e-6 of the
// collisions are missed (a candidate above w is accepted once; PairBatch::missed counts the rest,
// written to /run/collisions_missed_by_majorant), while <|g|>/w = 32 % of the candidates collide
// (6 sqrt(2), the value before SDK 6.0: 1e-7, 27 %). Exceedances raise the ratio until the update.
constexpr double kInitialMajorantRatio = 7.0;

// The most candidate pairs one collision stage may test (hard-sphere estimate P_c sigma^2 pi w dt
// / V_c summed over the cells), per step and per particle: beyond these a step no longer resolves
// collisions (a particle is tested a hundred times between two flights) and its work is absurd,
// so the run is refused rather than left to spin. At T0 a step of c tau0 tests about
// kInitialMajorantRatio c / 4 = 2.1 c candidates per particle.
constexpr double kMaxCandidatesPerStep = 1e9;
constexpr double kMaxCandidatesPerParticle = 100;

}  // namespace gdsmc::host
