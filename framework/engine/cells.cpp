#include "engine/cells.hpp"

#include <gdsmc/moments.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gdsmc::host {

void CellGrid::homogeneous(std::size_t particles, double volume) {
  slab_ = false;
  layers_ = 1;
  total_ = static_cast<std::uint32_t>(particles);
  cell_volume_ = volume;
  offsets_.assign(2, 0);
  offsets_[1] = total_;
  scratch_mean_.assign(3, 0.0);
}

void CellGrid::slab(std::size_t particles, std::size_t layers, double height, double cross_section) {
  if (particles > 0xFFFFFFFFull) throw std::runtime_error("a slab holds at most 2^32 - 1 particles");
  slab_ = true;
  layers_ = layers;
  total_ = static_cast<std::uint32_t>(particles);
  height_ = height;
  cell_volume_ = cross_section * height / static_cast<double>(layers);
  offsets_.assign(layers + 1, 0);
  fill_.assign(layers, 0);
  members_.assign(particles, 0);
  scratch_mean_.assign(3 * layers, 0.0);
}

void CellGrid::sort(const std::uint32_t* cell, std::size_t n) {
  if (!slab_) return;
  std::fill(fill_.begin(), fill_.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) ++fill_[cell[i]];
  offsets_[0] = 0;
  for (std::size_t c = 0; c < layers_; ++c) {
    offsets_[c + 1] = offsets_[c] + fill_[c];
    fill_[c] = offsets_[c];
  }
  for (std::size_t i = 0; i < n; ++i) members_[fill_[cell[i]]++] = static_cast<std::uint32_t>(i);
}

void CellGrid::assign_and_sort(const double* y, std::uint32_t* cell, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) cell[i] = slab_ ? layer_of(y[i]) : 0u;
  sort(cell, n);
}

void CellGrid::cell_moments(const ParticleSpan& p, double mean_density, std::vector<CellMoments>& cells,
                            CellMoments& global) const {
  cells.resize(layers_);
  double gsum[3] = {0, 0, 0}, weighted_t = 0;
  for (std::size_t c = 0; c < layers_; ++c) {
    const std::uint32_t* m = members(c);
    const std::uint32_t n = members_count(c);
    CellMoments& cm = cells[c];
    cm = CellMoments{};
    cm.count = n;
    cm.number_density = slab_ ? n / cell_volume_ : mean_density;  // n_I = N_I / (A delta y), Eq. 4.4
    if (n == 0) continue;
    double s[3] = {0, 0, 0};
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = m ? m[k] : k;
      s[0] += p.vx[i];
      s[1] += p.vy[i];
      s[2] += p.vz[i];
    }
    for (int a = 0; a < 3; ++a) {
      gsum[a] += s[a];
      cm.mean_velocity[a] = s[a] / n;  // u_I, Eq. 4.5
    }
    if (n < 2) continue;
    double c2 = 0;
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = m ? m[k] : k;
      const double cx = p.vx[i] - cm.mean_velocity[0], cy = p.vy[i] - cm.mean_velocity[1],
                   cz = p.vz[i] - cm.mean_velocity[2];
      c2 += cx * cx + cy * cy + cz * cz;
    }
    cm.temperature = c2 / (3.0 * n);  // T_I, Eq. 4.6 (m = 1)
    weighted_t += n * cm.temperature;
  }
  global = CellMoments{};
  global.count = p.count;
  global.number_density = mean_density;
  if (p.count == 0) return;
  for (int a = 0; a < 3; ++a) global.mean_velocity[a] = gsum[a] / static_cast<double>(p.count);
  global.temperature = weighted_t / static_cast<double>(p.count);  // T-bar, Eq. 4.8
}

void CellGrid::sampled_moments(const ParticleSpan& p, double mean_density, SampledMoments& out) const {
  out = SampledMoments{};
  out.number_density = mean_density;
  VelocityMoments& m = out.local;
  m.count = p.count;
  if (p.count == 0) return;
  // Pass 1: the mean of every cell and of everyone, and the kinetic energy.
  double* u = scratch_mean_.data();
  double g[3] = {0, 0, 0}, v2 = 0;
  for (std::size_t c = 0; c < layers_; ++c) {
    const std::uint32_t* mem = members(c);
    const std::uint32_t n = members_count(c);
    double s[3] = {0, 0, 0};
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = mem ? mem[k] : k;
      s[0] += p.vx[i];
      s[1] += p.vy[i];
      s[2] += p.vz[i];
      v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
    const double inv_n = n ? 1.0 / n : 0.0;
    for (int a = 0; a < 3; ++a) {
      g[a] += s[a];
      u[3 * c + a] = s[a] * inv_n;
    }
  }
  const double inv = 1.0 / static_cast<double>(p.count);
  for (int a = 0; a < 3; ++a) m.mean[a] = g[a] * inv;
  out.kinetic_energy = 0.5 * v2;  // 004 Eq. A1 (m = 1)
  out.cell_mean_velocity = u;
  // Pass 2: moments of the local peculiar velocities V = v - u_I.
  PeculiarSums sums;
  for (std::size_t c = 0; c < layers_; ++c) {
    const std::uint32_t* mem = members(c);
    const std::uint32_t n = members_count(c);
    const double ux = u[3 * c], uy = u[3 * c + 1], uz = u[3 * c + 2];
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = mem ? mem[k] : k;
      sums.add(p.vx[i] - ux, p.vy[i] - uy, p.vz[i] - uz);
    }
  }
  sums.finish(m, inv);  // T is T-bar (000 Eq. 4.8) in a slab, T (Eq. 4.15) in a homogeneous system
}

}  // namespace gdsmc::host
