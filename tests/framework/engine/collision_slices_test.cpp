// The collision stage (engine/collision_stage.cpp) bounds its work: a large cell is collided in
// slices of the step with the candidates of the whole step, an interrupt is polled between slices,
// and absurd work is refused before any pair is tested. In-process, with a rule that records what
// it is handed.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/collision_stage.hpp"
#include "engine/majorant.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// Counts the pairs the host hands it, rejects every one, and can set an interrupt flag on its first
// call (a signal arriving while the first slice runs). One thread only (no pool in these tests).
class RecordingRule final : public gdsmc::CollisionRule {
 public:
  void bind(const gdsmc::ParticleSpan&) override {}
  gdsmc::KernelForm kernel_form() const override { return gdsmc::KernelForm::hard_sphere; }
  double pair_rate(const gdsmc::Vec3&, const gdsmc::Vec3&) const override { return 0; }
  double rate_bound(double speed) const override { return speed; }
  void collide_batch(gdsmc::PairBatch& b) const override {
    pairs += b.count;
    for (std::uint32_t q = 0; q < b.count; ++q) b.accepted[q] = 0;
    if (set_on_first_call) set_on_first_call->store(true);
  }
  mutable std::uint64_t pairs = 0;
  std::atomic<bool>* set_on_first_call = nullptr;
};

// One homogeneous cell of N particles at T = 1 and the dt that gives `per_particle` hard-sphere
// candidates per particle.
struct Cell {
  std::size_t n = 200000;
  double volume = 1e8;
  host::CellGrid grid;
  gdsmc::ParticleSpan span;
  host::StreamFactory streams{7, 0};
  std::vector<double> vx, vy, vz;  // all at rest: the rule reads nothing
  Cell() : vx(n), vy(n), vz(n) {
    grid.homogeneous(n, volume);
    span.count = n;
    span.vx = vx.data(); span.vy = vy.data(); span.vz = vz.data();
  }
  double dt_for(double per_particle) const {
    const double pairs = host::pair_count(host::PairCount::distinct, static_cast<std::uint32_t>(n));
    return per_particle * static_cast<double>(n) * volume / (pairs * M_PI * host::kInitialMajorantRatio);
  }
  host::CollisionStage::Totals run(host::CollisionStage& stage, const RecordingRule& rule, double dt) {
    return stage.run(rule, span, grid, nullptr, 1.0, 1.0, 1.0, dt, streams);
  }
};

// A cell of 4e6 candidates (x 4 for a general kernel > 2^20) is collided in slices of dt with the
// remainder carried from slice to slice, so its count is that of the whole step at once, and every
// candidate reaches the rule.
TEST(CollisionSlices, ALargeCellsSlicesTestTheCandidatesOfTheWholeStep) {
  Cell cell;
  RecordingRule rule;
  host::CollisionStage stage;
  const auto t = cell.run(stage, rule, cell.dt_for(20));
  EXPECT_NEAR(static_cast<double>(t.candidates), 20 * 200000.0, 1.0);
  EXPECT_EQ(rule.pairs, t.candidates);
  EXPECT_EQ(t.accepted, 0u);
}

// An interrupt that arrives during the first slice ends the stage before the next one: the rule
// has seen at most one slice's candidates (16 slices here).
TEST(CollisionSlices, TheCollisionStagePollsTheInterruptBetweenSlices) {
  Cell cell;
  std::atomic<bool> flag{false};
  RecordingRule rule;
  rule.set_on_first_call = &flag;
  host::CollisionStage stage;
  stage.set_interrupt(&flag);
  EXPECT_THROW(cell.run(stage, rule, cell.dt_for(20)), host::Interrupted);
  const double slices = std::ceil(4 * 20 * 200000.0 / host::kCandidatesPerSlice);
  EXPECT_GT(rule.pairs, 0u);
  EXPECT_LE(static_cast<double>(rule.pairs), std::ceil(20 * 200000.0 / slices) + 1);
}

// More than 100 candidates per particle, or a count that is not finite, is refused before any
// pair is tested.
TEST(CollisionSlices, TheCollisionStageRefusesAbsurdWorkBeforeDoingAny) {
  Cell cell;
  for (const double dt : {cell.dt_for(150), HUGE_VAL, std::nan("")}) {
    RecordingRule rule;
    host::CollisionStage stage;
    try {
      cell.run(stage, rule, dt);
      ADD_FAILURE() << "dt " << dt << " was not refused";
    } catch (const host::CollisionStage::Overload& e) {
      EXPECT_TRUE(contains(e.what(), "candidate pairs")) << e.what();
    }
    EXPECT_EQ(rule.pairs, 0u);
  }
}

}  // namespace
}  // namespace gdsmc::test
