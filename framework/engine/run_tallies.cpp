#include "engine/run_tallies.hpp"

#include "util/text.hpp"

namespace gdsmc::host {

void EnergyLedger::open(const std::vector<std::string>& forcings, bool slab) {
  names_ = {"collisions"};
  names_.insert(names_.end(), forcings.begin(), forcings.end());
  if (slab) {
    names_.push_back("y_min");
    names_.push_back("y_max");
  }
  entries_.assign(names_.size(), EnergyLedgerEntry{});
  for (std::size_t k = 0; k < entries_.size(); ++k) entries_[k].stage = names_[k].c_str();
}

std::string EnergyLedger::balance_text(double change, double per) const {
  double added = 0;
  std::string parts;
  for (const auto& e : entries_) {
    added += e.energy;
    parts += std::string(parts.empty() ? "" : ", ") + e.stage + " " + fmt("%.6g", e.energy * per);
  }
  return "E - E0 = " + fmt("%.6g", change * per) + " = " + parts + " (residual " + fmt("%.2g", (change - added) * per) +
         ")";
}

void EnergyLedger::write(std::map<std::string, double>& run) const {
  for (const auto& e : entries_) run[std::string("energy_added.") + e.stage] = e.energy;
}

void EnergyLedger::save(StateWriter& out) const {
  std::vector<double> values;
  for (const auto& e : entries_) values.push_back(e.energy);
  out.write("energy_ledger", values);
}

void EnergyLedger::load(StateReader& in) {
  std::vector<double> values(entries_.size(), 0.0);
  in.read("energy_ledger", values.data(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k) entries_[k].energy = values[k];
}

void WallTallies::add(int side, const BoundaryTally& step) {
  BoundaryTally& t = sides_[static_cast<std::size_t>(side)];
  t.hits += step.hits;
  for (int a = 0; a < 3; ++a) t.momentum[a] += step.momentum[a];
  t.energy += step.energy;
}

void WallTallies::add_species(const BoundaryTally* step, std::size_t stride) {
  const std::size_t count = species_.size() / 2;
  for (std::size_t side = 0; side < 2; ++side)
    for (std::size_t s = 0; s < count; ++s) {
      BoundaryTally& t = species_[side * count + s];
      const BoundaryTally& d = step[side * stride + s];
      t.hits += d.hits;
      for (int a = 0; a < 3; ++a) t.momentum[a] += d.momentum[a];
      t.energy += d.energy;
    }
}

void WallTallies::write(std::map<std::string, double>& run) const {
  for (std::size_t s = 0; s < 2; ++s) {
    const std::string side = s == 0 ? "boundary.y_min." : "boundary.y_max.";
    const BoundaryTally& t = sides_[s];
    run[side + "hits"] = static_cast<double>(t.hits);
    run[side + "momentum_x"] = t.momentum[0];
    run[side + "momentum_y"] = t.momentum[1];
    run[side + "momentum_z"] = t.momentum[2];
    run[side + "energy"] = t.energy;
  }
}

void WallTallies::save(StateWriter& out) const {
  for (const BoundaryTally& t : sides_) {
    out.write("boundary.hits", t.hits);
    const double v[4] = {t.momentum[0], t.momentum[1], t.momentum[2], t.energy};
    out.write("boundary.values", v, 4);
  }
  for (const BoundaryTally& t : species_) {  // a mixture's only
    out.write("boundary.species.hits", t.hits);
    const double v[4] = {t.momentum[0], t.momentum[1], t.momentum[2], t.energy};
    out.write("boundary.species.values", v, 4);
  }
}

void WallTallies::load(StateReader& in) {
  for (BoundaryTally& t : sides_) {
    in.read("boundary.hits", t.hits);
    double v[4];
    in.read("boundary.values", v, 4);
    for (int a = 0; a < 3; ++a) t.momentum[a] = v[a];
    t.energy = v[3];
  }
  for (BoundaryTally& t : species_) {
    in.read("boundary.species.hits", t.hits);
    double v[4];
    in.read("boundary.species.values", v, 4);
    for (int a = 0; a < 3; ++a) t.momentum[a] = v[a];
    t.energy = v[3];
  }
}

void CollisionTallies::open(std::vector<std::string> names) {
  names_ = std::move(names);
  totals_.assign(names_.size(), CollisionTally{});
  for (std::size_t k = 0; k < totals_.size(); ++k) totals_[k].name = names_[k].c_str();
}

void CollisionTallies::add(const double* step) {
  for (std::size_t k = 0; k < totals_.size(); ++k) totals_[k].value += step[k];
}

void CollisionTallies::save(StateWriter& out) const {
  std::vector<double> values;
  for (const auto& t : totals_) values.push_back(t.value);
  out.write("collision_tallies", values);
}

void CollisionTallies::load(StateReader& in) {
  std::vector<double> values(totals_.size());
  in.read("collision_tallies", values.data(), values.size());
  for (std::size_t k = 0; k < values.size(); ++k) totals_[k].value = values[k];
}

}  // namespace gdsmc::host
