// Fully diffuse thermal wall (004 Eqs. 6-9).
#include <cmath>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>
#include <gdsmc/physics/species_values.hpp>

namespace {

class DiffuseWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "diffuse_wall";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Fully diffuse thermal wall (004 Eqs. 6-9): re-emission from the half-Maxwellian at T_w about the wall velocity";
  static constexpr const char* documentation =
      "Fully diffuse thermal wall of paper 004 (Sec. III A, Eqs. 6-9). At the exact crossing time the\n"
      "particle stays on the plane and forgets its velocity: it is re-emitted with\n"
      "  v_x = u_x + sqrt(T_w/m) G,  v_z = u_z + sqrt(T_w/m) G   (Eqs. 6, 8; G standard normal),\n"
      "  |v_y| from p(v) = (m v / T_w) exp(-m v^2 / 2 T_w)      (Eqs. 7, 9; Rayleigh, the flux distribution),\n"
      "v_y pointing into the gas. |v_y| = sqrt(-2 (T_w/m) ln U) with U uniform on (0, 1], never 0. The\n"
      "host then streams the remaining flight time of the step under the body acceleration, which is\n"
      "the a t_post of Eq. 6 and Eqs. 10-12. The physics is gdsmc::ThermalWall / diffuse_emission in\n"
      "gdsmc/physics/walls.hpp. For a partially diffuse wall (accommodation coefficient between specular and\n"
      "diffuse, 004 Sec. VI) use maxwell_wall; accommodation 1 there reproduces this wall bit for bit.\n"
      "Parameters: temperature T_w > 0 (bare numbers: T_w / T0; default 1), velocity_x and velocity_z\n"
      "the wall's velocity u in its plane (any real; bare numbers in units of sqrt(2 T0/m); default 0:\n"
      "e.g. +-U/2 on y_max / y_min for Couette flow). Conserves mass only: the wall exchanges energy\n"
      "(heat) and tangential momentum (shear stress) with the gas, which the host tallies per side; a\n"
      "gas at rest relative to the wall at temperature T_w is in detailed balance with it.\n"
      "Mixtures (system.species): a particle of species s (mass m_s, WallHit::species) is re-emitted\n"
      "from the wall Maxwellian of its own species, the thermal scale sqrt(T_w,s / m_s) in Eqs. 6-9:\n"
      "<v_x^2> = <v_z^2> = T_w,s / m_s about u and <v_y^2> = 2 T_w,s / m_s over the emitted flux, so\n"
      "that each species is in detailed balance with the wall at T_w,s (equipartition at the wall).\n"
      "T_w,s is `temperature` unless species_temperature names the species: \"heavy: 1.5\" (bare\n"
      "numbers in units of T0, entries separated by commas; the names are checked against the run's\n"
      "species). The wall velocity is the same for every species. A one-species run draws exactly\n"
      "as before mixtures.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    std::vector<gdsmc::ParamSpec> specs = gdsmc::ThermalWall::parameters();
    specs.push_back(gdsmc::ParamSpec::string("species_temperature",
                                             "mixtures: wall temperature for named species, \"name: T_w,s/T0, ...\" "
                                             "(others: temperature)")
                        .default_value(""));
    return specs;
  }
  explicit DiffuseWall(const gdsmc::Params& p)
      : wall_(p),
        species_temperature_(gdsmc::parse_species_values(name, "species_temperature", p.string("species_temperature"),
                                                         {0.0, gdsmc::kMaxWallTemperature, true})) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  // [setup] In a mixture (or with species_temperature given) one thermal wall and one mass per
  // species; otherwise none, and interact() takes the one-species path.
  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, const gdsmc::Vec3&) override {
    walls_.clear();
    masses_.clear();
    if (!gdsmc::has_species_masses(sys) && species_temperature_.empty()) return;
    const std::vector<double> T = gdsmc::species_values(sys, name, "species_temperature", species_temperature_,
                                                        wall_.temperature, sys.initial_temperature);
    for (std::size_t s = 0; s < sys.species_count; ++s) {
      walls_.push_back(wall_);
      walls_.back().temperature = T[s];
      masses_.push_back(sys.species_mass(s));
    }
  }

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    if (walls_.empty())
      wall_.reemit(hit, ctx.system->mass, rng);
    else
      walls_[hit.species].reemit(hit, masses_[hit.species], rng);  // Eqs. 6-9 with sqrt(T_w,s / m_s)
    return gdsmc::HitResult::reflected;
  }

 private:
  gdsmc::ThermalWall wall_;
  std::vector<gdsmc::SpeciesValue> species_temperature_;
  std::vector<gdsmc::ThermalWall> walls_;  // per species (empty: one species)
  std::vector<double> masses_;             // m_s
};

}  // namespace

GDSMC_PLUGIN(DiffuseWall)
