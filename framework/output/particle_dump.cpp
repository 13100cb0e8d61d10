#include "output/particle_dump.hpp"

#include <cmath>

namespace gdsmc::host {

std::vector<ParticleDataset> particle_datasets(const ParticleSpan& s, const SystemInfo& system) {
  std::vector<ParticleDataset> out;
  const double length = system.mean_free_path0, speed = std::sqrt(2.0 * system.initial_temperature / system.mass);
  auto column = [&](const char* name, const double* v, double scale, const char* unit, const char* doc) {
    ParticleDataset d{name, unit, doc, 1, std::vector<double>(v, v + s.count)};
    for (double& x : d.data) x /= scale;
    out.push_back(std::move(d));
  };
  column("x", s.x, length, "lambda0", "final position x");
  column("y", s.y, length, "lambda0", "final position y");
  column("z", s.z, length, "lambda0", "final position z");
  column("vx", s.vx, speed, "sqrt(2T0/m)", "final velocity x");
  column("vy", s.vy, speed, "sqrt(2T0/m)", "final velocity y");
  column("vz", s.vz, speed, "sqrt(2T0/m)", "final velocity z");
  for (std::size_t a = 0; a < s.attribute_count; ++a) {
    const AttributeSpec& spec = s.attribute_specs[a];
    const double* data = s.attribute_data[a];
    out.push_back(ParticleDataset{spec.name, spec.unit, spec.doc, spec.components,
                                  std::vector<double>(data, data + s.count * spec.components)});
  }
  return out;
}

}  // namespace gdsmc::host
