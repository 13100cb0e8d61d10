#include "engine/streaming.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gdsmc::host {

namespace {
inline double wrap(double x, double length) {
  if (x >= length) x -= length;
  else if (x < 0) x += length;
  if (x < 0 || x >= length) {
    x -= length * std::floor(x / length);
    if (x >= length) x = 0;  // rounding of a value just below 0
  }
  return x;
}

inline void add(BoundaryTally& to, const BoundaryTally& from) {
  to.hits += from.hits;
  for (int a = 0; a < 3; ++a) to.momentum[a] += from.momentum[a];
  to.energy += from.energy;
}
}  // namespace

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
    StreamingTally& block = blocks_[k];
    block = StreamingTally{};
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
  for (std::size_t k = 0; k < blocks; ++k) {  // tallies are summed per block, then blocks in order
    const StreamingTally& block = blocks_[k];
    for (int s = 0; s < 2; ++s) add(tally.sides[s], block.sides[s]);
    tally.acceleration_energy += block.acceleration_energy;
  }
}

template <bool Accelerated, class LayerOf>
void Mover::stream_block(const ParticleSpan& p, std::uint32_t* cell, std::uint32_t* counts, const LayerOf layer_of,
                         std::size_t layers, std::size_t begin, std::size_t end, double t0, double dt, const StepContext& ctx,
                         const StreamFactory& streams, StreamingTally& tally) const {
  // The grid and the mover as locals: a store through a particle array may alias a member, so
  // the loop would re-read them per particle.
  double* const x = p.x.data;
  double* const y = p.y.data;
  double* const z = p.z.data;
  double* const vx = p.vx.data;
  double* const vy = p.vy.data;
  double* const vz = p.vz.data;
  const double half = half_, lx = lx_, lz = lz_;
  const Vec3 g = g_;
  const double half_dt2 = 0.5 * dt * dt;
  const double g2 = dot(g, g);
  double energy = 0;
  // The block's layer counts for the sort: an increment here, where the flight's loads hide it,
  // instead of a pass of the sort's own over cell[].
  if (counts) std::fill(counts, counts + layers, 0u);
  const auto place = [&](std::size_t i, std::uint32_t l) {
    cell[i] = l;
    if (counts) ++counts[l];
  };
  // The particles that reach a wall are flown after each chunk of kHitBuffer particles, in index
  // order (the tally's sums come in the same order, so the same bits): with the call to
  // fly_with_hits inside the loop, the values the loop keeps lived on the stack (a call clobbers
  // every vector register), and the flight reloaded them per particle.
  std::uint32_t hit[kHitBuffer];
  std::size_t hits = 0;
  const auto fly_hits = [&] {
    for (std::size_t h = 0; h < hits; ++h) {
      const std::uint32_t i = hit[h];
      fly_with_hits(p, i, t0, dt, ctx, streams, tally);
      place(i, layer_of(y[i]));
    }
    hits = 0;
  };
  for (std::size_t chunk = begin; chunk < end; chunk += kHitBuffer) {
    for (std::size_t i = chunk, chunk_end = std::min(end, chunk + kHitBuffer); i < chunk_end; ++i) {
      double y1 = y[i] + vy[i] * dt;
      bool inside;
      if constexpr (Accelerated) {
        y1 += g.y * half_dt2;
        inside = y1 >= -half && y1 <= half;
        // A parabola can leave and come back within the step: check its apex.
        if (inside && g.y != 0 && vy[i] * (vy[i] + g.y * dt) < 0) {
          const double apex = y[i] - vy[i] * vy[i] / (2.0 * g.y);
          inside = apex >= -half && apex <= half;
        }
      } else {
        inside = y1 >= -half && y1 <= half;
      }
      if (!inside) {
        hit[hits++] = static_cast<std::uint32_t>(i);
        continue;
      }
      if constexpr (Accelerated) {
        energy += (g.x * vx[i] + g.y * vy[i] + g.z * vz[i]) * dt + 0.5 * g2 * dt * dt;
        x[i] = wrap(x[i] + vx[i] * dt + g.x * half_dt2, lx);
        z[i] = wrap(z[i] + vz[i] * dt + g.z * half_dt2, lz);
        vx[i] += g.x * dt;
        vy[i] += g.y * dt;
        vz[i] += g.z * dt;
      } else {
        x[i] = wrap(x[i] + vx[i] * dt, lx);
        z[i] = wrap(z[i] + vz[i] * dt, lz);
      }
      y[i] = y1;
      place(i, layer_of(y1));
    }
    if (hits) fly_hits();
  }
  tally.acceleration_energy += energy;
}

void Mover::fly_with_hits(const ParticleSpan& p, std::size_t i, double t0, double dt, const StepContext& ctx,
                          const StreamFactory& streams, StreamingTally& tally) const {
  Vec3 r{p.x[i], p.y[i], p.z[i]}, v{p.vx[i], p.vy[i], p.vz[i]};
  double left = dt;
  Rng rng;
  bool have_rng = false;
  const double g2 = dot(g_, g_);
  auto advance = [&](double t) {
    tally.acceleration_energy += dot(g_, v) * t + 0.5 * g2 * t * t;
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
    BoundaryTally& t = tally.sides[s];
    ++t.hits;
    t.momentum[0] += after.x - v.x;
    t.momentum[1] += after.y - v.y;
    t.momentum[2] += after.z - v.z;
    t.energy += 0.5 * (dot(after, after) - dot(v, v));
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
