#include "engine/cells.hpp"

#include <gdsmc/physics/moments.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

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
  cross_section_ = cross_section;
  cell_volume_ = cross_section * height / static_cast<double>(layers);
  edges_.clear();
  volumes_.clear();
  table_first_.clear();
  table_upper_.clear();
  offsets_.assign(layers + 1, 0);
  fill_.clear();
  members_.assign(particles, 0);
  next_.assign(layers, 0);
  scratch_mean_.assign(3 * layers, 0.0);
}

void CellGrid::set_edges(std::vector<double> edges) {
  if (!slab_) throw std::invalid_argument("layer edges need a slab");
  if (edges.empty()) {
    edges_.clear();
    volumes_.clear();
    table_first_.clear();
    table_upper_.clear();
    return;
  }
  const double half = 0.5 * height_;
  if (edges.size() != layers_ + 1)
    throw std::invalid_argument("layer edges: " + std::to_string(edges.size()) + " values for " +
                                std::to_string(layers_) + " layers (needs layers + 1)");
  if (edges.front() != -half || edges.back() != half)
    throw std::invalid_argument("layer edges: the first must be -Ly/2 and the last +Ly/2");
  for (std::size_t I = 0; I < layers_; ++I)
    if (!(edges[I] < edges[I + 1]))
      throw std::invalid_argument("layer edges: not strictly increasing at edge " + std::to_string(I + 1));
  // The fine bins: at least two per narrowest layer (a power of two), doubled until no two
  // interior edges fall in the same bin (the bin of an edge computed with TableIndex's own
  // arithmetic: rounding decides, not the intention).
  double narrowest = height_;
  for (std::size_t I = 0; I < layers_; ++I) narrowest = std::min(narrowest, edges[I + 1] - edges[I]);
  std::size_t bins = 1;
  while (bins < layers_ || static_cast<double>(bins) * narrowest < 2.0 * height_) {
    if (bins >= kMaxTableBins)
      throw std::invalid_argument("layer edges: the narrowest layer is " + std::to_string(narrowest / height_) +
                                  " of Ly, too narrow for the lookup table (at most 2^24 bins)");
    bins *= 2;
  }
  std::vector<std::uint64_t> edge_bin(layers_ + 1, 0);
  while (true) {
    const double scale = static_cast<double>(bins) / height_;
    const TableIndex probe = table_index(scale, bins);
    bool separated = true;
    for (std::size_t I = 1; I < layers_; ++I) {
      const std::uint64_t b = probe.bin(edges[I]);
      edge_bin[I] = b;
      if (I > 1 && b <= edge_bin[I - 1]) separated = false;
    }
    if (separated) {
      table_scale_ = scale;
      break;
    }
    if (bins >= kMaxTableBins)
      throw std::invalid_argument("layer edges: two edges closer than Ly/2^24 (lookup table)");
    bins *= 2;
  }
  table_first_.assign(bins, 0);
  std::uint32_t below = 0;  // interior edges in bins below b
  std::size_t next = 1;
  for (std::size_t b = 0; b < bins; ++b) {
    table_first_[b] = below;
    while (next < layers_ && edge_bin[next] == b) {
      ++below;
      ++next;
    }
  }
  table_upper_.resize(layers_);
  for (std::size_t k = 0; k + 1 < layers_; ++k) table_upper_[k] = edges[k + 1];
  table_upper_[layers_ - 1] = std::numeric_limits<double>::quiet_NaN();  // y >= NaN: false for every y, +inf too
  volumes_.resize(layers_);
  for (std::size_t I = 0; I < layers_; ++I) volumes_[I] = cross_section_ * (edges[I + 1] - edges[I]);
  edges_ = std::move(edges);
}

// A stable counting sort in blocks of kSortBlock particles: each block counts its layers, the
// blocks' starts follow layer by layer and block by block, and each block then places its own
// particles, so every layer lists its members in increasing index whatever the thread count.
void CellGrid::sort(const std::uint32_t* cell, std::size_t n, WorkPool* pool) {
  if (!slab_) return;
  count_blocks(cell, n, pool);
  sort_counted(cell, n, pool);
}

