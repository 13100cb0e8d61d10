#include "engine/collision_stage.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/bulk_rng.hpp"
#include "engine/candidate_batch.hpp"
#include "engine/interrupt.hpp"
#include "engine/majorant.hpp"
#include "engine/weighted_layer.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

using namespace candidates;

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
  candidates_since_.assign(cells, 0.0);
  groups_.assign(cells, Group{});
  cell_tallies_.assign(cells * tally_count_, 0.0);
  class_ratio_.assign(species_ > 1 ? cells * class_count() : 0, kInitialMajorantRatio / std::sqrt(2.0));
  class_remainder_.assign(class_ratio_.size(), 0.0);
}

void CollisionStage::reset_majorants() {
  for (std::size_t c = 0; c < ratio_.size(); ++c) {
    if (missed_so_far_[c] <= kMissedCollisionsTolerance * collided_so_far_[c]) {
      ratio_[c] = std::max(kInitialMajorantRatio, kMajorantDecay * ratio_[c]);
      for (std::size_t k = 0, classes = class_count(); species_ > 1 && k < classes; ++k) {
        double& r = class_ratio_[c * classes + k];
        r = std::max(kInitialMajorantRatio / std::sqrt(2.0), kMajorantDecay * r);
      }
    }
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
// The kept speed bounds of the particles of the first m pairs that collided, after the collision.
void follow_accepted(const KeptSpeedBounds& kept, std::uint8_t* bound, const BatchScratch& s, std::uint32_t m) {
  for (std::uint32_t q = 0; q < m; ++q)
    if (s.accepted[q]) {
      bound[s.i[q]] = kept.level(s.v1[q].x, s.v1[q].y, s.v1[q].z);
      bound[s.j[q]] = kept.level(s.v2[q].x, s.v2[q].y, s.v2[q].z);
    }
}
}  // namespace

CollisionStage::CollisionStage(PairCount scheme) : scheme_(scheme) {}
CollisionStage::~CollisionStage() = default;

void CollisionStage::collide_candidates(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                        std::uint64_t candidates, Rng& stream, PairBatch& batch, bool kept) {
  const Group& group = groups_[c];
  const GroupParticles particle(group.members, group.first, group.stride, particles.count);
  const std::uint32_t count = group.count;
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
    if (bound) follow_accepted(kept_, bound, s, m);
    s.close(m);
    m = 0;
  };
  // A candidate into the open batch (its velocities prefetched), the batch closed when full.
  const auto open = [&](std::uint32_t a, std::uint32_t b, std::uint32_t i, std::uint32_t j, double u) {
    s.put(m, a, b, i, j, u, vx, vy, vz);
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
  if (species_ > 1) {
    collide_group_species(rule, particles, c, dt, select, batch);
    counts[1] = batch.collided;
    counts[2] = batch.exceeded;
    energy_[c] = batch.energy_change;
    missed_[c] = batch.missed;
    return;
  }
  // Weighted pairs in every slab layer; in a homogeneous system of one group (members in storage
  // order) when asked for, or by default once its uniform majorant would accept fewer than
  // kUniformAcceptanceFloor of a Maxwellian's candidates (a pass over the particles per step then
  // buys back the candidates: USF IHS alpha = 0.5, a* = 4 accepted 20 % uniform, 68 % weighted).
  const bool in_storage_order = group.members && group.members == identity_.data();
  if (weighted_ && group.members &&
      (!in_storage_order || selection_ == PairSelection::weighted ||
       ratio_[c] * kUniformAcceptanceFloor > kMaxwellMeanRelativeSpeed)) {
    collide_group_weighted(rule, particles, c, dt, select, batch);
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
  slab_ = grid.is_slab();
  temperature_ = temperature;
  if (species_ > 1) species_cells_ = grid.species_cell_moments();
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
    if (species_ > 1) estimate_[c] = species_estimate(rule, c, dt);
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
  if (exchange_ && grid.is_slab()) share_layers(n);
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
    candidates_since_[c] += static_cast<double>(counts_[3 * c]);
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

// Each layer's step from its owner: candidates, accepted, exceeded, largest rate, energy change,
// missed collisions, remainder, majorant ratio, the rule's tallies, then a mixture's ratio and
// remainder of every pair class.
void CollisionStage::share_layers(std::size_t layers) {
  const std::size_t classes = species_ > 1 ? class_count() : 0, per = 8 + tally_count_ + 2 * classes;
  shared_.resize(per * layers);
  for (std::size_t c = 0; c < layers; ++c) {
    double* v = shared_.data() + per * c;
    for (int k = 0; k < 3; ++k) v[k] = static_cast<double>(counts_[3 * c + k]);  // below 2^53: exact
    v[3] = max_rate_[c], v[4] = energy_[c], v[5] = missed_[c], v[6] = remainder_[c], v[7] = ratio_[c];
    std::copy(cell_tallies_.data() + c * tally_count_, cell_tallies_.data() + (c + 1) * tally_count_, v + 8);
    double* w = v + 8 + tally_count_;
    for (std::size_t k = 0; k < classes; ++k)
      w[2 * k] = class_ratio_[c * classes + k], w[2 * k + 1] = class_remainder_[c * classes + k];
  }
  exchange_->share(shared_.data(), per);
  for (std::size_t c = 0; c < layers; ++c) {
    const double* v = shared_.data() + per * c;
    for (int k = 0; k < 3; ++k) counts_[3 * c + k] = static_cast<std::uint64_t>(v[k]);
    max_rate_[c] = v[3], energy_[c] = v[4], missed_[c] = v[5], remainder_[c] = v[6], ratio_[c] = v[7];
    std::copy(v + 8, v + 8 + tally_count_, cell_tallies_.data() + c * tally_count_);
    const double* w = v + 8 + tally_count_;
    for (std::size_t k = 0; k < classes; ++k)
      class_ratio_[c * classes + k] = w[2 * k], class_remainder_[c * classes + k] = w[2 * k + 1];
  }
}

}  // namespace gdsmc::host
