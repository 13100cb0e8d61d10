#include "engine/streaming.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace gdsmc::host {

namespace {
// A position more than one period outside [0, length), after one period was added or taken away.
inline double wrap_far(double x, double length) {
  x -= length * std::floor(x / length);
  return x >= length ? 0.0 : x;  // rounding of a value just below 0
}
inline double wrap(double x, double length) {
  if (x >= length) x -= length;
  else if (x < 0) x += length;
  if (x < 0 || x >= length) x = wrap_far(x, length);
  return x;
}

}  // namespace

ExactBoundaryTally& ExactBoundaryTally::operator+=(const ExactBoundaryTally& other) {
  hits += other.hits;
  for (int a = 0; a < 3; ++a) momentum[a] += other.momentum[a];
  energy += other.energy;
  return *this;
}

BoundaryTally ExactBoundaryTally::value(const TallyUnits& units) const {
  BoundaryTally t;
  t.hits = hits;
  for (int a = 0; a < 3; ++a) t.momentum[a] = momentum[a].value(units.momentum);
  t.energy = energy.value(units.energy);
  return t;
}

ExactStreamingTally& ExactStreamingTally::operator+=(const ExactStreamingTally& other) {
  for (int s = 0; s < 2; ++s) sides[s] += other.sides[s];
  acceleration_energy += other.acceleration_energy;
  for (std::size_t k = 0; k < species_sides.size(); ++k) species_sides[k] += other.species_sides[k];
  return *this;
}

void StreamingTally::to_values(const TallyUnits& units, std::size_t species) {
  for (int s = 0; s < 2; ++s) {
    sides[s] = exact.sides[s].value(units);
    for (std::size_t q = 0; q < species; ++q)
      species_sides[s * kMaxSpecies + q] = exact.species_sides[s * kMaxSpecies + q].value(units);
  }
  acceleration_energy = exact.acceleration_energy.value(units.energy);
}

double first_crossing(double y0, double v, double g, double plane, double t_max) {
  const double c = y0 - plane;
  if (g == 0) {
    if (v == 0) return -1;
    const double t = -c / v;
    return (t > 0 && t <= t_max) ? t : -1;
  }
  // (g/2) t^2 + v t + c = 0, roots in the cancellation-free form q/a and c/q.
  const double disc = v * v - 2.0 * g * c;
  if (disc < 0) return -1;
  const double q = -0.5 * (v + std::copysign(std::sqrt(disc), v));
  if (q == 0) return -1;
  const double t1 = q / (0.5 * g), t2 = c / q;
  double best = -1;
  for (double t : {t1, t2})
    if (t > 0 && t <= t_max && (best < 0 || t < best)) best = t;
  return best;
}

Mover::Mover(const double box[3], const Vec3& g, std::array<Side, 2> sides)
    : lx_(box[0]), ly_(box[1]), lz_(box[2]), half_(0.5 * box[1]), g_(g), sides_(std::move(sides)) {}

void Mover::stream(const ParticleSpan& p, std::uint32_t* cell, std::uint32_t* layer_counts, const CellGrid& grid,
                   double t0, double dt, const StepContext& ctx, const StreamFactory& streams, StreamingTally& tally,
                   WorkPool* pool) const {
  const bool accelerated = g_.x != 0 || g_.y != 0 || g_.z != 0;
  const std::size_t blocks = CellGrid::sort_blocks(p.count);  // kBlock = kSortBlock: a block's counts are a sort row
  if (blocks_.size() < blocks) blocks_.resize(blocks);
  for_pieces(pool, blocks, [&](std::size_t k) {
    ExactStreamingTally& block = blocks_[k];
    block.sides = {};
    block.acceleration_energy = {};
    if (mass_) block.species_sides = {};  // a mixture's only: one species leaves them untouched
    const std::size_t b = k * kBlock, e = std::min(p.count, b + kBlock);
    std::uint32_t* counts = layer_counts ? layer_counts + k * grid.count() : nullptr;
    // The uniform layers' arithmetic, or the lookup table of layers with edges: a loop for each,
    // so neither pays for the other.
    if (grid.uniform()) {
      const CellGrid::LayerIndex index = grid.layer_index();
      if (accelerated) stream_block<true>(p, cell, counts, index, grid.count(), b, e, t0, dt, ctx, streams, block);
      else stream_block<false>(p, cell, counts, index, grid.count(), b, e, t0, dt, ctx, streams, block);
    } else {
      const CellGrid::TableIndex index = grid.table_index();
      if (accelerated) stream_block<true>(p, cell, counts, index, grid.count(), b, e, t0, dt, ctx, streams, block);
      else stream_block<false>(p, cell, counts, index, grid.count(), b, e, t0, dt, ctx, streams, block);
    }
  });
  // Integer sums: the blocks in any order give the same bits (as would any other split of the particles).
  ExactStreamingTally& exact = tally.exact;
  for (std::size_t k = 0; k < blocks; ++k) {
    const ExactStreamingTally& block = blocks_[k];
    for (int s = 0; s < 2; ++s) exact.sides[s] += block.sides[s];
    exact.acceleration_energy += block.acceleration_energy;
    if (mass_)
      for (int s = 0; s < 2; ++s)
        for (std::size_t q = 0; q < species_count_; ++q) {
          const std::size_t at = s * StreamingTally::kMaxSpecies + q;
          exact.species_sides[at] += block.species_sides[at];
        }
  }
  tally.to_values(units_, mass_ ? species_count_ : 0);
}

