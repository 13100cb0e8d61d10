#include "engine/collision_stage.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/bulk_rng.hpp"
#include "engine/interrupt.hpp"
#include "engine/majorant.hpp"
#include "engine/weighted_layer.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

std::size_t subpopulation_count(std::size_t particles, std::size_t size) {
  if (size == 0 || particles <= size) return 1;
  return (particles + size - 1) / size;
}

void CollisionStage::reset(std::size_t cells) {
  kept_.invalidate();
  ratio_.assign(cells, kInitialMajorantRatio);
  remainder_.assign(cells, 0.0);
  energy_.assign(cells, 0.0);
  speed_.assign(cells, 0.0);
  estimate_.assign(cells, 0.0);
  max_rate_.assign(cells, 0.0);
  missed_.assign(cells, 0.0);
  missed_so_far_.assign(cells, 0.0);
  collided_so_far_.assign(cells, 0.0);
  counts_.assign(3 * cells, 0);
  groups_.assign(cells, Group{});
  cell_tallies_.assign(cells * tally_count_, 0.0);
}

void CollisionStage::reset_majorants() {
  for (std::size_t c = 0; c < ratio_.size(); ++c) {
    if (missed_so_far_[c] <= kMissedCollisionsTolerance * collided_so_far_[c])
      ratio_[c] = std::max(kInitialMajorantRatio, kMajorantDecay * ratio_[c]);
  }
}

void CollisionStage::set_tally_count(std::size_t count) {
  tally_count_ = count;
  cell_tallies_.assign(ratio_.size() * count, 0.0);
  step_tallies_.assign(count, 0.0);
}

namespace {
std::uint64_t gcd(std::uint64_t a, std::uint64_t b) {
  while (b) {
    const std::uint64_t t = a % b;
    a = b;
    b = t;
  }
  return a;
}
// a^-1 mod n for gcd(a, n) = 1 (extended Euclid).
std::uint64_t inverse_mod(std::uint64_t a, std::uint64_t n) {
  std::int64_t t = 0, new_t = 1;
  std::int64_t r = static_cast<std::int64_t>(n), new_r = static_cast<std::int64_t>(a);
  while (new_r != 0) {
    const std::int64_t q = r / new_r;
    std::int64_t x = t - q * new_t;
    t = new_t;
    new_t = x;
    x = r - q * new_r;
    r = new_r;
    new_r = x;
  }
  return static_cast<std::uint64_t>(t < 0 ? t + static_cast<std::int64_t>(n) : t);
}
}  // namespace

void CollisionStage::make_groups(const CellGrid& grid, std::size_t particles, const StreamFactory& streams) {
  const std::size_t n = groups_.size();
  if (grid.is_slab() || n == 1) {
    for (std::size_t c = 0; c < n; ++c)
      groups_[c] = Group{grid.members(c), 0, 1, grid.members_count(c), grid.cell_volume(c)};
    // A homogeneous system of one group draws weighted pairs like a layer: its members are storage
    // order (the list is written once per particle count, not per step).
    if (!grid.is_slab() && weighted_) {
      if (identity_.size() != particles) {
        identity_.resize(particles);
        for (std::size_t i = 0; i < particles; ++i) identity_[i] = static_cast<std::uint32_t>(i);
      }
      groups_[0].members = identity_.data();
    }
    return;
  }
  // Sub-populations: scramble the storage order by m = (s i + r) mod N with a random unit s and a
  // random offset r, and cut m into K ranges [kN/K, (k+1)N/K). Group k is then the arithmetic
  // progression i = s^-1 (m - r) mod N: no list, and from one step to the next two particles
  // share a group with probability ~1/K whatever their places in storage (a rotation alone keeps
  // neighbours in storage together, and the groups then develop flows of their own: an HCS at
  // alpha = 0.5 cooled 200 times too slowly with K = 5).
  const std::uint64_t total = particles;
  Rng rng = streams.rng(StreamPurpose::collisions, 1, 0);
  std::uint64_t s;  // in [2, N - 1]: s = 1 would make the stride 1, which CellCollision reads as a
                    // range without wrap-around (N > K >= 2, and N > size >= 2, so N >= 3)
  do s = 2 + rng.below(static_cast<std::uint32_t>(total - 2));
  while (gcd(s, total) != 1);
  const std::uint64_t r = rng.below(static_cast<std::uint32_t>(total));
  const std::uint64_t inverse = inverse_mod(s, total);
  const double all_pairs = pair_count(scheme_, static_cast<std::uint32_t>(total));
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t b = k * total / n, e = (k + 1) * total / n;
    Group& g = groups_[k];
    g.count = static_cast<std::uint32_t>(e - b);
    // The whole system's candidate rate per particle: P(N_c) / V_c = (N_c / N) P(N) / V.
    g.volume = grid.cell_volume() * pair_count(scheme_, g.count) * static_cast<double>(total) /
               (all_pairs * static_cast<double>(g.count));
    g.members = nullptr;
    g.first = static_cast<std::uint32_t>(static_cast<unsigned __int128>(inverse) * ((b + total - r) % total) % total);
    g.stride = inverse;
  }
}

