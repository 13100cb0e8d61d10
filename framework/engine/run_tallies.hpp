// What a run adds up besides its particles, each with its checkpoint entries and its /run
// attributes: the energy ledger (what every stage put into the gas), the walls' tallies, and the
// running totals of the collision rule's tallies. StepContext points plugins at all three.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/state.hpp>

namespace gdsmc::host {

// The kinetic energy each stage has added since the start (m = 1): collisions, every forcing by
// its instance name, then each y boundary of a slab (y_min, y_max).
class EnergyLedger {
 public:
  void open(const std::vector<std::string>& forcings, bool slab);
  void set_collisions(double total) { entries_[0].energy = total; }
  void add_forcing(std::uint32_t k, double energy) { entries_[1 + k].energy += energy; }
  void add_wall(int side, double energy) { entries_[entries_.size() - 2 + static_cast<std::size_t>(side)].energy += energy; }
  const EnergyLedgerEntry* data() const { return entries_.data(); }
  std::size_t size() const { return entries_.size(); }
  // The run's balance per particle, `per` = 1/(N T0): "E - E0 = x = collisions a, force b, ...
  // (residual r)"; the residual is round-off for plugins that tell the truth.
  std::string balance_text(double change, double per) const;
  void write(std::map<std::string, double>& run) const;  // energy_added.<stage>
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  std::vector<std::string> names_;  // entries_[k].stage points into names_[k]
  std::vector<EnergyLedgerEntry> entries_;
};

// What each y boundary (0: y_min, 1: y_max) has exchanged with the gas since the start.
class WallTallies {
 public:
  void add(int side, const BoundaryTally& step);
  const BoundaryTally* data() const { return sides_.data(); }
  // A mixture of `count` species: its tallies per side and species, [side * count + s].
  void open_species(std::size_t count) { species_.assign(2 * count, BoundaryTally{}); }
  // One step's, from [side * stride + s] of `step`.
  void add_species(const BoundaryTally* step, std::size_t stride);
  const BoundaryTally* species_data() const { return species_.empty() ? nullptr : species_.data(); }
  void write(std::map<std::string, double>& run) const;  // boundary.<side>.{hits, momentum_x, ..., energy}
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  std::array<BoundaryTally, 2> sides_{};
  std::vector<BoundaryTally> species_;  // a mixture's: [side * species + s]
};

// The running totals of the collision rule's tallies (CollisionRule::tallies), by name.
class CollisionTallies {
 public:
  void open(std::vector<std::string> names);
  void add(const double* step);  // one collision stage's sums, in the names' order
  std::size_t size() const { return totals_.size(); }
  const CollisionTally* data() const { return totals_.empty() ? nullptr : totals_.data(); }
  void save(StateWriter& out) const;
  void load(StateReader& in);

 private:
  std::vector<std::string> names_;  // totals_[k].name points into names_[k]
  std::vector<CollisionTally> totals_;
};

}  // namespace gdsmc::host
