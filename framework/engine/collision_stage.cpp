#include "engine/collision_stage.hpp"

#include <algorithm>
#include <cmath>

#include "engine/interrupt.hpp"
#include "engine/majorant.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

void CollisionStage::reset(std::size_t cells) {
  ratio_.assign(cells, kInitialMajorantRatio);
  remainder_.assign(cells, 0.0);
  energy_.assign(cells, 0.0);
  speed_.assign(cells, 0.0);
  estimate_.assign(cells, 0.0);
  cell_tallies_.assign(cells * tally_count_, 0.0);
}

void CollisionStage::set_tally_count(std::size_t count) {
  tally_count_ = count;
  cell_tallies_.assign(ratio_.size() * count, 0.0);
  step_tallies_.assign(count, 0.0);
}

CollisionStage::Totals CollisionStage::run(const CollisionRule& rule, const ParticleSpan& particles, const CellGrid& grid,
                                           const CellMoments* cells, double temperature, double mass, double sigma,
                                           double dt, const StreamFactory& streams, bool reversed) {
  const std::size_t n = grid.count();
  if (ratio_.size() != n) reset(n);
  // Every cell's majorant and hard-sphere candidate estimate first, so that a step whose work is
  // not finite or is absurd is refused before any pair is tested (the rule would cast the count
  // to an integer and loop on it).
  double total = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const double t_ref = cells ? std::max(cells[c].temperature, temperature) : temperature;
    speed_[c] = std::sqrt(t_ref / mass);
    // pi times the rule's bound of its rate (the hard-sphere count; a general kernel draws up to 4x)
    estimate_[c] = pair_count(scheme_, grid.members_count(c)) * sigma * sigma * M_PI * rule.rate_bound(ratio_[c] * speed_[c]) *
                   dt / grid.cell_volume();
    total += estimate_[c];
  }
  const double per_particle = particles.count ? total / static_cast<double>(particles.count) : 0.0;
  if (!(total <= kMaxCandidatesPerStep) || !(per_particle <= kMaxCandidatesPerParticle))
    throw Overload(fmt("the collision stage would test about %.3g candidate pairs (%.3g per particle; at most %.0e per "
                       "step and %.0f per particle are allowed)",
                       total, per_particle, kMaxCandidatesPerStep, kMaxCandidatesPerParticle),
                   total);

  Totals sum;
  for (std::size_t k = 0; k < n; ++k) {
    if (k % 64 == 0) poll_interrupt(interrupt_);
    const std::size_t c = reversed ? n - 1 - k : k;
    Rng rng = streams.rng(StreamPurpose::collisions, 0, c);
    const double majorant = ratio_[c] * speed_[c];
    // Slices of dt for a large cell (4 x the estimate: a general kernel's solid angle is 4 pi);
    // one slice, the whole dt, otherwise.
    const double upper = 4.0 * estimate_[c];
    const double slices = upper > kCandidatesPerSlice ? std::ceil(upper / kCandidatesPerSlice) : 1.0;
    CellCollision cell;
    cell.remainder = remainder_[c];
    double* const tally = tally_count_ ? cell_tallies_.data() + c * tally_count_ : nullptr;
    if (tally) std::fill(tally, tally + tally_count_, 0.0);
    double max_rate = 0, energy = 0;
    for (double s = 0; s < slices; ++s) {
      if (s > 0) poll_interrupt(interrupt_);
      const double remainder = cell.remainder;
      cell = CellCollision{};
      cell.particles = particles;
      cell.members = grid.members(c);
      cell.count = grid.members_count(c);
      cell.pairs = pair_count(scheme_, cell.count);
      cell.index = static_cast<std::uint32_t>(c);
      cell.volume = grid.cell_volume();
      cell.sigma = sigma;
      cell.dt = dt / slices;
      cell.majorant = majorant;
      cell.remainder = remainder;
      cell.rng = &rng;
      cell.tally = tally;  // summed over the slices
      rule.collide_cell(cell);
      sum.candidates += cell.candidates;
      sum.accepted += cell.accepted;
      sum.majorant_exceeded += cell.majorant_exceeded;
      max_rate = std::max(max_rate, cell.max_rate);
      energy += cell.energy_change;
    }
    remainder_[c] = cell.remainder;
    if (max_rate > majorant) ratio_[c] = kMajorantHeadroom * max_rate / speed_[c];
    sum.max_rate = std::max(sum.max_rate, max_rate);
    sum.finite_remainders = sum.finite_remainders && std::isfinite(cell.remainder);
    energy_[c] = energy;
  }
  for (std::size_t c = 0; c < n; ++c) sum.energy_change += energy_[c];
  if (tally_count_) {
    std::fill(step_tallies_.begin(), step_tallies_.end(), 0.0);
    for (std::size_t c = 0; c < n; ++c)
      for (std::size_t k = 0; k < tally_count_; ++k) step_tallies_[k] += cell_tallies_[c * tally_count_ + k];
    sum.tallies = step_tallies_.data();
  }
  return sum;
}

}  // namespace gdsmc::host