double CollisionStage::reference_temperature(const CellMoments* cells, std::size_t c, double temperature) {
  return cells && cells[c].count >= 2 && cells[c].temperature > 0 ? cells[c].temperature : temperature;
}

void CollisionStage::set_layer_majorants(const CellMoments* cells, const double* peculiar_speed_max, double temperature,
                                         double mass) {
  for (std::size_t c = 0; c < ratio_.size(); ++c) {
    const double speed = std::sqrt(reference_temperature(cells, c, temperature) / mass);
    ratio_[c] = std::max(kInitialMajorantRatio, kMajorantHeadroom * 2.0 * peculiar_speed_max[c] / speed);
  }
}

namespace {
// Particle a of a group without a member list: (first + a * stride) mod n, by a Barrett reduction
// (barrett = floor((2^64 - 1) / n), computed once per group), so no division per candidate.
inline std::uint32_t strided_particle(std::uint64_t first, std::uint64_t stride, std::uint32_t a, std::uint64_t n,
                                      std::uint64_t barrett) {
  const std::uint64_t x = first + static_cast<std::uint64_t>(a) * stride;
  const auto q = static_cast<std::uint64_t>((static_cast<unsigned __int128>(x) * barrett) >> 64);
  std::uint64_t r = x - q * n;
  while (r >= n) r -= n;
  return static_cast<std::uint32_t>(r);
}

template <class T>
inline void prefetch(const T* a) {
#if defined(__GNUC__)
  __builtin_prefetch(a, 1, 3);  // written if the pair collides
#else
  (void)a;
#endif
}

// One batch of candidates being drawn: at most kPairBatch pairs with no particle twice (a set of
// the cell's local indices, hashed into kSeenBits bits: a clash, real or of the hash, closes the
// batch early). Since the rule draws from its own stream and takes the pairs in order on the
// current velocities, where a batch ends changes only the speed, never a result.
constexpr std::uint32_t kPairBatch = 32;
// A uniform draw of this many candidates (three numbers each) or more takes its numbers from a
// BulkRng (64 at a time); fewer, from the stream itself.
constexpr std::uint64_t kBulkCandidates = 32;
constexpr std::uint32_t kSeenBits = 4096;
struct BatchScratch {
  std::uint32_t i[kPairBatch], j[kPairBatch];
  Vec3 v1[kPairBatch], v2[kPairBatch];
  double u[kPairBatch], w[kPairBatch];
  // Weighted pairs: each pair's time in the step and its particles' local indices.
  double t[kPairBatch];
  std::uint32_t la[kPairBatch], lb[kPairBatch];
  std::uint8_t accepted[kPairBatch];
  std::uint64_t seen[kSeenBits / 64];
  bool dirty = true;  // seen may hold bits of pairs no longer open (a batch left by an exception)
  bool holds(std::uint32_t a) const { return (seen[(a & (kSeenBits - 1)) >> 6] >> (a & 63)) & 1; }
  // An empty batch whose arrays the rule sees through `b`. The scratch is kept per thread (a layer
  // step holds a few candidates: clearing 512 bytes per layer cost more than drawing them).
  void open(PairBatch& b) {
    if (dirty) std::memset(seen, 0, sizeof seen);
    dirty = false;
    b.i = i, b.j = j, b.v1 = v1, b.v2 = v2, b.u = u, b.accepted = accepted;
  }
  // The set emptied after the first m pairs (local indices la, lb) were closed: their words only.
  void forget(std::uint32_t m) {
    for (std::uint32_t q = 0; q < m; ++q) seen[(la[q] & (kSeenBits - 1)) >> 6] = seen[(lb[q] & (kSeenBits - 1)) >> 6] = 0;
  }
  // The first m pairs' velocities from storage (prefetched as the pairs were drawn).
  void load_velocities(std::uint32_t m, const double* vx, const double* vy, const double* vz) {
    for (std::uint32_t q = 0; q < m; ++q) {
      v1[q] = Vec3{vx[i[q]], vy[i[q]], vz[i[q]]};
      v2[q] = Vec3{vx[j[q]], vy[j[q]], vz[j[q]]};
    }
  }
  // The accepted ones of the first m pairs back to storage.
  void store_accepted(std::uint32_t m, double* vx, double* vy, double* vz) const {
    for (std::uint32_t q = 0; q < m; ++q) {
      if (!accepted[q]) continue;
      vx[i[q]] = v1[q].x, vy[i[q]] = v1[q].y, vz[i[q]] = v1[q].z;
      vx[j[q]] = v2[q].x, vy[j[q]] = v2[q].y, vz[j[q]] = v2[q].z;
    }
  }
  void add(std::uint32_t a) {
    seen[(a & (kSeenBits - 1)) >> 6] |= std::uint64_t{1} << (a & 63);
    dirty = true;
  }
};
}  // namespace