namespace {
// The particles' arrays, as restrict pointers: a store through one cannot change another.
struct FlightArrays {
  double* __restrict x;
  double* __restrict y;
  double* __restrict z;
  double* __restrict vx;
  double* __restrict vy;
  double* __restrict vz;
};

constexpr std::size_t kChunk = Mover::kHitBuffer;

// Pass 1 of a chunk's flight, one particle after another without a branch (so the compiler
// vectorizes it): every particle that stays between the planes is flown (x += v t + g t^2/2,
// v += g t), the others are left as they were and marked in out[]; e[k] is
// the work of the body acceleration on particle k (0 for the marked ones), far[k] marks a
// position that one period does not bring back into the box (wrapped in pass 2), and layer[k]
// the equal layer of the new y (when `Equal`). Compiled for AVX-512 and AVX2 as well as the
// baseline, one chosen at load time: the same bits (IEEE operations; CMakeLists.txt forbids fused
// multiply-adds in this file). In cache, 3.1 ns a particle with a body force against 10.8 ns for the
// loop with branches it replaced (BM_SlabFlight, 10^4 particles, docs/performance.md).
template <bool Accelerated, bool Vertical, bool Equal>
__attribute__((target_clones("avx512f", "avx2", "default"))) void fly_pass(
    const FlightArrays a, const CellGrid::LayerIndex index, std::size_t begin, std::size_t m, double dt, double half,
    double lx, double lz, double gx, double gy, double gz, double* __restrict e, std::uint64_t* __restrict out,
    std::uint64_t* __restrict far, std::uint32_t* __restrict layer) {
  double* __restrict x = a.x + begin;
  double* __restrict y = a.y + begin;
  double* __restrict z = a.z + begin;
  double* __restrict vx = a.vx + begin;
  double* __restrict vy = a.vy + begin;
  double* __restrict vz = a.vz + begin;
  const double half_dt2 = 0.5 * dt * dt;
  const double g2 = gx * gx + gy * gy + gz * gz;
  const double kick = 0.5 * g2 * dt * dt;
  for (std::size_t k = 0; k < m; ++k) {
    const double y0 = y[k], vy0 = vy[k], vx0 = vx[k], vz0 = vz[k];
    double y1 = y0 + vy0 * dt;
    if constexpr (Accelerated) y1 += gy * half_dt2;
    bool outside = !((y1 >= -half) & (y1 <= half));
    if constexpr (Vertical) {
      // A parabola can leave and come back within the step: its apex, where v_y changes sign.
      const double apex = y0 - vy0 * vy0 / (2.0 * gy);
      outside = outside | ((vy0 * (vy0 + gy * dt) < 0) & !((apex >= -half) & (apex <= half)));
    }
    double x1, z1;
    if constexpr (Accelerated) {
      x1 = x[k] + vx0 * dt + gx * half_dt2;
      z1 = z[k] + vz0 * dt + gz * half_dt2;
    } else {
      x1 = x[k] + vx0 * dt;
      z1 = z[k] + vz0 * dt;
    }
    // Every value computed, then selected (a conditional operation would not be vectorized: it could
    // raise a floating-point exception the scalar code would not).
    const double x_down = x1 - lx, x_up = x1 + lx, z_down = z1 - lz, z_up = z1 + lz;
    x1 = x1 >= lx ? x_down : (x1 < 0 ? x_up : x1);
    z1 = z1 >= lz ? z_down : (z1 < 0 ? z_up : z1);
    far[k] = !((x1 >= 0) & (x1 < lx)) | !((z1 >= 0) & (z1 < lz));
    out[k] = outside;
    x[k] = outside ? x[k] : x1;
    z[k] = outside ? z[k] : z1;
    y[k] = outside ? y0 : y1;
    if constexpr (Accelerated) {
      const double work = (gx * vx0 + gy * vy0 + gz * vz0) * dt + kick;
      const double vx1 = vx0 + gx * dt, vy1 = vy0 + gy * dt, vz1 = vz0 + gz * dt;
      e[k] = outside ? 0.0 : work;
      vx[k] = outside ? vx0 : vx1;
      vy[k] = outside ? vy0 : vy1;
      vz[k] = outside ? vz0 : vz1;
    }
    if constexpr (Equal) layer[k] = index(y1);
  }
}

// The body force's work on a chunk's particles (e[k] of fly_pass, 0 for those left to
// fly_with_hits), each weighed by its species' mass in a mixture, as the sums of its terms' fixed-point
// parts (FixedPointSum::split): integer sums, so the compiler adds them in vector lanes and still
// gets the integers of one term after another. The same versions as fly_pass, the same bits.
static_assert(kChunk < 4096, "a chunk's fixed-point parts are summed in 64 bits (FixedPointSum::add)");
template <bool Weighted>
__attribute__((target_clones("avx512f", "avx2", "default"))) FixedPointSum::Parts work_parts(
    const double* __restrict e, const std::uint32_t* __restrict species, const double* __restrict mass, std::size_t m,
    const FixedPointUnit unit) {
  std::int64_t high = 0, low = 0, out = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const FixedPointSum::Parts p = FixedPointSum::split(Weighted ? mass[species[k]] * e[k] : e[k], unit);
    high += p.high;
    low += p.low;
    out |= p.out_of_range;
  }
  return {high, low, out};
}
}  // namespace

