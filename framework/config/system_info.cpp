#include "config/system_info.hpp"

#include <cmath>

namespace gdsmc::host {

SystemInfo system_info(const Pipeline& p, std::size_t n, std::uint32_t realization) {
  SystemInfo sys;
  sys.particles = n;
  sys.number_density = p.number_density;
  sys.sigma = p.sigma;
  sys.mass = 1.0;
  sys.initial_temperature = p.temperature;
  sys.mean_free_path0 = p.mean_free_path0();
  sys.time_unit0 = p.time_unit0();
  sys.volume = static_cast<double>(n) / p.number_density;
  sys.geometry = p.geometry;
  if (p.geometry == Geometry::slab) {
    sys.box[1] = p.box_y;
    const double area = sys.volume / p.box_y;  // A = (N/L)/n (000 Eq. 4.2)
    sys.box[0] = p.box_x > 0 ? p.box_x : std::sqrt(area);
    sys.box[2] = area / sys.box[0];
    sys.cells = p.layers;
    sys.bins = p.bins ? p.bins : p.layers;
  } else {
    sys.box[0] = sys.box[1] = sys.box[2] = std::cbrt(sys.volume);
    sys.cells = 1;
    sys.bins = 1;
  }
  if (p.species_table) {
    sys.species_count = p.species_table->info.size();
    sys.species = p.species_table->info.data();
  }
  sys.seed = p.seed;
  sys.realization = realization;
  return sys;
}

}  // namespace gdsmc::host