CollisionStage::CollisionStage(PairCount scheme) : scheme_(scheme) {}
CollisionStage::~CollisionStage() = default;

void CollisionStage::collide_candidates(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                        std::uint64_t candidates, Rng& stream, PairBatch& batch, bool kept) {
  const Group& group = groups_[c];
  const std::uint32_t* const members = group.members;
  const std::uint64_t first = group.first, stride = group.stride, total = particles.count;
  const std::uint64_t barrett = total ? ~std::uint64_t{0} / total : 0;
  const std::uint32_t count = group.count;
  // Particle a of the group: a member list (slab layers), a contiguous range, or a strided one
  // (the sub-populations of a homogeneous system).
  auto particle = [&](std::uint32_t a) -> std::uint32_t {
    if (members) return members[a];
    if (stride == 1) return static_cast<std::uint32_t>(first + a);
    return strided_particle(first, stride, a, total, barrett);
  };
  double* const vx = particles.vx.data;
  double* const vy = particles.vy.data;
  double* const vz = particles.vz.data;
  thread_local BatchScratch s;
  s.open(batch);
  batch.speed_bounds = nullptr;
  std::uint32_t m = 0;
  // The batch's velocities (prefetched as its pairs were drawn) to the rule, and the accepted
  // pairs' back to storage.
  std::uint8_t* const bound = kept ? kept_.levels() : nullptr;
  const auto flush = [&] {
    s.load_velocities(m, vx, vy, vz);
    batch.count = m;
    rule.collide_batch(batch);
    s.store_accepted(m, vx, vy, vz);
    if (bound)
      for (std::uint32_t q = 0; q < m; ++q)
        if (s.accepted[q]) {
          bound[s.i[q]] = kept_.level(s.v1[q].x, s.v1[q].y, s.v1[q].z);
          bound[s.j[q]] = kept_.level(s.v2[q].x, s.v2[q].y, s.v2[q].z);
        }
    s.forget(m);
    s.dirty = false;
    m = 0;
  };
  // A candidate into the open batch (its velocities prefetched), the batch closed when full.
  const auto open = [&](std::uint32_t a, std::uint32_t b, std::uint32_t i, std::uint32_t j, double u) {
    s.add(a);
    s.add(b);
    s.i[m] = i;
    s.j[m] = j;
    s.la[m] = a;
    s.lb[m] = b;
    s.u[m] = u;
    prefetch(vx + i), prefetch(vy + i), prefetch(vz + i);
    prefetch(vx + j), prefetch(vy + j), prefetch(vz + j);
    if (++m == kPairBatch) flush();
  };
  // The candidates from `draws` (the stream itself, or drawn ahead by BulkRng: the same numbers).
  const auto draw_all = [&](auto& draws) {
    if (bound) {
      // Candidates drawn kAhead ahead of their test, their bounds prefetched. A candidate that
      // meets a particle of the open batch closes it first (its bound is then current); one whose
      // u w is not below the two bounds' sum is rejected here, as the rule would reject it
      // (u w >= |g|), without its velocities; the rest go to the rule in order, as without bounds.
      constexpr std::uint32_t kAhead = 16;
      struct Drawn {
        std::uint32_t a, b, i, j;
        double u;
      } ring[kAhead];
      const double w = batch.speed_bound;
      const double* const level = kept_.speeds();
      const auto test = [&](const Drawn& d) {
        if (m > 0 && (s.holds(d.a) || s.holds(d.b))) flush();
        if (d.u * w >= level[bound[d.i]] + level[bound[d.j]]) return;
        open(d.a, d.b, d.i, d.j, d.u);
      };
      for (std::uint64_t k = 0; k < candidates; ++k) {
        Drawn& d = ring[k % kAhead];
        if (k >= kAhead) test(d);
        d.a = draws.below(count);
        d.b = draws.below(count - 1);
        d.b += (d.b >= d.a);
        d.u = draws.uniform32();
        d.i = particle(d.a);
        d.j = particle(d.b);
        prefetch(bound + d.i), prefetch(bound + d.j);
      }
      for (std::uint64_t k = candidates > kAhead ? candidates - kAhead : 0; k < candidates; ++k)
        test(ring[k % kAhead]);
    } else {
      for (std::uint64_t k = 0; k < candidates; ++k) {
        const std::uint32_t a = draws.below(count);
        std::uint32_t b = draws.below(count - 1);
        b += (b >= a);
        const double u = draws.uniform32();
        if (m > 0 && (s.holds(a) || s.holds(b))) flush();
        open(a, b, particle(a), particle(b), u);
      }
    }
    if (m > 0) flush();
  };
  // Three numbers a candidate: sixteen Philox blocks at a time once there are enough of them.
  draw_from(stream, candidates >= kBulkCandidates, draw_all);
}