template <bool Accelerated, class LayerOf>
void Mover::stream_block(const ParticleSpan& p, std::uint32_t* cell, std::uint32_t* counts, const LayerOf layer_of,
                         std::size_t layers, std::size_t begin, std::size_t end, double t0, double dt, const StepContext& ctx,
                         const StreamFactory& streams, ExactStreamingTally& tally) const {
  constexpr bool equal = std::is_same_v<LayerOf, CellGrid::LayerIndex>;
  const FlightArrays a{p.x.data, p.y.data, p.z.data, p.vx.data, p.vy.data, p.vz.data};
  CellGrid::LayerIndex index{};
  if constexpr (equal) index = layer_of;
  // The block's layer counts for the sort: an increment in the flight instead of a pass of the
  // sort's own over cell[]; without counts (no sort follows) the rows are counted and dropped.
  if (counts) std::fill(counts, counts + layers, 0u);
  thread_local std::vector<std::uint32_t> rows;
  rows.assign(4 * layers, 0u);
  const bool vertical = Accelerated && g_.y != 0;  // the apex test of a parabola along y
  FixedPointSum energy;
  const FixedPointUnit unit = units_.energy;
  alignas(64) double e[kChunk];
  alignas(64) std::uint64_t out[kChunk], far[kChunk];  // 0 or 1, as wide as a double lane
  alignas(64) std::uint32_t layer[kChunk];
  std::uint32_t hit[kChunk];
  for (std::size_t chunk = begin; chunk < end; chunk += kChunk) {
    const std::size_t m = std::min(end - chunk, kChunk);
    if (vertical)
      fly_pass<Accelerated, Accelerated, equal>(a, index, chunk, m, dt, half_, lx_, lz_, g_.x, g_.y, g_.z, e, out, far, layer);
    else
      fly_pass<Accelerated, false, equal>(a, index, chunk, m, dt, half_, lx_, lz_, g_.x, g_.y, g_.z, e, out, far, layer);
    if constexpr (Accelerated) {
      const FixedPointSum::Parts w = mass_ ? work_parts<true>(e, p.species + chunk, mass_, m, unit)
                                           : work_parts<false>(e, nullptr, nullptr, m, unit);
      energy.add(w.high, w.low, w.out_of_range);
    }
    // Pass 2, in index order: the hits listed, the wraps of far positions, the layer and its count.
    // The counts in four rows, particle k in row k mod 4, summed at the block's end: one counter
    // incremented particle after particle waits for its previous store, and counting runs of one
    // layer instead mispredicts wherever the layers are narrow (perf: 40 % of the pass in a
    // clustered channel of 180 layers).
    std::size_t hits = 0;
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = chunk + k;
      if (out[k]) {
        hit[hits++] = static_cast<std::uint32_t>(i);
        continue;
      }
      if (far[k]) {
        if (!(a.x[i] >= 0 && a.x[i] < lx_)) a.x[i] = wrap_far(a.x[i], lx_);
        if (!(a.z[i] >= 0 && a.z[i] < lz_)) a.z[i] = wrap_far(a.z[i], lz_);
      }
      const std::uint32_t l = equal ? layer[k] : layer_of(a.y[i]);
      cell[i] = l;
      ++rows[(k & 3) * layers + l];
    }
    for (std::size_t h = 0; h < hits; ++h) {
      const std::uint32_t i = hit[h];
      fly_with_hits(p, i, t0, dt, ctx, streams, tally);
      const std::uint32_t l = layer_of(p.y[i]);
      cell[i] = l;
      if (counts) ++counts[l];
    }
  }
  if (counts)
    for (std::size_t c = 0; c < layers; ++c) counts[c] += rows[c] + rows[layers + c] + rows[2 * layers + c] + rows[3 * layers + c];
  tally.acceleration_energy += energy;
}

