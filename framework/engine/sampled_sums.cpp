// The parts of a sampled step's moments that SDK 6.6 added (each cell's fresh moments, the sums in
// every sampling bin) and a decomposed slab's shares of the passes of CellGrid::sampled_moments:
// each layer's sums come from its owner, so every rank folds the serial values in layer order.
#include <algorithm>
#include <type_traits>

#include <gdsmc/physics/bins.hpp>

#include "engine/cells.hpp"

namespace gdsmc::host {

void CellGrid::share_sampled_means() const {
  constexpr std::size_t kValues = 5;  // N_I, sum v_a, sum |v|^2
  shared_.resize(kValues * layers_);
  for (std::size_t c = 0; c < layers_; ++c) {
    const PieceSums& ps = pieces_[c];
    const double values[kValues] = {static_cast<double>(members_count(c)), ps.s[0], ps.s[1], ps.s[2], ps.v2};
    std::copy(values, values + kValues, shared_.data() + kValues * c);
  }
  exchange_->share(shared_.data(), kValues);
  layer_counts_.resize(layers_);
  for (std::size_t c = 0; c < layers_; ++c) {
    const double* v = shared_.data() + kValues * c;
    layer_counts_[c] = v[0];
    PieceSums& ps = pieces_[c];
    ps.s[0] = v[1], ps.s[1] = v[2], ps.s[2] = v[3], ps.v2 = v[4];
  }
}

std::size_t CellGrid::shared_count() const {
  shared_.resize(layers_);
  for (std::size_t c = 0; c < layers_; ++c) shared_[c] = members_count(c);
  exchange_->share(shared_.data(), 1);
  double total = 0;
  for (std::size_t c = 0; c < layers_; ++c) total += shared_[c];
  return static_cast<std::size_t>(total);
}

void CellGrid::share_peculiar_sums() const {
  constexpr std::size_t kValues = 8;
  shared_.resize(kValues * layers_);
  for (std::size_t c = 0; c < layers_; ++c) {
    const PeculiarSums& q = pieces_[c].peculiar;
    const double values[kValues] = {q.xx, q.yy, q.zz, q.xy, q.xz, q.yz, q.v4, q.v6};
    std::copy(values, values + kValues, shared_.data() + kValues * c);
  }
  exchange_->share(shared_.data(), kValues);
  for (std::size_t c = 0; c < layers_; ++c) {
    const double* v = shared_.data() + kValues * c;
    pieces_[c].peculiar = PeculiarSums{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]};
  }
}

void CellGrid::fresh_cells(SampledMoments& out, double mean_density) const {
  sampled_cells_.assign(layers_, CellMoments{});
  out.cells = sampled_cells_.data();
  if (!slab_) {  // the one cell is everyone
    CellMoments& m = sampled_cells_[0];
    m.count = out.local.count;
    m.number_density = mean_density;
    for (int a = 0; a < 3; ++a) m.mean_velocity[a] = out.local.mean[a];
    if (m.count >= 2) m.temperature = out.local.temperature;
    return;
  }
  const double* u = scratch_mean_.data();
  for (std::size_t c = 0; c < layers_; ++c) {
    CellMoments& m = sampled_cells_[c];
    const double n = layer_count(c);
    m.count = static_cast<std::size_t>(n);
    m.number_density = n / cell_volume(c);  // n_I = N_I / (A delta y), 000 Eq. 4.4
    if (m.count == 0) continue;
    for (int a = 0; a < 3; ++a) m.mean_velocity[a] = u[3 * c + a];  // u_I, Eq. 4.5
    const PeculiarSums& q = pieces_[c].peculiar;
    if (m.count >= 2) m.temperature = (q.xx + q.yy + q.zz) / (3.0 * n);  // T_I, Eq. 4.6 (m = 1)
  }
}

