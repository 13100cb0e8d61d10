// Maxwellian initial state at rest (homogeneous), positions uniform in the box; in a mixture each
// species at its own temperature.
#include <cmath>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>
#include <gdsmc/physics/mixture_maxwellian.hpp>
#include <gdsmc/physics/species_values.hpp>

namespace {

class Maxwellian final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "maxwellian";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* summary = "Maxwellian velocities at temperature T, at rest; uniform positions";
  static constexpr const char* documentation =
      "Velocities drawn from f0(v) = n (m / 2 pi T)^{3/2} exp(-m v^2 / 2T) (paper 000, Eq. 2.14)\n"
      "with mean velocity zero; positions uniform in the box. With exact_moments (default) the\n"
      "sample is shifted to zero total momentum and rescaled to the exact temperature T, so the\n"
      "run starts at T/T0 = 1 to round-off. Each particle is drawn from its own stream\n"
      "(Streams::for_particle of its identity), so the state does not depend on the storage order.\n"
      "Mixtures (system.species): species s of mass m_s is drawn from its own Maxwellian at T_s,\n"
      "each velocity component with standard deviation sqrt(T_s / m_s), so that every species has\n"
      "the temperature T_s = m_s <V^2> / 3. T_s is `temperature` unless species_temperatures names\n"
      "the species: \"heavy: 2.0\" (bare numbers in units of T0; entries separated by commas) starts\n"
      "a run out of equipartition. With exact_moments every species of two or more particles is\n"
      "shifted to zero mean velocity and rescaled to exactly T_s, so the total momentum\n"
      "sum m_i v_i is zero and the mixture temperature sum m_i V_i^2 / 3N is sum_s x_s T_s, both to\n"
      "round-off (a species of one particle is left as drawn and the barycentric velocity of all\n"
      "is removed instead). A one-species run draws exactly the numbers it drew before mixtures.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("temperature", "initial temperature T").above(0.0).unit(gdsmc::Dimension::temperature).default_value(1.0),
            gdsmc::ParamSpec::boolean("exact_moments", "shift to zero momentum and rescale to exactly T").default_value(true),
            gdsmc::ParamSpec::string("species_temperatures",
                                     "mixtures: initial temperatures of named species, \"name: T_s/T0, ...\" (others: temperature)")
                .default_value("")};
  }
  explicit Maxwellian(const gdsmc::Params& p)
      : temperature_(p.real("temperature")),
        exact_(p.boolean("exact_moments")),
        species_temperatures_(gdsmc::parse_species_values(name, "species_temperatures", p.string("species_temperatures"),
                                                          {0.0, HUGE_VAL, true})) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void generate(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, const gdsmc::ParticleSpan& p,
                const gdsmc::Streams& streams) override {
    if (!gdsmc::has_species_masses(sys) && species_temperatures_.empty()) {
      gdsmc::sample_maxwellian(sys, p, temperature_, streams);
      if (exact_) gdsmc::impose_exact_moments(p, temperature_);
      return;
    }
    const std::vector<double> T = gdsmc::species_values(sys, name, "species_temperatures", species_temperatures_,
                                                        temperature_, sys.initial_temperature);
    gdsmc::sample_mixture_maxwellian(sys, p, T, streams);
    if (exact_) gdsmc::impose_exact_mixture_moments(sys, p, T);
  }

 private:
  double temperature_;
  bool exact_;
  std::vector<gdsmc::SpeciesValue> species_temperatures_;
};

}  // namespace

GDSMC_PLUGIN(Maxwellian)