// Weighted pairs of one layer over the step (000 Eq. 4.13 with pair majorants c_a + c_b): envelope
// events at the rate R = K E, K = sigma^2 pi scale (2 P(N_c) / N_c) / V_c, on a time counter whose
// credit is carried from step to step (as the uniform candidates' remainder). Particle a initiates
// candidates at the rate K c_a, with a partner drawn uniformly, so the pair (a, b) is a candidate at
// the rate K (c_a + c_b) / (N_c - 1) = (P / C(N_c, 2)) sigma^2 pi scale (c_a + c_b) / V_c, and
// collides with probability |g| / (c_a + c_b): the hard-sphere rate, pair by pair.
// A batch holds no particle twice, and a drawn pair that meets a particle of the open batch closes
// it first, so every test sees current speeds. When a collision lifts a particle's bound by dB at
// time t_q, its extra events (rate K dB, initiated by it, partner uniform) until the envelope takes
// them over are drawn: none before the batch's last event is the rule, and the batch stands; else
// the batch is cut at the first one's time E (the rule's work on the pairs after E is undone by
// running it again on the pairs before E from the saved stream, results and tallies), that event is
// the next candidate, and the time counter starts again at E. Returns the credit left at dt.
template <class Draws>
double CollisionStage::weighted_step(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                     WeightedLayer& layer, double credit, double dt, Draws& select, PairBatch& batch) {
  const Group& group = groups_[c];
  const std::uint32_t* const members = group.members;
  const std::uint32_t count = group.count;
  double* const vx = particles.vx.data;
  double* const vy = particles.vy.data;
  double* const vz = particles.vz.data;
  const double per_bound = 2.0 * pair_count(scheme_, count) / count * batch.sigma * batch.sigma * M_PI *
                           rule.rate_bound(1.0) / group.volume;  // K
  batch.speed_bound = 2.0 * layer.bulk_bound();  // the bulk's pair bound (for a rule that looks)
  batch.rate_bound = rule.rate_bound(batch.speed_bound);
  thread_local BatchScratch s;
  s.open(batch);
  batch.speed_bounds = s.w;
  std::uint32_t m = 0;
  std::uint64_t candidates = 0;
  // The time counter: since the anchor time t0 with credit f0 at rate R, envelope event k (k >= 1)
  // is at t0 + (k - f0) / R; `events` of them drawn so far, those at or before dt while
  // events + 1 <= budget.
  double t0 = 0, f0 = credit, rate = per_bound * layer.envelope(), inverse_rate = 1.0 / rate;
  double budget = std::isfinite(rate) ? f0 + rate * dt : 0.0;
  std::uint64_t events = 0;
  const auto anchor = [&](double t, double f) {
    t0 = t;
    f0 = std::min(std::max(f, 0.0), std::nextafter(1.0, 0.0));
    rate = per_bound * layer.envelope();
    inverse_rate = 1.0 / rate;
    // A speed that is not finite (a rule that broke a velocity) ends the layer's step here; the
    // engine's checks of the state name it.
    budget = std::isfinite(rate) ? f0 + rate * (dt - t0) : 0.0;
    events = 0;
  };
  std::int64_t initiator = -1;  // an extra event's particle, the next candidate (at t0)
  thread_local std::vector<double> saved_tally;
  saved_tally.resize(tally_count_);
  // Close the batch, whose newest event is at `last`: the rule's pass, every collided particle's new
  // speed, the extra events of those that rose. True if the batch was cut (an extra event before
  // `last`: `initiator` is set, and the time counter starts again at its time).
  const auto flush = [&](double last) -> bool {
    s.load_velocities(m, vx, vy, vz);
    const Rng kernel_before = *batch.rng;
    const std::uint64_t collided = batch.collided, exceeded = batch.exceeded;
    const double max_rate = batch.max_rate, energy = batch.energy_change, missed = batch.missed;
    if (batch.tally) std::copy(batch.tally, batch.tally + tally_count_, saved_tally.begin());
    batch.count = m;
    rule.collide_batch(batch);
    double first_extra = INFINITY;
    std::uint32_t extra = 0, kept = m;
    bool rose = false;
    for (std::uint32_t q = 0; q < m; ++q) {
      if (s.t[q] > first_extra) {
        kept = q;
        break;
      }
      if (!s.accepted[q]) continue;
      const Vec3 after[2] = {s.v1[q], s.v2[q]};
      for (int e = 0; e < 2; ++e) {
        const std::uint32_t a = e == 0 ? s.la[q] : s.lb[q];
        const double lift = layer.rise(a, layer.peculiar_square(after[e].x, after[e].y, after[e].z));
        if (lift > 0) {
          rose = true;
          const double t = s.t[q] - std::log1p(-select.uniform()) / (per_bound * lift);
          if (t < first_extra) first_extra = t, extra = a;
        }
      }
    }
    if (kept < m) {
      // Undo the rule's pass and run it again on the pairs before the cut: the same draws, so the
      // same outcomes for them, and results and tallies that hold those pairs only.
      *batch.rng = kernel_before;
      batch.collided = collided, batch.exceeded = exceeded, batch.max_rate = max_rate;
      batch.energy_change = energy, batch.missed = missed;
      if (batch.tally) std::copy(saved_tally.begin(), saved_tally.end(), batch.tally);
      s.load_velocities(kept, vx, vy, vz);
      batch.count = kept;
      rule.collide_batch(batch);
    }
    s.store_accepted(kept, vx, vy, vz);
    candidates += kept;
    s.forget(m);
    s.dirty = false;
    m = 0;
    if (first_extra <= last) {
      // The envelope events after E are dropped; the counter goes on from E with the new envelope.
      const double due = f0 + rate * (first_extra - t0);
      anchor(first_extra, due - std::floor(due));
      initiator = extra;
      return true;
    }
    if (rose) anchor(last, f0 + rate * (last - t0) - static_cast<double>(events));
    return false;
  };
  const auto draw_time = [&] { return t0 + (static_cast<double>(events) - f0) * inverse_rate; };
  for (;;) {
    std::uint32_t a;
    double t, thin;
    bool from_bulk = false;
    if (initiator >= 0) {
      a = static_cast<std::uint32_t>(initiator);
      initiator = -1;
      t = t0;
      thin = select.uniform();
    } else if (static_cast<double>(events + 1) <= budget) {
      ++events;
      if ((events & 0xFFFF) == 0) poll_interrupt(interrupt_);
      t = draw_time();
      a = layer.pick(select.uniform(), thin, from_bulk);
    } else {
      if (m > 0 && flush(dt)) continue;
      break;
    }
    // a thinned first (its speed is current once no open pair holds it), then its partner and the
    // acceptance number for a candidate only.
    if (m > 0 && s.holds(a) && flush(t)) continue;  // cut before t: this draw goes
    if (!layer.candidate(a, thin, from_bulk)) continue;
    std::uint32_t b = select.below(count - 1);
    b += (b >= a);
    const double u = select.uniform32();
    if (m > 0 && s.holds(b) && flush(t)) continue;
    s.add(a);
    s.add(b);
    const std::uint32_t i = members[a], j = members[b];
    s.i[m] = i;
    s.j[m] = j;
    s.la[m] = a;
    s.lb[m] = b;
    s.u[m] = u;
    s.t[m] = t;
    s.w[m] = layer.speed(a) + layer.speed(b);
    prefetch(vx + i), prefetch(vy + i), prefetch(vz + i);
    prefetch(vx + j), prefetch(vy + j), prefetch(vz + j);
    if (++m == kPairBatch) flush(t);
  }
  counts_[3 * c] = candidates;
  return f0 + rate * (dt - t0) - static_cast<double>(events);
}

