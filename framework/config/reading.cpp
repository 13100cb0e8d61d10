#include "config/reading.hpp"

#include <cmath>

#include "config/system_info.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

std::vector<std::string> bare_value_lines(const Pipeline& p) {
  std::vector<std::string> lines;
  const UnitScales scales = unit_scales(p);
  for (const BareValue& b : p.bare_values) {
    const std::string dimension = to_string(b.dimension);
    lines.push_back(fmt("%s = %.10g (%s), a bare %s: read as ", b.path.c_str(), b.value, b.where.str().c_str(),
                        dimension.c_str()) +
                    common_units_text(b.value * reference_factor(b.dimension, scales), b.dimension, scales));
  }
  return lines;
}

std::string system_numbers_line(const Pipeline& p) {
  const double n_sigma3 = p.number_density * p.sigma * p.sigma * p.sigma;
  std::string s = fmt("n sigma^3 = %.4g (phi = pi n sigma^3/6 = %.4g), lambda0 = %.4g sigma, tau0 = %.4g (reduced), "
                      "T0 = %.4g",
                      n_sigma3, M_PI / 6 * n_sigma3, p.mean_free_path0() / p.sigma, p.time_unit0(), p.temperature);
  if (p.geometry == Geometry::slab && p.box_y > 0) {
    const double per_layer = static_cast<double>(p.particles) / static_cast<double>(p.layers);
    s += fmt("; slab Ly = %.4g sigma = %.4g lambda0: Kn = lambda0/Ly = %.4g; %zu layers of %.4g lambda0, %.4g "
             "particles per layer",
             p.box_y / p.sigma, p.box_y / p.mean_free_path0(), p.mean_free_path0() / p.box_y, p.layers,
             p.box_y / static_cast<double>(p.layers) / p.mean_free_path0(), per_layer);
    if (p.layers_mean_free_paths > 0 && p.layers_max_width > 0)
      s += fmt(" until t = %.4g tau0, then sized from the density profile to at most %.4g local mean free paths "
               "and %.4g lambda0 each",
               p.layers_after_tau0, p.layers_mean_free_paths, p.layers_max_width / p.mean_free_path0());
    else if (p.layers_mean_free_paths > 0)
      s += fmt(" until t = %.4g tau0, then sized from the density profile to %.4g local mean free paths each "
               "(target %.4g)",
               p.layers_after_tau0, p.box_y / static_cast<double>(p.layers) / p.mean_free_path0(),
               p.layers_mean_free_paths);
  }
  if (!p.species.empty()) {
    // A mixture: each species with its mass, diameter, fraction and count; phi of every species.
    const std::vector<std::size_t> counts = species_counts(p.species, p.particles);
    double phi = 0;
    s += "; mixture of";
    for (std::size_t k = 0; k < p.species.size(); ++k) {
      const SpeciesSpec& sp = p.species[k];
      s += fmt("%s %s (m = %.4g m, sigma = %.4g sigma, x = %.4g, %zu particles)", k ? "," : "", sp.name.c_str(), sp.mass,
               sp.diameter, sp.fraction, counts[k]);
      phi += M_PI / 6 * n_sigma3 * sp.fraction * sp.diameter * sp.diameter * sp.diameter;
    }
    s += fmt(", phi = sum pi n_s sigma_s^3/6 = %.4g", phi);
  }
  if (p.time_step_tau0 > 0)
    s += fmt("; dt = %.4g tau0 = %.4g mean free times of hard spheres at T0%s", p.time_step_tau0,
             p.time_step_tau0 / kMeanFreeTimeTau0, p.time_step_follows_temperature ? " (times sqrt(T0/T))" : "");
  return s;
}

}  // namespace gdsmc::host
