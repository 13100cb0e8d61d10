#include "engine/kept_speed_bounds.hpp"

#include <cmath>

namespace gdsmc::host {

std::uint8_t KeptSpeedBounds::level(double vx, double vy, double vz) const {
  const double dx = vx - velocity_[0], dy = vy - velocity_[1], dz = vz - velocity_[2];
  // Strictly above c / step, and above it by 1e-6 of a level at least: beyond the roundings of c
  // here and of |g| in the rule (4e-9 of the speed at the highest finite level).
  const double q = std::sqrt(dx * dx + dy * dy + dz * dz) * inverse_step_ + 1e-6;
  return q < kLevels - 2 ? static_cast<std::uint8_t>(static_cast<int>(q) + 1)
                         : static_cast<std::uint8_t>(kLevels - 1);  // also NaN
}

void KeptSpeedBounds::build(const ParticleSpan& particles, double unit) {
  const std::size_t n = particles.count;
  double mean[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i)
    mean[0] += particles.vx.data[i], mean[1] += particles.vy.data[i], mean[2] += particles.vz.data[i];
  for (int k = 0; k < 3; ++k) velocity_[k] = std::isfinite(mean[k]) ? mean[k] / static_cast<double>(n) : 0.0;
  unit_ = unit;
  const double step = kTop * unit / (kLevels - 2);
  inverse_step_ = 1.0 / step;
  for (int q = 0; q < kLevels - 1; ++q) speed_[q] = q * step;
  speed_[kLevels - 1] = INFINITY;
  levels_.resize(n);
  for (std::size_t i = 0; i < n; ++i) levels_[i] = level(particles.vx.data[i], particles.vy.data[i], particles.vz.data[i]);
  vx_ = particles.vx.data;
  count_ = n;
  valid_ = true;
}

}  // namespace gdsmc::host
