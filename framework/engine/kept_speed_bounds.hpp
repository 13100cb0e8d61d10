// Kept speed bounds of a homogeneous system that only collides (CollisionStage::set_collisions_only):
// particle i's peculiar speed |v_i - u| (u the mean velocity at the build) is at most
// speed(level(i)), a byte per particle. Level q < kLevels - 1 bounds speeds up to q times the level
// step kTop sqrt(T/m) / (kLevels - 2) at the build's T, the last level any speed (and NaN). Two
// levels thus bound |g| (triangle inequality), with room for every rounding of a rule's |g|: a
// uniform candidate whose acceptance number u has u w >= speed(a) + speed(b) would be rejected by
// the hard-sphere kernel (u w >= |g|), and one that could exceed w passes. Built in one pass, then
// set after every accepted pair: 1 MB at 10^6 particles, read where the velocities' three arrays
// (24 MB) were.
#pragma once
#include <cstdint>
#include <vector>

#include <gdsmc/plugin.hpp>

namespace gdsmc::host {

class KeptSpeedBounds {
 public:
  static constexpr int kLevels = 256;
  static constexpr double kTop = 8.0;  // the highest finite level, in sqrt(T/m) of the build

  // Whether the bounds hold for `particles` at the thermal speed `unit` = sqrt(T/m): built for this
  // storage and not invalidated since, with sqrt(T) within [0.7, 1.42] of the build's (the levels'
  // resolution).
  bool current(const ParticleSpan& particles, double unit) const {
    return valid_ && vx_ == particles.vx.data && count_ == particles.count && unit > 0.7 * unit_ &&
           unit < 1.42 * unit_;
  }
  void build(const ParticleSpan& particles, double unit);
  void invalidate() { valid_ = false; }
  // The level of a velocity: strictly above its speed.
  std::uint8_t level(double vx, double vy, double vz) const;
  std::uint8_t* levels() { return levels_.data(); }
  const double* speeds() const { return speed_; }  // the bound of each level

 private:
  std::vector<std::uint8_t> levels_;
  double speed_[kLevels] = {};
  double velocity_[3] = {0, 0, 0}, unit_ = 0, inverse_step_ = 0;
  const double* vx_ = nullptr;  // the storage the bounds were built for
  std::size_t count_ = 0;
  bool valid_ = false;
};

}  // namespace gdsmc::host