// A layer-step draws two numbers an envelope event and two more a candidate: a few Philox blocks at
// least, which sixteen side by side (AVX2, AVX-512) cost less than one after the other; without a
// vector version, from a local copy of the stream.
double CollisionStage::collide_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                        WeightedLayer& layer, double credit, double dt, Rng& stream,
                                        PairBatch& batch) {
  double left = 0;
  draw_from(stream, philox_sixteen_vectorized(),
            [&](auto& draws) { left = weighted_step(rule, particles, c, layer, credit, dt, draws, batch); });
  return left;
}

void CollisionStage::collide_group(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c, double sigma,
                                   double dt, const StreamFactory& streams) {
  poll_interrupt(interrupt_);
  // Two streams per group: the scheme's (which pairs, their acceptance numbers) and the rule's
  // (impact directions, its own draws), so that neither depends on how the candidates are batched.
  Rng select = streams.rng(StreamPurpose::collisions, 0, c);
  Rng kernel = streams.rng(StreamPurpose::collisions, 2, c);
  const Group& group = groups_[c];
  const double majorant = ratio_[c] * speed_[c];
  double* const tally = tally_count_ ? cell_tallies_.data() + c * tally_count_ : nullptr;
  if (tally) std::fill(tally, tally + tally_count_, 0.0);
  std::uint64_t* const counts = counts_.data() + 3 * c;
  counts[0] = counts[1] = counts[2] = 0;
  max_rate_[c] = 0;
  energy_[c] = 0;
  missed_[c] = 0;
  if (group.count < 2 || !(majorant > 0)) {
    remainder_[c] = 0;
    return;
  }
  PairBatch batch;
  batch.cell = static_cast<std::uint32_t>(c);
  batch.sigma = sigma;
  batch.particles = &particles;
  batch.rng = &kernel;
  batch.tally = tally;  // summed over the slices
  // Weighted pairs in every slab layer; in a homogeneous system of one group (members in storage
  // order) when asked for, or by default once its uniform majorant would accept fewer than
  // kUniformAcceptanceFloor of a Maxwellian's candidates (a pass over the particles per step then
  // buys back the candidates: USF IHS alpha = 0.5, a* = 4 accepted 20 % uniform, 68 % weighted).
  const bool in_storage_order = group.members && group.members == identity_.data();
  if (weighted_ && group.members &&
      (!in_storage_order || selection_ == PairSelection::weighted ||
       ratio_[c] * kUniformAcceptanceFloor > kMaxwellMeanRelativeSpeed)) {
    thread_local WeightedLayer layer;
    // About the layer's mean velocity at the last moment update (any u bounds |g|; one near the
    // mean keeps the speeds small), with the bulk bound kBulkSpeedBound times the rms speed.
    double u[3] = {0, 0, 0};
    if (cells_ && cells_[c].count >= 2) {
      std::copy(cells_[c].mean_velocity, cells_[c].mean_velocity + 3, u);
    } else {
      for (std::uint32_t a = 0; a < group.count; ++a) {
        const std::uint32_t i = group.members[a];
        u[0] += particles.vx.data[i], u[1] += particles.vy.data[i], u[2] += particles.vz.data[i];
      }
      for (double& x : u) x /= group.count;
    }
    // A homogeneous system of one group: storage order, and B_0 from the reference temperature
    // (kBulkSpeedBound times the rms speed sqrt(3 T_ref/m)), so one pass builds the envelope.
    if (in_storage_order ? !layer.build_contiguous(particles, group.count, u, kBulkSpeedBound * std::sqrt(3.0) * speed_[c])
                   : !layer.build(particles, group.members, group.count, u, kBulkSpeedBound)) {
      remainder_[c] = 0;
      return;
    }
    // This step's velocities are not followed by the kept bounds (a homogeneous system of one
    // group: no other group runs meanwhile); they are rebuilt at the next uniform step.
    kept_.invalidate();
    // The remainder is a fraction of an envelope event here and of a uniform candidate otherwise:
    // in [0, 1) either way, so a layer that changes its draw (run.pair_selection at a resume)
    // carries less than one.
    remainder_[c] = collide_weighted(rule, particles, c, layer, remainder_[c], dt, select, batch);
    counts[1] = batch.collided;
    counts[2] = batch.exceeded;
    energy_[c] = batch.energy_change;
    missed_[c] = batch.missed;
    return;
  }
  // Candidates of the step (000 Eqs. 4.13, 4.23): P_c sigma^2 Omega_B W dt / V_c, W the rule's
  // bound of its kernel for |g| <= w, Omega_B = pi (hard-sphere form) or 4 pi (general).
  const double w = majorant;
  const double bound = rule.rate_bound(w);
  const double per_time = pair_count(scheme_, group.count) * sigma * sigma * solid_angle_ * bound / group.volume;
  batch.speed_bound = w;
  batch.rate_bound = bound;
  // Slices of dt for a large group (4 x the estimate: a general kernel's solid angle is 4 pi),
  // each with a check for an interrupt; one slice, the whole dt, otherwise.
  const double upper = 4.0 * estimate_[c];
  const double slices = upper > kCandidatesPerSlice ? std::ceil(upper / kCandidatesPerSlice) : 1.0;
  double remainder = remainder_[c];
  for (double k = 0; k < slices; ++k) {
    if (k > 0) poll_interrupt(interrupt_);
    const double expected = per_time * (dt / slices) + remainder;
    const auto candidates = static_cast<std::uint64_t>(expected);
    remainder = expected - static_cast<double>(candidates);
    collide_candidates(rule, particles, c, candidates, select, batch, kept_this_step_);
    counts[0] += candidates;
  }
  counts[1] = batch.collided;
  counts[2] = batch.exceeded;
  remainder_[c] = remainder;
  if (batch.max_rate > majorant) ratio_[c] = kMajorantHeadroom * batch.max_rate / speed_[c];
  max_rate_[c] = batch.max_rate;
  energy_[c] = batch.energy_change;
  missed_[c] = batch.missed;
}

