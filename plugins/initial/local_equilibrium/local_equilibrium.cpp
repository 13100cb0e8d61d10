// Local equilibrium with the linear shear profile (000 Eq. 3.12).
#include <cmath>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class LocalEquilibrium final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "local_equilibrium";
  static constexpr const char* version = "1.1.0";
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
      "publishes (the lees_edwards boundary), and the run is refused if none does.";

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
                .default_value(true)};
  }
  explicit LocalEquilibrium(const gdsmc::Params& p)
      : temperature_(p.real("temperature")),
        shear_rate_(p.real("shear_rate")),
        published_shear_rate_(p.entry("shear_rate").defaulted),
        laboratory_(p.string("frame") == "laboratory"),
        exact_(p.boolean("exact_moments")) {}

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
    gdsmc::sample_maxwellian(sys, p, temperature_, streams);
    if (exact_) gdsmc::impose_exact_moments(p, temperature_);
    if (laboratory_)
      for (std::size_t i = 0; i < p.count; ++i) p.vx[i] += a * p.y[i];
  }

 private:
  double temperature_, shear_rate_;
  bool published_shear_rate_, laboratory_, exact_;
};

}  // namespace

GDSMC_PLUGIN(LocalEquilibrium)
