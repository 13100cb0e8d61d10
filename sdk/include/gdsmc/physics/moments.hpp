// gdsmc SDK: velocity moments of a set of particles (000 Eqs. 4.15-4.18), the one place where
// T, P_ij, <V^4> and <V^6> are computed from particles.
#pragma once
#include <cstddef>
#include <cstdint>

#include <cmath>

#include "gdsmc/context.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/random.hpp"

namespace gdsmc {

// Sums of the peculiar velocities' second, fourth and sixth moments, added particle by particle
// in a fixed order; finish() writes <V_a V_b>, T (000 Eq. 4.15), <V^4> and <V^6> given 1/N.
struct PeculiarSums {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0, v4 = 0, v6 = 0;
  void add(double cx, double cy, double cz) {
    xx += cx * cx; yy += cy * cy; zz += cz * cz;
    xy += cx * cy; xz += cx * cz; yz += cy * cz;
    const double c2 = cx * cx + cy * cy + cz * cz;
    v4 += c2 * c2;
    v6 += c2 * c2 * c2;
  }
  // Add the sums of another set of particles (pieces summed apart, then in a fixed order).
  void merge(const PeculiarSums& o) {
    xx += o.xx; yy += o.yy; zz += o.zz;
    xy += o.xy; xz += o.xz; yz += o.yz;
    v4 += o.v4; v6 += o.v6;
  }
  void finish(VelocityMoments& m, double inv) const {
    m.second[0][0] = xx * inv; m.second[1][1] = yy * inv; m.second[2][2] = zz * inv;
    m.second[0][1] = m.second[1][0] = xy * inv;
    m.second[0][2] = m.second[2][0] = xz * inv;
    m.second[1][2] = m.second[2][1] = yz * inv;
    m.temperature = (xx + yy + zz) * inv / 3.0;
    m.fourth = v4 * inv;
    m.sixth = v6 * inv;
  }
};

// Sums over a whole span in index order, one pass: sum v_a and sum |v|^2 (laboratory frame). The
// forcings' mean velocity is mean(), sum / N (000 Eq. 4.5 for the whole system).
struct VelocitySums {
  double sum[3] = {0, 0, 0};
  double square = 0;  // sum |v|^2
  std::size_t count = 0;
  void mean(double u[3]) const {
    for (int c = 0; c < 3; ++c) u[c] = sum[c] / static_cast<double>(count);
  }
};
inline VelocitySums velocity_sums(const ParticleSpan& p) {
  VelocitySums s;
  s.count = p.count;
  for (std::size_t i = 0; i < p.count; ++i) {
    s.sum[0] += p.vx[i];
    s.sum[1] += p.vy[i];
    s.sum[2] += p.vz[i];
    s.square += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  }
  return s;
}
// sum |v - u|^2 over the span in index order (3 N T / m about the mean u, 000 Eq. 4.6), summed from
// the differences (no cancellation).
inline double peculiar_square_sum(const ParticleSpan& p, const double u[3]) {
  double s = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const double dx = p.vx[i] - u[0], dy = p.vy[i] - u[1], dz = p.vz[i] - u[2];
    s += dx * dx + dy * dy + dz * dz;
  }
  return s;
}

// Moments of the particles listed in `members` (nullptr: all of particles). Two passes in a fixed
// order, so the result is bit-reproducible.
inline VelocityMoments velocity_moments(const ParticleSpan& p, const std::uint32_t* members = nullptr,
                                        std::size_t count = static_cast<std::size_t>(-1)) {
  VelocityMoments m;
  const std::size_t n = members ? count : p.count;
  m.count = n;
  if (n == 0) return m;
  double sx = 0, sy = 0, sz = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = members ? members[k] : k;
    sx += p.vx[i];
    sy += p.vy[i];
    sz += p.vz[i];
  }
  const double inv = 1.0 / static_cast<double>(n);
  m.mean[0] = sx * inv;
  m.mean[1] = sy * inv;
  m.mean[2] = sz * inv;
  PeculiarSums sums;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = members ? members[k] : k;
    sums.add(p.vx[i] - m.mean[0], p.vy[i] - m.mean[1], p.vz[i] - m.mean[2]);
  }
  sums.finish(m, inv);
  return m;
}

// <V12^3> / <V12^3>_0 estimated from `pairs` random pairs i != j (000 Eq. 4.20), with the
// local-equilibrium value <V12^3>_0 = 32/sqrt(pi) (T/m)^{3/2} (000 Eq. 2.15), m = 1.
inline double relative_speed_cube_ratio(const ParticleSpan& p, double temperature, std::uint64_t pairs, Rng& rng) {
  if (p.count < 2 || !(temperature > 0) || pairs == 0) return std::nan("");
  const auto n = static_cast<std::uint32_t>(p.count);
  double sum = 0;
  for (std::uint64_t k = 0; k < pairs; ++k) {
    const std::uint32_t i = rng.below(n);
    std::uint32_t j = rng.below(n - 1);
    j += (j >= i);
    const double dx = p.vx[i] - p.vx[j], dy = p.vy[i] - p.vy[j], dz = p.vz[i] - p.vz[j];
    const double g2 = dx * dx + dy * dy + dz * dz;
    sum += g2 * std::sqrt(g2);
  }
  return sum / static_cast<double>(pairs) / (32.0 / std::sqrt(M_PI) * temperature * std::sqrt(temperature));
}

// A position uniform in the box (slab convention: x in [0, Lx), y in [-Ly/2, Ly/2), z in [0, Lz))
// for particle i: drawn in every system, stored where particles have positions (a slab; nullptr in
// a homogeneous system), so the draws that follow are the same in both.
inline void place_uniformly(const SystemInfo& sys, const ParticleSpan& p, std::size_t i, Rng& rng) {
  const double x = sys.box[0] * rng.uniform(), y = sys.box[1] * rng.uniform() - 0.5 * sys.box[1],
               z = sys.box[2] * rng.uniform();
  if (p.x) {
    p.x[i] = x;
    p.y[i] = y;
    p.z[i] = z;
  }
}

// Positions uniform in the box (place_uniformly) and velocities from a Maxwellian at `temperature`
// with zero mean (000 Eq. 2.14), each particle from its own stream, so the state does not depend
// on storage order.
inline void sample_maxwellian(const SystemInfo& sys, const ParticleSpan& p, double temperature, const Streams& streams) {
  const double sd = std::sqrt(temperature / sys.mass);
  for (std::size_t i = 0; i < p.count; ++i) {
    Rng rng = streams.for_particle(p.id[i]);
    place_uniformly(sys, p, i, rng);
    p.vx[i] = sd * rng.normal();
    p.vy[i] = sd * rng.normal();
    p.vz[i] = sd * rng.normal();
  }
}

// Shift the velocities to zero total momentum and rescale them to exactly `temperature`.
inline void impose_exact_moments(const ParticleSpan& p, double temperature) {
  if (p.count < 2) return;
  const VelocityMoments m = velocity_moments(p);
  const double scale = std::sqrt(temperature / m.temperature);
  for (std::size_t i = 0; i < p.count; ++i) {
    p.vx[i] = (p.vx[i] - m.mean[0]) * scale;
    p.vy[i] = (p.vy[i] - m.mean[1]) * scale;
    p.vz[i] = (p.vz[i] - m.mean[2]) * scale;
  }
}

}  // namespace gdsmc