void CollisionStage::scatter_and_collide(const CollisionRule& rule, const ParticleSpan& particles,
                                         const PendingMembers& pending, double sigma, double dt,
                                         const StreamFactory& streams) {
  CellGrid& grid = *pending.grid;
  const std::size_t layers = grid.count(), blocks = CellGrid::sort_blocks(particles.count);
  if (scattered_size_ < blocks) {
    scattered_ = std::make_unique<std::atomic<std::uint64_t>[]>(blocks);
    for (std::size_t b = 0; b < blocks; ++b) scattered_[b].store(0, std::memory_order_relaxed);
    scattered_size_ = blocks;
  }
  const std::uint64_t stamp = ++stamp_;
  // The layers by their last block (a counting sort; key 0: empty, key b + 1: last block b).
  const auto key = [&](std::size_t c) {
    const std::size_t b = grid.last_block(c);
    return b == CellGrid::kNoBlock ? std::size_t{0} : b + 1;
  };
  key_start_.assign(blocks + 2, 0);
  for (std::size_t c = 0; c < layers; ++c) ++key_start_[key(c) + 1];
  for (std::size_t k = 1; k < key_start_.size(); ++k) key_start_[k] += key_start_[k - 1];
  by_key_.resize(layers);
  key_next_.assign(key_start_.begin(), key_start_.end() - 1);
  for (std::size_t c = 0; c < layers; ++c) by_key_[key_next_[key(c)]++] = static_cast<std::uint32_t>(c);
  // The pieces: the first kScatterLead blocks and the empty layers; then, for every block b, the
  // scatter of block b + kScatterLead and the layers whose last block is b. The scatters run
  // ahead of the layers that need them, so that a thread seldom waits for one.
  pieces_.clear();
  const auto layers_of_key = [&](std::size_t k) {
    for (std::uint32_t j = key_start_[k]; j < key_start_[k + 1]; ++j)
      pieces_.push_back(static_cast<std::uint32_t>(blocks) + by_key_[j]);
  };
  for (std::size_t b = 0; b < std::min(kScatterLead, blocks); ++b) pieces_.push_back(static_cast<std::uint32_t>(b));
  layers_of_key(0);
  for (std::size_t b = 0; b < blocks; ++b) {
    if (b + kScatterLead < blocks) pieces_.push_back(static_cast<std::uint32_t>(b + kScatterLead));
    layers_of_key(b + 1);
  }
  for_pieces(pool_, pieces_.size(), [&](std::size_t k) {
    const std::uint32_t piece = pieces_[k];
    if (piece < blocks) {
      grid.scatter_block(pending.cell, piece, particles.count);
      scattered_[piece].store(stamp, std::memory_order_release);
      return;
    }
    const std::size_t c = piece - blocks, last = grid.last_block(c);
    // Every block up to the last is an earlier piece, and the pool starts pieces in order, so
    // each of them has started on some thread (or is done) and the wait ends.
    if (last != CellGrid::kNoBlock)
      for (std::size_t b = 0; b <= last; ++b)
        while (scattered_[b].load(std::memory_order_acquire) != stamp) cpu_relax();
    collide_group(rule, particles, c, sigma, dt, streams);
  });
}