void CellGrid::count_blocks(const std::uint32_t* cell, std::size_t n, WorkPool* pool) {
  std::uint32_t* const counts = block_counts(n);
  for_pieces(pool, sort_blocks(n), [&](std::size_t b) {
    std::uint32_t* count = counts + b * layers_;
    std::fill(count, count + layers_, 0u);
    for (std::size_t i = b * kSortBlock, e = std::min(n, i + kSortBlock); i < e; ++i) ++count[cell[i]];
  });
}

std::uint32_t* CellGrid::block_counts(std::size_t n) {
  const std::size_t size = sort_blocks(n) * layers_;
  if (fill_.size() != size) fill_.resize(size);
  return fill_.data();
}

void CellGrid::sort_counted(const std::uint32_t* cell, std::size_t n, WorkPool* pool) {
  if (!slab_) return;
  place_blocks(n);
  scatter_blocks(cell, n, pool);
}

void CellGrid::scatter_blocks(const std::uint32_t* cell, std::size_t n, WorkPool* pool) {
  // Pieces 0, 1, 2, 3, ... place blocks 0, h, 1, h + 1, ... (h = half the blocks): pieces taken
  // at the same time by two threads then write far apart in members_, not next to each other
  // within the same layers (at 10^6 particles 0.74 -> 0.60 ms on 2 threads; the places, and so
  // the result, do not depend on the order).
  const std::size_t blocks = sort_blocks(n), half = (blocks + 1) / 2;
  for_pieces(pool, blocks, [&](std::size_t k) { scatter_block(cell, k % 2 == 0 ? k / 2 : half + k / 2, n); });
}

void CellGrid::place_blocks(std::size_t n) {
  const std::size_t blocks = sort_blocks(n);
  // Each layer's start (the layers' totals, block rows read in storage order), then each block's
  // start within a layer, the blocks in order: the same places as taking layer by layer, block by
  // block, without striding across the rows.
  std::fill(offsets_.begin(), offsets_.end(), 0u);
  last_block_.assign(layers_, kNoBlock);
  for (std::size_t b = 0; b < blocks; ++b)
    for (std::size_t c = 0; c < layers_; ++c) {
      const std::uint32_t k = fill_[b * layers_ + c];
      offsets_[c + 1] += k;
      if (k) last_block_[c] = b;
    }
  for (std::size_t c = 0; c < layers_; ++c) offsets_[c + 1] += offsets_[c];
  next_.assign(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t b = 0; b < blocks; ++b)
    for (std::size_t c = 0; c < layers_; ++c) {
      std::uint32_t& slot = fill_[b * layers_ + c];
      const std::uint32_t k = slot;
      slot = next_[c];
      next_[c] += k;
    }
}

void CellGrid::scatter_block(const std::uint32_t* cell, std::size_t b, std::size_t n) {
  std::uint32_t* place = fill_.data() + b * layers_;
  std::uint32_t* const members = members_.data();
  std::size_t i = b * kSortBlock;
  const std::size_t e = std::min(n, i + kSortBlock);
  // Four particles at a time: their layers' places are read before any is written, and a particle
  // whose layer an earlier one of the four shares goes one place further for each. One particle at
  // a time, each place waited for the store of the one before whenever neighbours share a layer
  // (most do: storage is in layer order after each reordering). The same places.
  for (; i + 4 <= e; i += 4) {
    const std::uint32_t c0 = cell[i], c1 = cell[i + 1], c2 = cell[i + 2], c3 = cell[i + 3];
    const std::uint32_t q0 = place[c0], q1 = place[c1], q2 = place[c2], q3 = place[c3];
    const std::uint32_t p0 = q0;
    const std::uint32_t p1 = q1 + (c1 == c0);
    const std::uint32_t p2 = q2 + (c2 == c0) + (c2 == c1);
    const std::uint32_t p3 = q3 + (c3 == c0) + (c3 == c1) + (c3 == c2);
    members[p0] = static_cast<std::uint32_t>(i);
    members[p1] = static_cast<std::uint32_t>(i + 1);
    members[p2] = static_cast<std::uint32_t>(i + 2);
    members[p3] = static_cast<std::uint32_t>(i + 3);
    place[c0] = p0 + 1;  // a layer's last store is that of its last particle of the four
    place[c1] = p1 + 1;
    place[c2] = p2 + 1;
    place[c3] = p3 + 1;
  }
  for (; i < e; ++i) members[place[cell[i]]++] = static_cast<std::uint32_t>(i);
}

