// The collision stage of a mixture (CollisionStage::set_species): in every group, candidates per
// pair of species (a, b), each pair class with its own majorant w_ab and remainder, as SPARTA keeps
// vremax[cell][igroup][jgroup]. Class (a, b) of a group with N_a, N_b particles in volume V_c tests
// P_ab sigma_ab^2 Omega_B W(w_ab) dt / V_c candidates (000 Eq. 4.13 per class), P_aa the pair count
// of N_a (PairCount), P_ab = N_a N_b, sigma_ab = (sigma_a + sigma_b) / 2, and accepts a pair with
// the rule's rate over W(w_ab), as one species does. The classes of a group draw from the group's
// two streams in class order: the same bits whatever the thread count or cell order.
#include <algorithm>
#include <cmath>

#include "engine/candidate_batch.hpp"
#include "engine/collision_stage.hpp"
#include "engine/interrupt.hpp"
#include "engine/majorant.hpp"
#include "engine/weighted_layer.hpp"

namespace gdsmc::host {

using namespace candidates;

void CollisionStage::set_species(const double* mass, const double* diameter, std::size_t count) {
  species_ = mass ? count : 1;
  for (std::size_t s = 0; s < species_ && mass; ++s) {
    species_mass_[s] = mass[s];
    species_diameter_[s] = diameter[s];
  }
}

double CollisionStage::class_scale(std::size_t c, std::size_t a, std::size_t b) const {
  // sqrt(T_a/m_a + T_b/m_b): the thermal scale of the relative speed of an (a, b) pair, with T_s the
  // species' temperature in the cell at the last moment update (the cell's, or the mean, below 2).
  const std::size_t cell = species_cells_ && slab_ ? c : 0;
  const double fallback = reference_temperature(cells_, c, temperature_);
  double t[2];
  for (int k = 0; k < 2; ++k) {
    const std::size_t s = k == 0 ? a : b;
    const CellGrid::SpeciesCellMoments* m = species_cells_ ? species_cells_ + cell * species_ + s : nullptr;
    t[k] = m && m->count >= 2 && m->temperature > 0 ? m->temperature : fallback;
  }
  return std::sqrt(t[0] / species_mass_[a] + t[1] / species_mass_[b]);
}

double CollisionStage::species_estimate(const CollisionRule& rule, std::size_t c, double dt) const {
  double sigma = 0, w = 0;
  for (std::size_t a = 0, k = 0; a < species_; ++a)
    for (std::size_t b = a; b < species_; ++b, ++k) {
      sigma = std::max(sigma, 0.5 * (species_diameter_[a] + species_diameter_[b]));
      w = std::max(w, class_ratio_[c * class_count() + k] * class_scale(c, a, b));
    }
  return pair_count(scheme_, groups_[c].count) * sigma * sigma * M_PI * rule.rate_bound(w) * dt / groups_[c].volume;
}

void CollisionStage::set_species_majorants(const CellGrid::SpeciesCellMoments* moments, const CellMoments* cells,
                                           double temperature) {
  cells_ = cells;
  temperature_ = temperature;
  species_cells_ = moments;
  slab_ = true;
  // ratio_ab = max(initial, headroom (c_a + c_b) / scale): no (a, b) pair of the cell is further
  // apart than the two species' largest peculiar speeds c_a + c_b.
  const std::size_t classes = class_count();
  for (std::size_t c = 0; c < ratio_.size(); ++c)
    for (std::size_t a = 0, k = 0; a < species_; ++a)
      for (std::size_t b = a; b < species_; ++b, ++k) {
        const double reach = moments[c * species_ + a].speed_max + moments[c * species_ + b].speed_max;
        class_ratio_[c * classes + k] =
            std::max(kInitialMajorantRatio / std::sqrt(2.0), kMajorantHeadroom * reach / class_scale(c, a, b));
      }
}

void CollisionStage::collide_group_species(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                           double dt, Rng& select, PairBatch& batch) {
  const Group& group = groups_[c];
  const GroupParticles particle(group.members, group.first, group.stride, particles.count);
  // The group's particles by species, each species in the group's order (a counting sort).
  thread_local std::vector<std::uint32_t> sorted;
  sorted.resize(group.count);
  std::uint32_t start[kMaxSpecies + 1] = {}, next[kMaxSpecies];
  for (std::uint32_t a = 0; a < group.count; ++a) ++start[particles.species[particle(a)] + 1];
  for (std::size_t s = 0; s < species_; ++s) start[s + 1] += start[s];
  std::copy(start, start + species_, next);
  for (std::uint32_t a = 0; a < group.count; ++a) {
    const std::uint32_t i = particle(a);
    sorted[next[particles.species[i]]++] = i;
  }
  thread_local BatchScratch s;
  s.open(batch);
  batch.speed_bounds = nullptr;
  std::uint64_t tested = 0;
  const bool weighted = weighted_ && group.members && (slab_ || selection_ == PairSelection::weighted);
  for (std::size_t a = 0, k = 0; a < species_; ++a)
    for (std::size_t b = a; b < species_; ++b, ++k) {
      if (weighted && collide_class_weighted(rule, particles, c, a, b, k, sorted.data(), start, dt, select, batch)) {
        batch.speed_bounds = nullptr;
        s.open(batch);  // the uniform scratch again (weighted_step opened its own)
        continue;
      }
      tested += collide_class_uniform(rule, particles, c, a, b, k, sorted.data(), start, dt, select, s, batch);
    }
  counts_[3 * c] += tested;
}

// Class (a, b) of group c (the k-th) with uniform candidates against its majorant w_ab: returns the
// candidates tested.
std::uint64_t CollisionStage::collide_class_uniform(const CollisionRule& rule, const ParticleSpan& particles,
                                                    std::size_t c, std::size_t a, std::size_t b, std::size_t k,
                                                    const std::uint32_t* sorted, const std::uint32_t* start, double dt,
                                                    Rng& select, BatchScratch& s, PairBatch& batch) {
  const Group& group = groups_[c];
  const std::size_t classes = class_count();
  double* const vx = particles.vx.data;
  double* const vy = particles.vy.data;
  double* const vz = particles.vz.data;
  std::uint64_t tested = 0;
  const std::uint32_t na = start[a + 1] - start[a], nb = start[b + 1] - start[b];
  double& remainder = class_remainder_[c * classes + k];
  double& ratio = class_ratio_[c * classes + k];
  const double pairs = a == b ? pair_count(scheme_, na) : static_cast<double>(na) * nb;
  const double scale = class_scale(c, a, b), w = ratio * scale;
  if (!(pairs > 0) || !(w > 0)) {
    remainder = 0;
    return 0;
  }
  const double sigma = 0.5 * (species_diameter_[a] + species_diameter_[b]);  // sigma_ab
  const double bound = rule.rate_bound(w);
  const double per_time = pairs * sigma * sigma * solid_angle_ * bound / group.volume;
  batch.sigma = sigma;
  batch.speed_bound = w;
  batch.rate_bound = bound;
  batch.max_rate = 0;
  const double slices = estimate_[c] * 4.0 > kCandidatesPerSlice ? std::ceil(4.0 * estimate_[c] / kCandidatesPerSlice) : 1.0;
  std::uint32_t m = 0;
  const auto flush = [&] {
    s.load_velocities(m, vx, vy, vz);
    batch.count = m;
    rule.collide_batch(batch);
    s.store_accepted(m, vx, vy, vz);
    s.close(m);
    m = 0;
  };
  for (double slice = 0; slice < slices; ++slice) {
    if (slice > 0) poll_interrupt(interrupt_);
    const double expected = per_time * (dt / slices) + remainder;
    const auto candidates = static_cast<std::uint64_t>(expected);
    remainder = expected - static_cast<double>(candidates);
    for (std::uint64_t q = 0; q < candidates; ++q) {
      std::uint32_t x = select.below(na), y;
      if (a == b) {
        y = select.below(na - 1);
        y += (y >= x);
      } else {
        y = select.below(nb);
      }
      const double u = select.uniform32();
      x += start[a];  // local indices: places in `sorted`, distinct across the classes' lists
      y += start[b];
      if (m > 0 && (s.holds(x) || s.holds(y))) flush();
      s.put(m, x, y, sorted[x], sorted[y], u, vx, vy, vz);
      if (++m == kPairBatch) flush();
    }
    if (m > 0) flush();
    tested += candidates;
  }
  if (batch.max_rate > w) ratio = kMajorantHeadroom * batch.max_rate / scale;
  max_rate_[c] = std::max(max_rate_[c], batch.max_rate);
  return tested;
}

// Class (a, b) over the step with weighted pairs (collide_weighted, one species' scheme per class):
// like species, K = sigma_aa^2 pi scale (2 P(N_a) / N_a) / V_c with the partner from the same
// species; unlike species, a member of a initiates at K' N_b times its bound and one of b at K' N_a,
// K' = sigma_ab^2 pi scale / V_c, the partner drawn from the other species, so that the pair (i, j)
// is a candidate at the rate K' (c_i + c_j) and collides at sigma_ab^2 pi scale |g| / V_c, the
// uniform class's rate. Both envelopes are about the cell's barycentric velocity.
bool CollisionStage::collide_class_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                            std::size_t a, std::size_t b, std::size_t k, const std::uint32_t* sorted,
                                            const std::uint32_t* start, double dt, Rng& select, PairBatch& batch) {
  const Group& group = groups_[c];
  double& credit = class_remainder_[c * class_count() + k];
  const std::uint32_t na = start[a + 1] - start[a], nb = start[b + 1] - start[b];
  if (a == b ? na < 2 : (na == 0 || nb == 0)) {
    credit = 0;
    return true;
  }
  double u[3];
  envelope_velocity(particles, c, sorted, group.count, u);
  thread_local WeightedLayer layers[2];
  WeightedSides sides;
  sides.n = a == b ? 1 : 2;
  const std::size_t species[2] = {a, b};
  for (int k = 0; k < sides.n; ++k) {
    const std::size_t s = species[k];
    sides.layer[k] = &layers[k];
    sides.members[k] = sorted + start[s];
    sides.count[k] = start[s + 1] - start[s];
    sides.offset[k] = start[s];
    // A species whose members all sit at u (no peculiar speed: measure zero but for a cold start)
    // has no envelope: the class then draws uniform candidates this step.
    if (!layers[k].build(particles, sides.members[k], sides.count[k], u, kBulkSpeedBound)) return false;
  }
  const double sigma = 0.5 * (species_diameter_[a] + species_diameter_[b]);  // sigma_ab
  const double k_prime = sigma * sigma * M_PI * rule.rate_bound(1.0) / group.volume;
  if (a == b) {
    sides.per_bound[0] = 2.0 * pair_count(scheme_, na) / na * k_prime;
  } else {
    sides.per_bound[0] = k_prime * nb;
    sides.per_bound[1] = k_prime * na;
  }
  batch.sigma = sigma;
  credit = collide_weighted(rule, particles, c, sides, credit, dt, select, batch);
  return true;
}

}  // namespace gdsmc::host