CollisionStage::Totals CollisionStage::run(const CollisionRule& rule, const ParticleSpan& particles, const CellGrid& grid,
                                           const CellMoments* cells, double temperature, double mass, double sigma,
                                           double dt, const StreamFactory& streams, bool reversed,
                                           const PendingMembers* pending) {
  const std::size_t n = grid.is_slab() ? grid.count() : subpopulation_count(particles.count, subpopulation_);
  if (ratio_.size() != n) reset(n);
  if (particles.vx.stride != 1 || particles.vy.stride != 1 || particles.vz.stride != 1)
    throw std::logic_error("CollisionStage: velocities are expected in arrays of stride 1");
  cells_ = cells;
  solid_angle_ = rule.kernel_form() == KernelForm::general ? 4.0 * M_PI : M_PI;
  weighted_ = selection_ != PairSelection::uniform && rule.kernel_form() == KernelForm::hard_sphere;
  make_groups(grid, particles.count, streams);
  // Every group's majorant and hard-sphere candidate estimate first, so that a step whose work is
  // not finite or is absurd is refused before any pair is tested (the rule would cast the count
  // to an integer and loop on it).
  double total = 0;
  for (std::size_t c = 0; c < n; ++c) {
    speed_[c] = std::sqrt(reference_temperature(cells, c, temperature) / mass);
    // pi times the rule's bound of its rate (the hard-sphere count; a general kernel draws up to 4x)
    estimate_[c] = pair_count(scheme_, groups_[c].count) * sigma * sigma * M_PI *
                   rule.rate_bound(ratio_[c] * speed_[c]) * dt / groups_[c].volume;
    total += estimate_[c];
  }
  const double per_particle = particles.count ? total / static_cast<double>(particles.count) : 0.0;
  if (!(total <= kMaxCandidatesPerStep) || !(per_particle <= kMaxCandidatesPerParticle))
    throw Overload(fmt("the collision stage would test about %.3g candidate pairs (%.3g per particle; at most %.0e per "
                       "step and %.0f per particle are allowed)",
                       total, per_particle, kMaxCandidatesPerStep, kMaxCandidatesPerParticle),
                   total);

  // The kept speed bounds of a system that only collides (set_collisions_only), rebuilt when not
  // current (KeptSpeedBounds::current).
  kept_this_step_ = collisions_only_ && !grid.is_slab() && rule.kernel_form() == KernelForm::hard_sphere &&
                    particles.count >= 2 && speed_[0] > 0 && std::isfinite(speed_[0]);
  if (kept_this_step_ && !kept_.current(particles, speed_[0])) kept_.build(particles, speed_[0]);

  // The groups are independent (own stream, majorant, remainder, results): any thread, any order.
  if (pending && !reversed && grid.is_slab()) {
    scatter_and_collide(rule, particles, *pending, sigma, dt, streams);
  } else {
    if (pending) pending->grid->scatter_blocks(pending->cell, particles.count, pool_);
    for_pieces(pool_, n,
               [&](std::size_t k) { collide_group(rule, particles, reversed ? n - 1 - k : k, sigma, dt, streams); });
  }
  // The totals in group order.
  Totals sum;
  for (std::size_t c = 0; c < n; ++c) {
    sum.candidates += counts_[3 * c];
    sum.accepted += counts_[3 * c + 1];
    sum.majorant_exceeded += counts_[3 * c + 2];
    sum.max_rate = std::max(sum.max_rate, max_rate_[c]);
    sum.finite_remainders = sum.finite_remainders && std::isfinite(remainder_[c]);
    sum.energy_change += energy_[c];
    sum.missed += missed_[c];
    missed_so_far_[c] += missed_[c];
    collided_so_far_[c] += static_cast<double>(counts_[3 * c + 1]);
  }
  if (tally_count_) {
    std::fill(step_tallies_.begin(), step_tallies_.end(), 0.0);
    for (std::size_t c = 0; c < n; ++c)
      for (std::size_t k = 0; k < tally_count_; ++k) step_tallies_[k] += cell_tallies_[c * tally_count_ + k];
    sum.tallies = step_tallies_.data();
  }
  return sum;
}

}  // namespace gdsmc::host