void Mover::fly_with_hits(const ParticleSpan& p, std::size_t i, double t0, double dt, const StepContext& ctx,
                          const StreamFactory& streams, ExactStreamingTally& tally) const {
  Vec3 r{p.x[i], p.y[i], p.z[i]}, v{p.vx[i], p.vy[i], p.vz[i]};
  double left = dt;
  Rng rng;
  bool have_rng = false;
  const double g2 = dot(g_, g_);
  const std::uint32_t species = p.species_of(i);
  const double m = mass_ ? mass_[species] : 1.0;  // x 1.0: the one-species bits
  auto advance = [&](double t) {
    tally.acceleration_energy.add(m * (dot(g_, v) * t + 0.5 * g2 * t * t), units_.energy);
    r = r + t * v + (0.5 * t * t) * g_;
    v = v + t * g_;
  };
  for (int hits = 0;; ++hits) {
    const double t_low = first_crossing(r.y, v.y, g_.y, -half_, left);
    const double t_high = first_crossing(r.y, v.y, g_.y, half_, left);
    if (t_low < 0 && t_high < 0) {
      advance(left);
      r.y = std::clamp(r.y, -half_, half_);  // a crossing lost to rounding at the very end
      break;
    }
    const int s = (t_high < 0 || (t_low >= 0 && t_low <= t_high)) ? 0 : 1;
    const double tc = s == 0 ? t_low : t_high;
    const double plane = s == 0 ? -half_ : half_;
    if (hits >= max_hits_per_step)
      throw std::runtime_error(sides_[s].name + ": particle " + std::to_string(p.id[i]) + " hit the boundaries " +
                               std::to_string(max_hits_per_step) +
                               " times in one step; the time step is too long for the gap or the boundary "
                               "re-emits particles that cannot leave it");
    advance(tc);
    r.y = plane;
    left -= tc;
    WallHit hit;
    hit.id = p.id[i];
    hit.side = s == 0 ? -1 : 1;
    hit.position = r;
    hit.velocity = v;
    hit.time = t0 + (dt - left);
    hit.remaining = left;
    hit.species = species;
    if (!have_rng) {
      rng = streams.rng(StreamPurpose::boundary, 0, p.id[i]);
      have_rng = true;
    }
    const HitResult result = sides_[s].boundary->interact(ctx, hit, rng);
    const Vec3 after = hit.velocity;
    if (!std::isfinite(after.x) || !std::isfinite(after.y) || !std::isfinite(after.z) ||
        !std::isfinite(hit.position.x) || !std::isfinite(hit.position.z))
      throw std::runtime_error(sides_[s].name + " returned a non-finite velocity or position");
    // Reflected: back into the gas from this plane; transferred: on through the opposite plane.
    const double inward = result == HitResult::transferred ? -hit.side : hit.side;
    if (!(after.y * inward < 0))
      throw std::runtime_error(sides_[s].name + (result == HitResult::transferred ? " transferred" : " reflected") +
                               " a particle with v_y = " + std::to_string(after.y) +
                               ", which does not point into the gas");
    const double dp[3] = {m * (after.x - v.x), m * (after.y - v.y), m * (after.z - v.z)};
    const double de = 0.5 * m * (dot(after, after) - dot(v, v));
    for (ExactBoundaryTally* t : {&tally.sides[s], mass_ ? &tally.species_sides[s * StreamingTally::kMaxSpecies + species] : nullptr}) {
      if (!t) continue;
      ++t->hits;
      for (int a = 0; a < 3; ++a) t->momentum[a].add(dp[a], units_.momentum);
      t->energy.add(de, units_.energy);
    }
    v = after;
    r = Vec3{hit.position.x, result == HitResult::transferred ? -plane : plane, hit.position.z};
  }
  p.x[i] = wrap(r.x, lx_);
  p.y[i] = r.y;
  p.z[i] = wrap(r.z, lz_);
  p.vx[i] = v.x;
  p.vy[i] = v.y;
  p.vz[i] = v.z;
}

}  // namespace gdsmc::host
