// gdsmc SDK: velocity moments of a set of particles (000 Eqs. 4.15-4.18), the one place where
// T, P_ij, <V^4> and <V^6> are computed from particles.
#pragma once
#include <cstddef>
#include <cstdint>

#include "gdsmc/particles.hpp"

namespace gdsmc {

struct VelocityMoments {
  std::size_t count = 0;
  double mean[3] = {0, 0, 0};      // u
  double second[3][3] = {};        // <V_a V_b>, V = v - u
  double temperature = 0;          // T = (m/3) <V^2>                          (000 Eq. 4.15)
  double fourth = 0;               // <V^4>
  double sixth = 0;                // <V^6>
  // a2 = <V^4> / (15 (T/m)^2) - 1                                              (000 Eq. 4.17)
  double a2() const { return fourth / (15.0 * temperature * temperature) - 1.0; }
  // a3 = -<V^6> / (105 (T/m)^3) + 1 + 3 a2                                     (000 Eq. 4.18)
  double a3() const { return -sixth / (105.0 * temperature * temperature * temperature) + 1.0 + 3.0 * a2(); }
};

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
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0, v4 = 0, v6 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = members ? members[k] : k;
    const double cx = p.vx[i] - m.mean[0], cy = p.vy[i] - m.mean[1], cz = p.vz[i] - m.mean[2];
    xx += cx * cx; yy += cy * cy; zz += cz * cz;
    xy += cx * cy; xz += cx * cz; yz += cy * cz;
    const double c2 = cx * cx + cy * cy + cz * cz;
    v4 += c2 * c2;
    v6 += c2 * c2 * c2;
  }
  m.second[0][0] = xx * inv; m.second[1][1] = yy * inv; m.second[2][2] = zz * inv;
  m.second[0][1] = m.second[1][0] = xy * inv;
  m.second[0][2] = m.second[2][0] = xz * inv;
  m.second[1][2] = m.second[2][1] = yz * inv;
  m.temperature = (xx + yy + zz) * inv / 3.0;
  m.fourth = v4 * inv;
  m.sixth = v6 * inv;
  return m;
}

}  // namespace gdsmc
