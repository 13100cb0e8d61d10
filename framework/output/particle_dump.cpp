#include "output/particle_dump.hpp"

#include <cmath>

#include <gdsmc/physics/units.hpp>


namespace gdsmc::host {

std::vector<ParticleColumn> particle_columns(const ParticleSpan& s, const SystemInfo& system, const double* species) {
  const double length = system.mean_free_path0, speed = std::sqrt(2.0 * system.initial_temperature / system.mass);
  std::vector<ParticleColumn> out;
  if (s.x)  // a homogeneous system keeps no positions
    out = {{"x", units::length, "final position x", 1, s.x.data, s.count, length},
           {"y", units::length, "final position y", 1, s.y.data, s.count, length},
           {"z", units::length, "final position z", 1, s.z.data, s.count, length}};
  out.insert(out.end(), {
      {"vx", units::speed, "final velocity x", 1, s.vx.data, s.count, speed},
      {"vy", units::speed, "final velocity y", 1, s.vy.data, s.count, speed},
      {"vz", units::speed, "final velocity z", 1, s.vz.data, s.count, speed}});
  if (species)
    out.push_back({"species", "1", "species index k of each particle (/system attributes species.<name>.index)", 1,
                   species, s.count, 1.0});
  for (std::size_t a = 0; a < s.attribute_count; ++a) {
    const AttributeSpec& spec = s.attribute_specs[a];
    out.push_back({spec.name, spec.unit, spec.doc, spec.components, s.attribute_data[a], s.count, 1.0});
  }
  return out;
}

std::vector<ParticleDataset> particle_datasets(const ParticleSpan& s, const SystemInfo& system, const double* species,
                                               const ParticleStager* stage) {
  const std::vector<ParticleColumn> columns = particle_columns(s, system, species);
  if (stage && *stage) return (*stage)(columns);
  std::vector<ParticleDataset> out;
  for (const auto& c : columns) {
    ParticleDataset d{c.name, c.unit, c.doc, c.components, {c.values, c.values + c.count * c.components}, ""};
    if (c.scale != 1)
      for (double& x : d.data) x /= c.scale;
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace gdsmc::host