void CellGrid::set_layer_order(std::uint32_t* cell, WorkPool* pool) {
  if (!slab_) return;
  for_pieces(pool, layers_, [&](std::size_t c) {
    for (std::uint32_t k = offsets_[c]; k < offsets_[c + 1]; ++k) {
      cell[k] = static_cast<std::uint32_t>(c);
      members_[k] = k;
    }
  });
}

void CellGrid::assign_and_sort(const double* y, std::uint32_t* cell, std::size_t n) {
  if (!slab_) return;  // one cell, and no positions or cell array to fill
  for (std::size_t i = 0; i < n; ++i) cell[i] = layer_of(y[i]);
  sort(cell, n);
}

std::size_t CellGrid::piece_count() const {
  return slab_ ? layers_ : std::max<std::size_t>(1, (total_ + kMomentBlock - 1) / kMomentBlock);
}

// Pieces pair[0] and pair[1] (count of them: 1 or 2), add(sums[k], i) over piece k's particles i in
// their order, the two pieces' additions side by side: each piece keeps its own order (the same bits
// as one piece after the other), and their chains of dependent additions overlap.
template <class Sums, class Add>
void CellGrid::side_by_side(const std::size_t (&pair)[2], std::size_t count, Sums (&sums)[2], Add&& add) const {
  std::size_t c[2], b[2] = {0, 0}, e[2] = {0, 0};
  const std::uint32_t* mem[2] = {nullptr, nullptr};
  for (std::size_t k = 0; k < count; ++k) {
    piece_range(pair[k], c[k], b[k], e[k]);
    mem[k] = members(c[k]);
  }
  const auto index = [&](std::size_t k, std::size_t q) { return mem[k] ? mem[k][q] : static_cast<std::uint32_t>(q); };
  Sums s0 = sums[0], s1 = sums[1];  // locals: in registers through the loop
  const std::size_t n0 = e[0] - b[0], n1 = e[1] - b[1], common = std::min(n0, n1);
  for (std::size_t q = 0; q < common; ++q) {
    add(s0, index(0, b[0] + q));
    add(s1, index(1, b[1] + q));
  }
  for (std::size_t q = common; q < n0; ++q) add(s0, index(0, b[0] + q));
  for (std::size_t q = common; q < n1; ++q) add(s1, index(1, b[1] + q));
  sums[0] = s0;
  sums[1] = s1;
}

CellGrid::PieceSums& CellGrid::open_piece(std::size_t k, std::size_t& cell, std::size_t& begin, std::size_t& end) const {
  piece_range(k, cell, begin, end);
  return pieces_[k] = PieceSums{};
}

void CellGrid::piece_range(std::size_t k, std::size_t& cell, std::size_t& begin, std::size_t& end) const {
  if (slab_) {
    cell = k;
    begin = 0;
    end = members_count(k);
  } else {
    cell = 0;
    begin = k * kMomentBlock;
    end = std::min<std::size_t>(total_, begin + kMomentBlock);
  }
}

