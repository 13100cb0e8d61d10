// The moments of a mixture (CellGrid::set_species): every particle weighed by its species' mass
// (SDK context.hpp, "In a mixture"). Two passes over fixed pieces (layers of a slab, blocks of
// kMomentBlock particles of a homogeneous system), summed per species and added in piece order:
// the same bits for any thread count. One-species runs never come here.
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/cells.hpp"

namespace gdsmc::host {

void CellGrid::mixture_sums(const ParticleSpan& p, WorkPool* pool, bool peculiar) const {
  const std::size_t pieces = piece_count(), K = species_count_;
  species_sums_.resize(pieces * K);
  const std::uint32_t* species = p.species;
  // Pass 1: per piece and species, the count, sum v and sum v^2.
  for_pieces(pool, pieces, [&](std::size_t k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    const std::uint32_t* mem = members(c);
    SpeciesSums* sums = species_sums_.data() + k * K;
    for (std::size_t s = 0; s < K; ++s) sums[s] = SpeciesSums{};
    for (std::size_t q = b; q < e; ++q) {
      const std::uint32_t i = mem ? mem[q] : static_cast<std::uint32_t>(q);
      SpeciesSums& t = sums[species[i]];
      t.n += 1;
      t.s[0] += p.vx[i];
      t.s[1] += p.vy[i];
      t.s[2] += p.vz[i];
      t.v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
  });
  // Each cell's barycentric velocity u_c = sum m_i v_i / sum m_i, its pieces in order.
  double* u = scratch_mean_.data();
  std::vector<double>& mass_of_cell = mixture_mass_;
  mass_of_cell.assign(layers_, 0.0);
  std::fill(u, u + 3 * layers_, 0.0);
  for (std::size_t k = 0; k < pieces; ++k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    for (std::size_t s = 0; s < K; ++s) {
      const SpeciesSums& t = species_sums_[k * K + s];
      for (int a = 0; a < 3; ++a) u[3 * c + a] += species_mass_[s] * t.s[a];
      mass_of_cell[c] += species_mass_[s] * t.n;
    }
  }
  for (std::size_t c = 0; c < layers_; ++c)
    for (int a = 0; a < 3; ++a) u[3 * c + a] = mass_of_cell[c] > 0 ? u[3 * c + a] / mass_of_cell[c] : 0.0;
  if (!peculiar) return;
  // Pass 2: per piece and species, the peculiar sums around the cell's u_c (mass-weighted).
  for_pieces(pool, pieces, [&](std::size_t k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    const std::uint32_t* mem = members(c);
    SpeciesSums* sums = species_sums_.data() + k * K;
    const double ux = u[3 * c], uy = u[3 * c + 1], uz = u[3 * c + 2];
    for (std::size_t q = b; q < e; ++q) {
      const std::uint32_t i = mem ? mem[q] : static_cast<std::uint32_t>(q);
      const std::uint32_t s = species[i];
      SpeciesSums& t = sums[s];
      const double m = species_mass_[s];
      const double cx = p.vx[i] - ux, cy = p.vy[i] - uy, cz = p.vz[i] - uz;
      const double c2 = cx * cx + cy * cy + cz * cz;
      t.c2 += c2;
      t.c2_max = std::max(t.c2_max, c2);
      PeculiarSums& ps = t.peculiar;
      ps.xx += m * cx * cx;
      ps.yy += m * cy * cy;
      ps.zz += m * cz * cz;
      ps.xy += m * cx * cy;
      ps.xz += m * cx * cz;
      ps.yz += m * cy * cz;
      const double e2 = m * c2;  // twice the particle's peculiar energy
      ps.v4 += e2 * e2;
      ps.v6 += e2 * e2 * e2;
    }
  });
}

void CellGrid::mixture_cell_moments(const ParticleSpan& p, double mean_density, std::vector<CellMoments>& cells,
                                    CellMoments& global, WorkPool* pool) const {
  const std::size_t K = species_count_;
  mixture_sums(p, pool, true);
  const double* u = scratch_mean_.data();
  species_cells_.assign(layers_ * K, SpeciesCellMoments{});
  if (slab_) speed_max_.assign(layers_, 0.0);  // unused: a mixture's majorants are per species (species_cell_moments)
  std::vector<double>& energy = mixture_energy_;  // per cell: sum m_i (v - u_c)^2
  energy.assign(layers_, 0.0);
  for (std::size_t k = 0, pieces = piece_count(); k < pieces; ++k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    for (std::size_t s = 0; s < K; ++s) {
      const SpeciesSums& t = species_sums_[k * K + s];
      SpeciesCellMoments& sc = species_cells_[c * K + s];
      sc.count += t.n;
      sc.temperature += t.c2;  // the sum for now
      sc.speed_max = std::max(sc.speed_max, t.c2_max);
      energy[c] += species_mass_[s] * t.c2;
    }
  }
  std::vector<double>& cell_mass = mixture_mass_;  // per cell: sum m_i
  cell_mass.assign(layers_, 0.0);
  for (std::size_t c = 0; c < layers_; ++c) {
    const std::uint32_t n = members_count(c);
    CellMoments& cm = cells[c];
    cm = CellMoments{};
    cm.count = n;
    cm.number_density = slab_ ? n / cell_volume(c) : mean_density;  // n_I = N_I / (A delta y), Eq. 4.4
    for (std::size_t s = 0; s < K; ++s) {
      SpeciesCellMoments& sc = species_cells_[c * K + s];
      sc.temperature = sc.count >= 2 ? species_mass_[s] * sc.temperature / (3.0 * sc.count) : 0.0;
      sc.speed_max = std::sqrt(sc.speed_max);
      cell_mass[c] += species_mass_[s] * sc.count;
    }
    for (int a = 0; a < 3; ++a) cm.mean_velocity[a] = u[3 * c + a];  // barycentric u_I
    if (n >= 2) cm.temperature = energy[c] / (3.0 * n);  // T_I = sum m_i V_i^2 / 3 N_I
  }
  if (exchange_ && slab_) share_mixture_layers(cells);
  double weighted_t = 0, gsum[3] = {0, 0, 0}, gmass = 0;
  std::size_t count = 0;
  for (std::size_t c = 0; c < layers_; ++c) {
    const CellMoments& cm = cells[c];
    for (int a = 0; a < 3; ++a) gsum[a] += cell_mass[c] * cm.mean_velocity[a];
    gmass += cell_mass[c];
    weighted_t += cm.count * cm.temperature;
    count += cm.count;
  }
  global = CellMoments{};
  global.count = count;
  global.number_density = mean_density;
  if (count == 0) return;
  for (int a = 0; a < 3; ++a) global.mean_velocity[a] = gmass > 0 ? gsum[a] / gmass : 0.0;
  global.temperature = weighted_t / static_cast<double>(count);  // T-bar, Eq. 4.8
}

// A decomposed slab: every layer's moments, its species' moments and its mass from the owner.
void CellGrid::share_mixture_layers(std::vector<CellMoments>& cells) const {
  const std::size_t K = species_count_, per = 7 + 3 * K;
  shared_.resize(per * layers_);
  for (std::size_t c = 0; c < layers_; ++c) {
    double* v = shared_.data() + per * c;
    const CellMoments& m = cells[c];
    const double head[7] = {static_cast<double>(m.count), m.number_density, m.mean_velocity[0], m.mean_velocity[1],
                            m.mean_velocity[2], m.temperature, mixture_mass_[c]};
    std::copy(head, head + 7, v);
    for (std::size_t s = 0; s < K; ++s) {
      const SpeciesCellMoments& sc = species_cells_[c * K + s];
      v[7 + 3 * s] = sc.count, v[8 + 3 * s] = sc.temperature, v[9 + 3 * s] = sc.speed_max;
    }
  }
  exchange_->share(shared_.data(), per);
  for (std::size_t c = 0; c < layers_; ++c) {
    const double* v = shared_.data() + per * c;
    CellMoments& m = cells[c];
    m.count = static_cast<std::size_t>(v[0]);  // below 2^53: exact
    m.number_density = v[1];
    for (int a = 0; a < 3; ++a) m.mean_velocity[a] = v[2 + a];
    m.temperature = v[5];
    mixture_mass_[c] = v[6];
    for (std::size_t s = 0; s < K; ++s) species_cells_[c * K + s] = {v[7 + 3 * s], v[8 + 3 * s], v[9 + 3 * s]};
  }
}

void CellGrid::mixture_sampled_moments(const ParticleSpan& p, SampledMoments& out, WorkPool* pool,
                                       std::uint32_t parts) const {
  const std::size_t K = species_count_;
  mixture_sums(p, pool, (parts & moments_peculiar) != 0);
  double g[3] = {0, 0, 0}, mass = 0, v2 = 0;
  PeculiarSums sums;
  for (std::size_t k = 0, pieces = piece_count(); k < pieces; ++k)
    for (std::size_t s = 0; s < K; ++s) {
      const SpeciesSums& t = species_sums_[k * K + s];
      const double m = species_mass_[s];
      for (int a = 0; a < 3; ++a) g[a] += m * t.s[a];
      mass += m * t.n;
      v2 += m * t.v2;
      if (parts & moments_peculiar) sums.merge(t.peculiar);
    }
  VelocityMoments& m = out.local;
  for (int a = 0; a < 3; ++a) m.mean[a] = mass > 0 ? g[a] / mass : 0.0;  // barycentric
  out.kinetic_energy = 0.5 * v2;  // sum m_i v_i^2 / 2 (004 Eq. A1)
  out.cell_mean_velocity = scratch_mean_.data();
  if (parts & moments_peculiar) sums.finish(m, 1.0 / static_cast<double>(p.count));
}

}  // namespace gdsmc::host
