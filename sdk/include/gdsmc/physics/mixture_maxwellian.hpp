// gdsmc SDK, physics toolkit: Maxwellian states of a mixture (SDK 6.5, SystemInfo::species), the
// per-species form of sample_maxwellian and impose_exact_moments (moments.hpp). Species s has mass
// m_s = SystemInfo::species_mass(s) and its own temperature T_s; its Maxwellian is
// f_s(v) = n_s (m_s / 2 pi T_s)^{3/2} exp(-m_s v^2 / 2 T_s) (000 Eq. 2.14 for each species), so
// each velocity component has the standard deviation sqrt(T_s / m_s).
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "gdsmc/context.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/physics/moments.hpp"
#include "gdsmc/random.hpp"

namespace gdsmc {

// Positions uniform in the box and velocities from the Maxwellian of each particle's species at
// rest, temperatures[s] for species s (species_count entries). Each particle draws from its own
// stream exactly as sample_maxwellian does (a position, then three normals), so a one-species run
// with temperatures = {T} gives the same state to the last bit.
inline void sample_mixture_maxwellian(const SystemInfo& sys, const ParticleSpan& p, const std::vector<double>& temperatures,
                                      const Streams& streams) {
  std::vector<double> sd(sys.species_count);
  for (std::size_t s = 0; s < sys.species_count; ++s) sd[s] = std::sqrt(temperatures[s] / sys.species_mass(s));
  for (std::size_t i = 0; i < p.count; ++i) {
    Rng rng = streams.for_particle(p.id[i]);
    place_uniformly(sys, p, i, rng);
    const double scale = sd[p.species_of(i)];  // sqrt(T_s / m_s), 000 Eq. 2.14 per species
    p.vx[i] = scale * rng.normal();
    p.vy[i] = scale * rng.normal();
    p.vz[i] = scale * rng.normal();
  }
}

// The barycentric velocity of the span, U = sum m_i v_i / sum m_i (the flow velocity of a mixture).
inline Vec3 barycentric_velocity(const SystemInfo& sys, const ParticleSpan& p) {
  double mass = 0, px = 0, py = 0, pz = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const double m = sys.species_mass(p.species_of(i));
    mass += m;
    px += m * p.vx[i];
    py += m * p.vy[i];
    pz += m * p.vz[i];
  }
  return mass > 0 ? Vec3{px / mass, py / mass, pz / mass} : Vec3{0, 0, 0};
}

// Exact moments of a mixture: every species with at least two particles is shifted to zero mean
// velocity and rescaled to exactly its temperature, T_s = m_s sum_{i in s} V_i^2 / 3 N_s. Then the
// total momentum sum m_i v_i is zero and the mixture temperature sum_i m_i V_i^2 / 3N is
// sum_s x_s T_s exactly (to round-off), and the species start exactly at the temperatures asked
// for (in equipartition when they are all equal). A species of a single particle cannot be fixed
// that way: it is left as drawn and the barycentric velocity of the whole span is then removed
// from every particle (the total momentum is zero again; the temperatures exact only to
// O(1/N)). Three passes in index order: bit-reproducible.
inline void impose_exact_mixture_moments(const SystemInfo& sys, const ParticleSpan& p, const std::vector<double>& temperatures) {
  const std::size_t S = sys.species_count;
  std::vector<double> count(S, 0.0), mean(3 * S, 0.0), square(S, 0.0), scale(S, 1.0);
  for (std::size_t i = 0; i < p.count; ++i) {
    const std::size_t s = p.species_of(i);
    count[s] += 1;
    mean[3 * s] += p.vx[i];
    mean[3 * s + 1] += p.vy[i];
    mean[3 * s + 2] += p.vz[i];
  }
  for (std::size_t s = 0; s < S; ++s)
    for (int c = 0; c < 3; ++c) mean[3 * s + c] = count[s] > 0 ? mean[3 * s + c] / count[s] : 0.0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const std::size_t s = p.species_of(i);
    const double dx = p.vx[i] - mean[3 * s], dy = p.vy[i] - mean[3 * s + 1], dz = p.vz[i] - mean[3 * s + 2];
    square[s] += dx * dx + dy * dy + dz * dz;
  }
  bool lone = false;
  for (std::size_t s = 0; s < S; ++s) {
    if (count[s] >= 2 && square[s] > 0) {
      // T_s = m_s sum V^2 / (3 N_s): the factor that makes it exactly temperatures[s]
      scale[s] = std::sqrt(3.0 * count[s] * temperatures[s] / (sys.species_mass(s) * square[s]));
    } else if (count[s] > 0) {
      lone = true;
      for (int c = 0; c < 3; ++c) mean[3 * s + c] = 0.0;  // left as drawn
    }
  }
  for (std::size_t i = 0; i < p.count; ++i) {
    const std::size_t s = p.species_of(i);
    p.vx[i] = (p.vx[i] - mean[3 * s]) * scale[s];
    p.vy[i] = (p.vy[i] - mean[3 * s + 1]) * scale[s];
    p.vz[i] = (p.vz[i] - mean[3 * s + 2]) * scale[s];
  }
  if (!lone) return;
  const Vec3 u = barycentric_velocity(sys, p);
  for (std::size_t i = 0; i < p.count; ++i) {
    p.vx[i] -= u.x;
    p.vy[i] -= u.y;
    p.vz[i] -= u.z;
  }
}

}  // namespace gdsmc