// One cell whose mean u' is known to be conserved (to round-off): the sums of c = v - u' in one
// pass are the peculiar sums, u = u' + <c> and E = (sum c^2 + 2 u'.sum c + N u'^2) / 2 exactly.
// False (nothing kept) when <c> shows the mean has moved after all.
template <class Run>
bool CellGrid::one_pass_moments(const ParticleSpan& p, const double* shift, SampledMoments& out, Run&& run) const {
  const std::size_t pieces = piece_count();
  run(pieces, [&](std::size_t k) {
    std::size_t c, b, e;
    PieceSums& ps = open_piece(k, c, b, e);
    // kLanes independent partial sums (particles i, i + kLanes, ...), added in lane order at the
    // end: the compiler keeps them in vector registers, and no sum waits on the one before (2.3
    // -> 1.6 ms at N = 1e6, against 1.3 ms for reading the velocities alone).
    constexpr std::size_t kLanes = 8;
    double sx[kLanes] = {}, sy[kLanes] = {}, sz[kLanes] = {}, xx[kLanes] = {}, yy[kLanes] = {}, zz[kLanes] = {},
           xy[kLanes] = {}, xz[kLanes] = {}, yz[kLanes] = {}, v4[kLanes] = {}, v6[kLanes] = {};
    std::size_t i = b;
    for (; i + kLanes <= e; i += kLanes)
      for (std::size_t l = 0; l < kLanes; ++l) {
        const double cx = p.vx[i + l] - shift[0], cy = p.vy[i + l] - shift[1], cz = p.vz[i + l] - shift[2];
        sx[l] += cx;
        sy[l] += cy;
        sz[l] += cz;
        xx[l] += cx * cx;
        yy[l] += cy * cy;
        zz[l] += cz * cz;
        xy[l] += cx * cy;
        xz[l] += cx * cz;
        yz[l] += cy * cz;
        const double c2 = cx * cx + cy * cy + cz * cz;
        v4[l] += c2 * c2;
        v6[l] += c2 * c2 * c2;
      }
    PeculiarSums& sums = ps.peculiar;
    for (std::size_t l = 0; l < kLanes; ++l) {
      ps.s[0] += sx[l];
      ps.s[1] += sy[l];
      ps.s[2] += sz[l];
      sums.merge(PeculiarSums{xx[l], yy[l], zz[l], xy[l], xz[l], yz[l], v4[l], v6[l]});
    }
    for (; i < e; ++i) {
      const double cx = p.vx[i] - shift[0], cy = p.vy[i] - shift[1], cz = p.vz[i] - shift[2];
      ps.s[0] += cx;
      ps.s[1] += cy;
      ps.s[2] += cz;
      sums.add(cx, cy, cz);
    }
  });
  double s[3] = {0, 0, 0};
  PeculiarSums sums;
  for (std::size_t k = 0; k < pieces; ++k) {
    for (int a = 0; a < 3; ++a) s[a] += pieces_[k].s[a];
    sums.merge(pieces_[k].peculiar);
  }
  const double n = static_cast<double>(p.count), inv = 1.0 / n;
  const double c2 = sums.xx + sums.yy + sums.zz;
  const double moved2 = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) * inv * inv;  // |u - u'|^2
  if (!(moved2 * 3.0 * n <= kConservedMeanTolerance * c2)) return false;
  double* u = scratch_mean_.data();
  double shift_dot_s = 0, shift2 = 0;
  for (int a = 0; a < 3; ++a) {
    u[a] = out.local.mean[a] = shift[a] + s[a] * inv;
    shift_dot_s += shift[a] * s[a];
    shift2 += shift[a] * shift[a];
  }
  out.kinetic_energy = 0.5 * (c2 + 2.0 * shift_dot_s + n * shift2);  // 004 Eq. A1 (m = 1)
  out.cell_mean_velocity = u;
  sums.finish(out.local, inv);
  return true;
}

