// Maxwell's partially diffuse wall (004 Sec. VI): diffuse with probability alpha, else specular.
#include <cmath>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>
#include <gdsmc/physics/species_values.hpp>

namespace {

class MaxwellWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "maxwell_wall";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Thermal partially diffuse (Maxwell) wall with accommodation coefficient alpha: diffuse with probability alpha, else specular";
  static constexpr const char* documentation =
      "Maxwell's partially diffuse wall (paper 004, Sec. VI: accommodation coefficient alpha in [0, 1],\n"
      "1 fully diffuse, 0 fully specular). At the exact crossing time the particle stays on the plane;\n"
      "with probability alpha it is re-emitted as by the fully diffuse thermal wall (Eqs. 6-9: x and z\n"
      "Gaussian with variance T_w/m about the wall velocity u, |v_y| Rayleigh with\n"
      "p(v) = (m v / T_w) exp(-m v^2 / 2 T_w), never 0), otherwise reflected specularly (v_y -> -v_y);\n"
      "v_y points into the gas either way. The host then streams the remaining flight time of the step\n"
      "under the body acceleration (Eqs. 10-12). The physics is gdsmc::maxwell_reflection in\n"
      "gdsmc/physics/walls.hpp. accommodation = 1 draws exactly as diffuse_wall and 0 exactly as specular_wall\n"
      "(no extra random number is drawn at either end), so both limits reproduce those walls bit for bit.\n"
      "Parameters: accommodation alpha in [0, 1] (required); temperature T_w > 0 (bare numbers: T_w / T0;\n"
      "default 1); velocity_x and velocity_z the wall's velocity u in its plane (any real; bare numbers in\n"
      "units of sqrt(2 T0/m); default 0). Conserves mass; energy and tangential momentum only at\n"
      "alpha = 0: the diffuse part exchanges heat and shear stress with the gas, which the host tallies\n"
      "per side. See diffuse_wall (alpha = 1) and specular_wall (alpha = 0).\n"
      "Mixtures (system.species): a particle of species s (mass m_s, WallHit::species) that is\n"
      "re-emitted diffusely leaves with the wall Maxwellian of its own species, thermal scale\n"
      "sqrt(T_w,s / m_s) (<v_y^2> = 2 T_w,s / m_s over the emitted flux), with probability alpha_s.\n"
      "T_w,s is `temperature` and alpha_s is `accommodation` unless species_temperature or\n"
      "species_accommodation names the species: \"heavy: 1.5\" (bare numbers, temperatures in units\n"
      "of T0, accommodations in [0, 1]; entries separated by commas; the names are checked against\n"
      "the run's species). A one-species run draws exactly as before mixtures.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    std::vector<gdsmc::ParamSpec> specs{
        gdsmc::ParamSpec::real("accommodation", "accommodation coefficient alpha: probability of diffuse re-emission "
                                                "(0 specular, 1 fully diffuse)")
            .range(0.0, 1.0)};
    for (auto& s : gdsmc::ThermalWall::parameters()) specs.push_back(std::move(s));
    specs.push_back(gdsmc::ParamSpec::string("species_temperature",
                                             "mixtures: wall temperature for named species, \"name: T_w,s/T0, ...\" "
                                             "(others: temperature)")
                        .default_value(""));
    specs.push_back(gdsmc::ParamSpec::string("species_accommodation",
                                             "mixtures: accommodation for named species, \"name: alpha_s, ...\" in [0, 1] "
                                             "(others: accommodation)")
                        .default_value(""));
    return specs;
  }
  explicit MaxwellWall(const gdsmc::Params& p)
      : accommodation_(p.real("accommodation")),
        wall_(p),
        species_temperature_(gdsmc::parse_species_values(name, "species_temperature", p.string("species_temperature"),
                                                         {0.0, gdsmc::kMaxWallTemperature, true})),
        species_accommodation_(gdsmc::parse_species_values(name, "species_accommodation",
                                                           p.string("species_accommodation"), {0.0, 1.0, false})) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  // [setup] In a mixture (or with a per-species parameter given) one thermal wall, accommodation
  // and mass per species; otherwise none, and interact() takes the one-species path.
  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, const gdsmc::Vec3&) override {
    walls_.clear();
    accommodations_.clear();
    masses_.clear();
    if (!gdsmc::has_species_masses(sys) && species_temperature_.empty() && species_accommodation_.empty()) return;
    const std::vector<double> T = gdsmc::species_values(sys, name, "species_temperature", species_temperature_,
                                                        wall_.temperature, sys.initial_temperature);
    accommodations_ = gdsmc::species_values(sys, name, "species_accommodation", species_accommodation_, accommodation_);
    for (std::size_t s = 0; s < sys.species_count; ++s) {
      walls_.push_back(wall_);
      walls_.back().temperature = T[s];
      masses_.push_back(sys.species_mass(s));
    }
  }

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    if (walls_.empty()) {
      gdsmc::maxwell_reflection(hit, accommodation_, wall_, ctx.system->mass, rng);
    } else {
      const std::uint32_t s = hit.species;  // 004 Sec. VI with alpha_s, T_w,s and m_s
      gdsmc::maxwell_reflection(hit, accommodations_[s], walls_[s], masses_[s], rng);
    }
    return gdsmc::HitResult::reflected;
  }

 private:
  double accommodation_;
  gdsmc::ThermalWall wall_;
  std::vector<gdsmc::SpeciesValue> species_temperature_, species_accommodation_;
  std::vector<gdsmc::ThermalWall> walls_;  // per species (empty: one species)
  std::vector<double> accommodations_, masses_;
};

}  // namespace

GDSMC_PLUGIN(MaxwellWall)
