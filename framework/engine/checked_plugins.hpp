// The collision rule and the boundaries as the engine's stages call them: each call marked for the
// fatal-signal handler (engine/plugin_calls.hpp), and the collision rule's results checked for
// non-finite velocities as they leave each batch (a few compares per accepted pair, no pass over
// the particles), so that a rule that writes NaN or infinity is named at the step it does so; a
// forcing's velocities are checked after each apply() (first_non_finite_velocity).
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>

#include <gdsmc/plugin.hpp>

#include "engine/plugin_calls.hpp"

namespace gdsmc::host {

class CheckedCollisionRule final : public CollisionRule {
 public:
  void set(CollisionRule* rule, const PluginCallSite* site) {
    rule_ = rule;
    site_ = site;
  }
  void bind(const ParticleSpan& particles) override {
    PluginCall call(*site_, "bind");
    rule_->bind(particles);
  }
  KernelForm kernel_form() const override { return rule_->kernel_form(); }
  double pair_rate(const Vec3& g, const Vec3& s) const override { return rule_->pair_rate(g, s); }
  double rate_bound(double speed) const override {
    PluginCall call(*site_, "rate_bound");
    return rule_->rate_bound(speed);
  }
  void collide_batch(PairBatch& b) const override {
    {
      PluginCall call(*site_, "collide_batch");
      rule_->collide_batch(b);
    }
    // The sum of every pair's velocity components is NaN or infinite as soon as one of them is
    // (finite velocities do not add up to 1e308): four partial sums, no branch per pair, one test
    // per batch. A rejected pair holds the velocities it was handed: flag() tells them apart.
    double z[4] = {0, 0, 0, 0};
    for (std::uint32_t q = 0; q < b.count; ++q) {
      const Vec3 &a = b.v1[q], &c = b.v2[q];
      z[q & 3] += ((a.x + a.y) + (a.z + c.x)) + (c.y + c.z);
    }
    const double sum = (z[0] + z[1]) + (z[2] + z[3]);
    if (!(sum - sum == 0)) flag(b);
  }

  // Whether some accepted pair left a batch with a non-finite velocity, and the first one seen.
  bool wrote_non_finite() const { return bad_.load(std::memory_order_relaxed); }
  struct Bad {
    std::uint32_t cell = 0, i = 0, j = 0;
    Vec3 v1{0, 0, 0}, v2{0, 0, 0};
  };
  Bad first_bad() const { return bad_pair_; }
  // Whether some candidate pair was handed to the rule with a non-finite velocity (it came from
  // elsewhere: a forcing).
  bool handed_non_finite() const { return handed_.load(std::memory_order_relaxed); }

 private:
  // Rare: which pair. An accepted one left the rule non-finite (its fault); a rejected one was
  // handed to it so (another plugin's: the engine's moment check names it).
  void flag(const PairBatch& b) const {
    for (std::uint32_t q = 0; q < b.count; ++q) {
      const Vec3 &a = b.v1[q], &c = b.v2[q];
      const double z = (a.x - a.x) + (a.y - a.y) + (a.z - a.z) + (c.x - c.x) + (c.y - c.y) + (c.z - c.z);
      if (z == z) continue;  // finite: x - x is NaN only for NaN and infinities
      if (!b.accepted[q]) {
        handed_.store(true, std::memory_order_relaxed);
        continue;
      }
      if (bad_.exchange(true)) return;
      bad_pair_ = Bad{b.cell, b.i[q], b.j[q], a, c};
      return;
    }
  }
  CollisionRule* rule_ = nullptr;
  const PluginCallSite* site_ = nullptr;
  mutable std::atomic<bool> bad_{false}, handed_{false};
  mutable Bad bad_pair_;  // written once, by the thread that set bad_; read after the stage
};

// The first particle whose velocity is not finite, or count if every one is: what a forcing's
// apply() left (the host cannot see inside it). One pass over the three velocity columns with
// four partial sums each, no branch per particle (vectorised): the sum of finite velocities stays
// finite. Only a sum that is not (a non-finite velocity, or finite ones beyond 1e308 together)
// looks for the particle, which is then count when there is none.
inline std::size_t first_non_finite_velocity(const ParticleSpan& p) {
  const std::size_t n = p.count;
  double z[4] = {0, 0, 0, 0};
  if (p.vx.stride == 1 && p.vy.stride == 1 && p.vz.stride == 1) {
    const double* __restrict x = p.vx.data;
    const double* __restrict y = p.vy.data;
    const double* __restrict w = p.vz.data;
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
      for (std::size_t k = 0; k < 4; ++k) z[k] += (x[i + k] + y[i + k]) + w[i + k];
    for (; i < n; ++i) z[0] += (x[i] + y[i]) + w[i];
  } else {
    for (std::size_t i = 0; i < n; ++i) z[i & 3] += (p.vx[i] + p.vy[i]) + p.vz[i];
  }
  const double sum = (z[0] + z[1]) + (z[2] + z[3]);
  if (sum - sum == 0) return n;
  for (std::size_t i = 0; i < n; ++i)
    if (!(p.vx[i] - p.vx[i] == 0 && p.vy[i] - p.vy[i] == 0 && p.vz[i] - p.vz[i] == 0)) return i;
  return n;
}

class GuardedBoundary final : public Boundary {
 public:
  void set(Boundary* boundary, const PluginCallSite* site) {
    boundary_ = boundary;
    site_ = site;
  }
  void begin(const SystemInfo& system, const QuantityBoard& quantities, const Vec3& g) override {
    PluginCall call(*site_, "begin");
    boundary_->begin(system, quantities, g);
  }
  bool transfers() const override { return boundary_->transfers(); }
  HitResult interact(const StepContext& ctx, WallHit& hit, Rng& rng) const override {
    PluginCall call(*site_, "interact");
    return boundary_->interact(ctx, hit, rng);
  }

 private:
  Boundary* boundary_ = nullptr;
  const PluginCallSite* site_ = nullptr;
};

}  // namespace gdsmc::host