// One cell: one pass of sums of c = v - u' and c^2 around the previous mean u' (which moves little
// between updates, so the difference below loses nothing), u = u' + <c>, T = (<c^2> - <c>^2) / 3:
// half the memory traffic of two passes.
template <class Run>
void CellGrid::homogeneous_moments(const ParticleSpan& p, double mean_density, CellMoments& cell, CellMoments& global,
                                   Run&& run) const {
  const double shift[3] = {global.mean_velocity[0], global.mean_velocity[1], global.mean_velocity[2]};
  const std::size_t pieces = piece_count();
  run(pieces, [&](std::size_t k) {
    std::size_t c, b, e;
    PieceSums& ps = open_piece(k, c, b, e);
    double sx = ps.s[0], sy = ps.s[1], sz = ps.s[2], c2 = ps.c2;  // locals: see sampled_moments
    for (std::size_t i = b; i < e; ++i) {
      const double cx = p.vx[i] - shift[0], cy = p.vy[i] - shift[1], cz = p.vz[i] - shift[2];
      sx += cx;
      sy += cy;
      sz += cz;
      c2 += cx * cx + cy * cy + cz * cz;
    }
    ps.s[0] = sx, ps.s[1] = sy, ps.s[2] = sz, ps.c2 = c2;
  });
  double s[3] = {0, 0, 0}, c2 = 0;
  for (std::size_t k = 0; k < pieces; ++k) {
    for (int a = 0; a < 3; ++a) s[a] += pieces_[k].s[a];
    c2 += pieces_[k].c2;
  }
  cell = CellMoments{};
  cell.count = p.count;
  cell.number_density = mean_density;
  global = CellMoments{};
  global.count = p.count;
  global.number_density = mean_density;
  if (p.count == 0) return;
  const double n = static_cast<double>(p.count);
  for (int a = 0; a < 3; ++a) cell.mean_velocity[a] = global.mean_velocity[a] = shift[a] + s[a] / n;  // Eq. 4.5
  if (p.count < 2) return;
  cell.temperature = global.temperature = (c2 - (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / n) / (3.0 * n);  // Eq. 4.15
}

void CellGrid::cell_moments(const ParticleSpan& p, double mean_density, std::vector<CellMoments>& cells,
                            CellMoments& global, WorkPool* pool) const {
  cells.resize(layers_);
  if (species_mass_) return mixture_cell_moments(p, mean_density, cells, global, pool);
  pieces_.resize(piece_count());
  auto run = [&](std::size_t count, auto&& f) { for_pieces(pool, count, f); };
  if (!slab_) {
    homogeneous_moments(p, mean_density, cells[0], global, run);
    return;
  }
  // Two layers at a time (a piece of the pool, side_by_side): their means, then their temperatures
  // and largest peculiar speeds, while their particles are in cache.
  speed_max_.resize(layers_);
  run((layers_ + 1) / 2, [&](std::size_t j) {
    const std::size_t pair[2] = {2 * j, std::min(2 * j + 1, layers_ - 1)};
    const std::size_t count = pair[1] == pair[0] ? 1 : 2;
    struct Mean { double x = 0, y = 0, z = 0; } mean[2];
    side_by_side(pair, count, mean, [&](Mean& m, std::uint32_t i) {
      m.x += p.vx[i];
      m.y += p.vy[i];
      m.z += p.vz[i];
    });
    struct Peculiar { double ux = 0, uy = 0, uz = 0, c2 = 0, c2_max = 0; } peculiar[2];
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t c = pair[k];
      const std::uint32_t n = members_count(c);
      CellMoments& cm = cells[c];
      cm = CellMoments{};
      cm.count = n;
      cm.number_density = n / cell_volume(c);  // n_I = N_I / (A delta y), Eq. 4.4
      double* s = pieces_[c].s;
      s[0] = mean[k].x, s[1] = mean[k].y, s[2] = mean[k].z;
      if (n)
        for (int a = 0; a < 3; ++a) cm.mean_velocity[a] = s[a] / n;  // u_I, Eq. 4.5
      peculiar[k].ux = cm.mean_velocity[0], peculiar[k].uy = cm.mean_velocity[1], peculiar[k].uz = cm.mean_velocity[2];
    }
    side_by_side(pair, count, peculiar, [&](Peculiar& q, std::uint32_t i) {
      const double cx = p.vx[i] - q.ux, cy = p.vy[i] - q.uy, cz = p.vz[i] - q.uz;
      const double ci2 = cx * cx + cy * cy + cz * cz;
      q.c2 += ci2;
      q.c2_max = std::max(q.c2_max, ci2);
    });
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t c = pair[k];
      const std::uint32_t n = members_count(c);
      speed_max_[c] = n < 2 ? 0.0 : std::sqrt(peculiar[k].c2_max);
      if (n >= 2) cells[c].temperature = peculiar[k].c2 / (3.0 * n);  // T_I, Eq. 4.6 (m = 1)
    }
  });
  if (exchange_) share_layers(cells);
  // The whole system, in layer order.
  double gsum[3] = {0, 0, 0}, weighted_t = 0;
  std::size_t count = 0;
  for (std::size_t c = 0; c < layers_; ++c) {
    for (int a = 0; a < 3; ++a) gsum[a] += pieces_[c].s[a];
    weighted_t += cells[c].count * cells[c].temperature;
    count += cells[c].count;
  }
  global = CellMoments{};
  global.count = count;
  global.number_density = mean_density;
  if (count == 0) return;
  for (int a = 0; a < 3; ++a) global.mean_velocity[a] = gsum[a] / static_cast<double>(count);
  global.temperature = weighted_t / static_cast<double>(count);  // T-bar, Eq. 4.8
}

