// The majorant of the hard-sphere acceptance rate used by the collision stage (engine), the
// conformance harness and the benchmark, and the bounds on the work of one collision stage: one
// definition.
#pragma once
#include <cmath>

namespace gdsmc::host {

// The majorant of the hard-sphere acceptance rate |g| in units of sqrt(T/m) that a group drawing
// uniform pairs starts from, and that a homogeneous system's groups return to at every moment
// update (as SPARTA resets its vremax): for a Maxwellian |g| / sqrt(T/m) is sqrt(2) chi_3, which
// exceeds 7 with probability 1.9e-5 per candidate, by 4 % on average, so that 2.4e-6 of the
// collisions are missed (a candidate above w is accepted once; PairBatch::missed counts the rest,
// written to /run/collisions_missed_by_majorant), while <|g|>/w = 32 % of the candidates collide
// (6 sqrt(2), the value before SDK 6.0: 1e-7, 27 %). Exceedances raise the ratio until the update.
constexpr double kInitialMajorantRatio = 7.0;
// <|g|> / sqrt(T/m) of a Maxwellian, 4 / sqrt(pi): a uniform draw against the ratio w accepts
// kMaxwellMeanRelativeSpeed / w of its candidates.
constexpr double kMaxwellMeanRelativeSpeed = 2.2567583341910251;
// The acceptance below which a homogeneous system of one group draws weighted pairs by default
// (run.pair_selection: auto; CollisionStage::collide_group): its uniform ratio above 7.52.
constexpr double kUniformAcceptanceFloor = 0.30;
// The collisions a homogeneous group may have missed since the start, as a fraction of those it
// made, and still let its ratio decay, by kMajorantDecay per moment update, towards
// kInitialMajorantRatio (CollisionStage::reset_majorants). Resetting to 7 at every update left USF
// IHS alpha = 0.5, a* = 4 missing 4.7e-4 of its collisions; never decaying, 1e-6 but 16 % accepted.
constexpr double kMissedCollisionsTolerance = 1e-5;
constexpr double kMajorantDecay = 0.97;
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