void CellGrid::bin_sums(const ParticleSpan& p, SampledMoments& out, WorkPool* pool, bool heat) const {
  if (!system_) return;
  const std::size_t bins = system_->bins, stride = heat ? BinSums::kSums : BinSums::kSecond;
  const std::size_t pieces = piece_count();
  // The bins piece k may hold: its layer's, one more on each side for a position on an edge
  // (clamped into them: the serial and the decomposed run clamp alike); a homogeneous piece, all.
  const auto first_bin = [&](std::size_t k) -> std::size_t {
    return slab_ ? std::max<std::size_t>(system_->bin_of(system_->layer_lower(k)), 1) - 1 : 0;
  };
  const auto last_bin = [&](std::size_t k) -> std::size_t {
    return slab_ ? std::min(system_->bin_of(system_->layer_upper(k)) + 1, bins - 1) : bins - 1;
  };
  std::size_t width = 1;
  for (std::size_t k = 0; k < pieces; ++k) width = std::max(width, last_bin(k) - first_bin(k) + 1);
  const std::size_t per_piece = width * stride;
  bin_pieces_.assign(pieces * per_piece, 0.0);
  const bool positions = p.y.data != nullptr;
  // SystemInfo::bin_of's arithmetic, in registers (through system_ every store could alias it).
  const double half = 0.5 * system_->box[1], height = system_->box[1], divisions = static_cast<double>(bins);
  const auto bin_of = [=](double y) -> std::size_t {
    const double f = (y + half) / height * divisions;
    if (!(f > 0)) return 0;
    const auto k = static_cast<std::size_t>(f);
    return k < bins ? k : bins - 1;
  };
  const auto piece = [&](std::size_t k, auto third) {
    std::size_t c, b, e;
    piece_range(k, c, b, e);
    const std::uint32_t* mem = members(c);
    const std::size_t lo = first_bin(k), hi = last_bin(k);
    double* sums = bin_pieces_.data() + k * per_piece;
    // The sums of the bin the last particle fell in, in registers (a layer's particles mostly
    // share one bin): loaded and stored back when the bin changes, the same additions in the
    // same order as straight into memory, without a store and reload per particle.
    constexpr std::size_t n = decltype(third)::value ? BinSums::kSums : BinSums::kSecond;
    double s[n];
    // A layer that lies inside one bin, with a margin far above the round-off of a position's
    // layer, puts every member in that bin: its positions need not be read.
    const double margin = 1e-9 * height;
    const std::size_t inside = slab_ && bin_of(system_->layer_lower(k) - margin) == bin_of(system_->layer_upper(k) + margin)
                                   ? bin_of(system_->layer_lower(k)) : bins;
    const bool read_y = positions && inside == bins;
    std::size_t open = positions && !read_y ? inside : lo;
    std::copy(sums + (open - lo) * stride, sums + (open - lo) * stride + n, s);
    for (std::size_t q = b; q < e; ++q) {
      const std::uint32_t i = mem ? mem[q] : static_cast<std::uint32_t>(q);
      const std::size_t bin = read_y ? std::clamp(bin_of(p.y[i]), lo, hi) : open;
      if (bin != open) {
        std::copy(s, s + n, sums + (open - lo) * stride);
        open = bin;
        std::copy(sums + (open - lo) * stride, sums + (open - lo) * stride + n, s);
      }
      const double vx = p.vx[i], vy = p.vy[i], vz = p.vz[i];
      s[BinSums::kCount] += 1.0;
      s[BinSums::kVx] += vx, s[BinSums::kVy] += vy, s[BinSums::kVz] += vz;
      s[BinSums::kVxx] += vx * vx, s[BinSums::kVyy] += vy * vy, s[BinSums::kVzz] += vz * vz;
      s[BinSums::kVxy] += vx * vy, s[BinSums::kVxz] += vx * vz, s[BinSums::kVyz] += vy * vz;
      if constexpr (decltype(third)::value) {
        const double v2 = vx * vx + vy * vy + vz * vz;
        s[BinSums::kWx] += v2 * vx, s[BinSums::kWy] += v2 * vy, s[BinSums::kWz] += v2 * vz;
      }
    }
    std::copy(s, s + n, sums + (open - lo) * stride);
  };
  for_pieces(pool, pieces, [&](std::size_t k) {
    if (heat) piece(k, std::true_type{});
    else piece(k, std::false_type{});
  });
  if (exchange_) exchange_->share(bin_pieces_.data(), per_piece);
  bin_sums_.assign(bins * stride, 0.0);
  for (std::size_t k = 0; k < pieces; ++k) {
    const std::size_t lo = first_bin(k), n = (last_bin(k) - lo + 1) * stride;
    const double* from = bin_pieces_.data() + k * per_piece;
    double* to = bin_sums_.data() + lo * stride;
    for (std::size_t j = 0; j < n; ++j) to[j] += from[j];
  }
  out.bin_sums = bin_sums_.data();
  out.bin_count = bins;
  out.bin_sum_stride = stride;
}

}  // namespace gdsmc::host