void CellGrid::share_layers(std::vector<CellMoments>& cells) const {
  constexpr std::size_t kValues = 10;
  shared_.resize(kValues * layers_);
  for (std::size_t c = 0; c < layers_; ++c) {
    const CellMoments& m = cells[c];
    double* v = shared_.data() + kValues * c;
    const double values[kValues] = {static_cast<double>(m.count), m.number_density, m.mean_velocity[0],
                                    m.mean_velocity[1], m.mean_velocity[2], m.temperature, pieces_[c].s[0],
                                    pieces_[c].s[1], pieces_[c].s[2], speed_max_[c]};
    std::copy(values, values + kValues, v);
  }
  exchange_->share(shared_.data(), kValues);
  for (std::size_t c = 0; c < layers_; ++c) {
    CellMoments& m = cells[c];
    const double* v = shared_.data() + kValues * c;
    m.count = static_cast<std::size_t>(v[0]);  // below 2^53: exact
    m.number_density = v[1];
    for (int a = 0; a < 3; ++a) m.mean_velocity[a] = v[2 + a], pieces_[c].s[a] = v[6 + a];
    m.temperature = v[5];
    speed_max_[c] = v[9];
  }
}

void CellGrid::sampled_moments(const ParticleSpan& p, double mean_density, SampledMoments& out, WorkPool* pool,
                               const double* conserved_mean, std::uint32_t parts) const {
  out = SampledMoments{};
  out.number_density = mean_density;
  VelocityMoments& m = out.local;
  m.count = p.count;
  if (p.count == 0 && !exchange_) return;  // a decomposed rank may hold none, and still shares
  // The cells' fresh temperatures are the layers' peculiar sums.
  const bool cells = (parts & moments_cells) && !species_mass_;
  const std::uint32_t passes = (parts & moments_all) | (cells ? moments_means | moments_peculiar : 0u);
  measure_moments(p, out, pool, conserved_mean, passes);
  if (exchange_ && !passes) m.count = shared_count();  // local.count is every rank's
  if (cells) fresh_cells(out, mean_density);
  if (parts & (moments_bins | moments_bin_heat)) bin_sums(p, out, pool, (parts & moments_bin_heat) != 0);
  // The parts not asked for: NaN, so that a diagnostic that reads one it did not declare shows it.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(parts & moments_means)) {
    m.mean[0] = m.mean[1] = m.mean[2] = nan;
    out.cell_mean_velocity = nullptr;
  }
  if (!(parts & moments_energy)) out.kinetic_energy = nan;
  if (!(parts & moments_peculiar)) {
    for (auto& row : m.second) row[0] = row[1] = row[2] = nan;
    m.temperature = m.fourth = m.sixth = nan;
  }
}

