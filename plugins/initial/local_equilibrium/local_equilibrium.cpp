// Local equilibrium with the linear shear profile (000 Eq. 3.12).
#include <cmath>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>
#include <gdsmc/physics/mixture_maxwellian.hpp>
#include <gdsmc/physics/species_values.hpp>

namespace {

class LocalEquilibrium final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "local_equilibrium";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* summary =
      "Local equilibrium of uniform shear flow (Eq. 3.12): Maxwellian about the profile a y x_hat";
  static constexpr const char* documentation =
      "Paper 000, Eq. (3.12): f(r, v; 0) = n (m/2 pi T)^{3/2} exp[-m (v - a y x_hat)^2 / 2T], uniform\n"
      "density, positions uniform in the box (y in [-L/2, L/2), so the profile vanishes mid-box).\n"
      "frame: lagrangian (default) stores the peculiar velocities V = v - a y x_hat, which is what the\n"
      "homogeneous USF engine evolves (uniform_shear forcing, Eq. 3.4): there the profile a y x_hat is\n"
      "carried by the frame and the stored state is simply a Maxwellian at rest, whatever the shear\n"
      "rate. frame: laboratory stores the laboratory velocities v = V + a y x_hat, for slab runs with\n"
      "Lees-Edwards boundaries (3.1); do not combine it with the uniform_shear forcing. With\n"
      "exact_moments (default) the peculiar velocities are shifted to zero mean and rescaled to exactly\n"
      "T before the profile is added. Each particle is drawn from its own stream (Streams::for_particle\n"
      "of its identity), so the state does not depend on the storage order. shear_rate (used only by\n"
      "frame: laboratory): a bare number is a tau0 (any sign); when it is not given (the default\n"
      "shown as -1 means 'not given') the shear rate is the quantity 'shear_rate' that another plugin\n"
      "publishes (the lees_edwards boundary), and the run is refused if none does.\n"
      "Mixtures (system.species): species s of mass m_s is Maxwellian at its own T_s about the same\n"
      "profile a y x_hat (the flow is common to all species), each peculiar velocity component with\n"
      "standard deviation sqrt(T_s / m_s); T_s is `temperature` unless species_temperatures names\n"
      "the species (\"heavy: 2.0\", bare numbers in units of T0, entries separated by commas). With\n"
      "exact_moments every species of two or more particles has zero mean peculiar velocity and\n"
      "exactly T_s = m_s <V^2> / 3, hence zero barycentric peculiar velocity and the mixture\n"
      "temperature sum m_i V_i^2 / 3N = sum_s x_s T_s to round-off (a species of one particle is left\n"
      "as drawn and the barycentric velocity removed instead). A one-species run draws exactly the\n"
      "numbers it drew before mixtures.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("temperature", "initial temperature T").above(0.0).unit(gdsmc::Dimension::temperature).default_value(1.0),
            gdsmc::ParamSpec::real("shear_rate",
                                   "shear rate a of the profile a y x_hat (bare numbers: a tau0; frame: laboratory only); "
                                   "not given: the published 'shear_rate' (lees_edwards)")
                .unit(gdsmc::Dimension::inverse_time)
                .default_value(-1.0),
            gdsmc::ParamSpec::choice("frame", {"lagrangian", "laboratory"},
                                     "store peculiar (lagrangian) or laboratory velocities")
                .default_value("lagrangian"),
            gdsmc::ParamSpec::boolean("exact_moments", "shift to zero mean peculiar velocity and rescale to exactly T")
                .default_value(true),
            gdsmc::ParamSpec::string("species_temperatures",
                                     "mixtures: initial temperatures of named species, \"name: T_s/T0, ...\" (others: temperature)")
                .default_value("")};
  }
  explicit LocalEquilibrium(const gdsmc::Params& p)
      : temperature_(p.real("temperature")),
        shear_rate_(p.real("shear_rate")),
        published_shear_rate_(p.entry("shear_rate").defaulted),
        laboratory_(p.string("frame") == "laboratory"),
        exact_(p.boolean("exact_moments")),
        species_temperatures_(gdsmc::parse_species_values(name, "species_temperatures", p.string("species_temperatures"),
                                                          {0.0, HUGE_VAL, true})) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void generate(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& quantities, const gdsmc::ParticleSpan& p,
                const gdsmc::Streams& streams) override {
    double a = shear_rate_;
    if (laboratory_ && sys.geometry != gdsmc::Geometry::slab)
      throw gdsmc::ParameterError("frame",
                                  "local_equilibrium: frame: laboratory adds the profile a y x_hat, which needs positions: "
                                  "use it in a slab (Lees-Edwards boundaries); a homogeneous system keeps no positions and "
                                  "takes frame: lagrangian");
    if (laboratory_ && published_shear_rate_) {
      const double* published = quantities.find("shear_rate");
      if (!published)
        throw gdsmc::ParameterError("shear_rate",
                                    "local_equilibrium: frame: laboratory needs a shear rate: give shear_rate, or use a "
                                    "boundary that publishes 'shear_rate' (lees_edwards)");
      a = *published;
    }
    if (!gdsmc::has_species_masses(sys) && species_temperatures_.empty()) {
      gdsmc::sample_maxwellian(sys, p, temperature_, streams);
      if (exact_) gdsmc::impose_exact_moments(p, temperature_);
    } else {
      const std::vector<double> T = gdsmc::species_values(sys, name, "species_temperatures", species_temperatures_,
                                                          temperature_, sys.initial_temperature);
      gdsmc::sample_mixture_maxwellian(sys, p, T, streams);
      if (exact_) gdsmc::impose_exact_mixture_moments(sys, p, T);
    }
    if (laboratory_)
      for (std::size_t i = 0; i < p.count; ++i) p.vx[i] += a * p.y[i];
  }

 private:
  double temperature_, shear_rate_;
  bool published_shear_rate_, laboratory_, exact_;
  std::vector<gdsmc::SpeciesValue> species_temperatures_;
};

}  // namespace

GDSMC_PLUGIN(LocalEquilibrium)
