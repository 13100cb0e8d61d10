// The majorant of the hard-sphere acceptance rate used by the collision stage (engine), the
// conformance harness and the benchmark (its starting ratio and the bounds on the work of a step
// are in config/work_limits.hpp, where the pipeline's checks read them): one definition.
#pragma once
#include <cmath>

#include "config/work_limits.hpp"

namespace gdsmc::host {

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

// A cell whose candidates may exceed this (general kernels draw 4 times the hard-sphere estimate)
// is processed in slices of dt, with a check for an interrupt between them: a few milliseconds each.
constexpr double kCandidatesPerSlice = 1 << 20;

}  // namespace gdsmc::host