void CellGrid::measure_moments(const ParticleSpan& p, SampledMoments& out, WorkPool* pool, const double* conserved_mean,
                               std::uint32_t parts) const {
  if (parts == 0) return;
  if (species_mass_) return mixture_sampled_moments(p, out, pool, parts);
  VelocityMoments& m = out.local;
  const std::size_t pieces = piece_count();
  pieces_.resize(pieces);
  auto run = [&](std::size_t count, auto&& f) { for_pieces(pool, count, f); };
  if (!slab_ && conserved_mean && one_pass_moments(p, conserved_mean, out, run)) return;
  // Pass 1: the mean of every cell and of everyone, and the kinetic energy; two pieces at a time
  // (side_by_side), their sums in locals (summed in pieces_, which a store could alias, each
  // addition would wait for the store of the previous one).
  run((pieces + 1) / 2, [&](std::size_t j) {
    const std::size_t pair[2] = {2 * j, std::min(2 * j + 1, pieces - 1)};
    const std::size_t count = pair[1] == pair[0] ? 1 : 2;
    struct Sums { double x = 0, y = 0, z = 0, v2 = 0; } sums[2];
    side_by_side(pair, count, sums, [&](Sums& s, std::uint32_t i) {
      s.x += p.vx[i];
      s.y += p.vy[i];
      s.z += p.vz[i];
      s.v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    });
    for (std::size_t k = 0; k < count; ++k) {
      std::size_t c, b, e;
      PieceSums& ps = open_piece(pair[k], c, b, e);
      ps.s[0] = sums[k].x, ps.s[1] = sums[k].y, ps.s[2] = sums[k].z, ps.v2 = sums[k].v2;
    }
  });
  if (exchange_) share_sampled_means();
  double* u = scratch_mean_.data();
  std::fill(u, u + 3 * layers_, 0.0);
  double g[3] = {0, 0, 0}, v2 = 0;
  for (std::size_t k = 0; k < pieces; ++k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    for (int a = 0; a < 3; ++a) {
      u[3 * c + a] += pieces_[k].s[a];
      g[a] += pieces_[k].s[a];
    }
    v2 += pieces_[k].v2;
  }
  double total = exchange_ ? 0.0 : static_cast<double>(p.count);  // a decomposed slab: every rank's
  for (std::size_t c = 0; c < layers_; ++c) {
    const double n = layer_count(c);
    if (exchange_) total += n;
    const double inv_n = n ? 1.0 / n : 0.0;
    for (int a = 0; a < 3; ++a) u[3 * c + a] *= inv_n;
  }
  m.count = static_cast<std::size_t>(total);
  const double inv = 1.0 / total;
  for (int a = 0; a < 3; ++a) m.mean[a] = g[a] * inv;
  out.kinetic_energy = 0.5 * v2;  // 004 Eq. A1 (m = 1)
  out.cell_mean_velocity = u;
  if (!(parts & moments_peculiar)) return;
  // Pass 2: moments of the local peculiar velocities V = v - u_I.
  run(pieces, [&](std::size_t k) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    const std::uint32_t* mem = members(c);
    const double ux = u[3 * c], uy = u[3 * c + 1], uz = u[3 * c + 2];
    PeculiarSums sums;
    for (std::size_t q = b; q < e; ++q) {
      const std::uint32_t i = mem ? mem[q] : static_cast<std::uint32_t>(q);
      sums.add(p.vx[i] - ux, p.vy[i] - uy, p.vz[i] - uz);
    }
    pieces_[k].peculiar = sums;
  });
  if (exchange_) share_peculiar_sums();
  PeculiarSums sums;
  for (std::size_t k = 0; k < pieces; ++k) sums.merge(pieces_[k].peculiar);
  sums.finish(m, inv);  // T is T-bar (000 Eq. 4.8) in a slab, T (Eq. 4.15) in a homogeneous system
}

}  // namespace gdsmc::host
