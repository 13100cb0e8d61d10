#include "engine/collision_stage.hpp"

#include <algorithm>
#include <cmath>

#include "engine/majorant.hpp"

namespace gdsmc::host {

void CollisionStage::reset(std::size_t cells) {
  ratio_.assign(cells, kInitialMajorantRatio);
  remainder_.assign(cells, 0.0);
  energy_.assign(cells, 0.0);
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
  Totals sum;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t c = reversed ? n - 1 - k : k;
    Rng rng = streams.rng(StreamPurpose::collisions, 0, c);
    CellCollision cell;
    cell.particles = particles;
    cell.members = grid.members(c);
    cell.count = grid.members_count(c);
    cell.pairs = pair_count(scheme_, cell.count);
    cell.index = static_cast<std::uint32_t>(c);
    cell.volume = grid.cell_volume();
    cell.sigma = sigma;
    cell.dt = dt;
    const double t_ref = cells ? std::max(cells[c].temperature, temperature) : temperature;
    const double thermal_speed = std::sqrt(t_ref / mass);
    cell.majorant = ratio_[c] * thermal_speed;
    cell.remainder = remainder_[c];
    cell.rng = &rng;
    if (tally_count_) {
      cell.tally = cell_tallies_.data() + c * tally_count_;
      std::fill(cell.tally, cell.tally + tally_count_, 0.0);
    }
    rule.collide_cell(cell);
    remainder_[c] = cell.remainder;
    if (cell.max_rate > cell.majorant) ratio_[c] = kMajorantHeadroom * cell.max_rate / thermal_speed;
    sum.candidates += cell.candidates;
    sum.accepted += cell.accepted;
    sum.majorant_exceeded += cell.majorant_exceeded;
    sum.max_rate = std::max(sum.max_rate, cell.max_rate);
    sum.finite_remainders = sum.finite_remainders && std::isfinite(cell.remainder);
    energy_[c] = cell.energy_change;
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
