// A two-temperature ("bimodal") Maxwellian: a fraction f of the particles drawn from a Maxwellian
// at T_hot, the rest from one at T_cold, both at rest, positions uniform in the box:
//   f(v) = n [ f M(v; T_hot) + (1 - f) M(v; T_cold) ],   M(v; T) = (m / 2 pi T)^{3/2} exp(-m v^2 / 2T),
// with T_hot / T_cold = r and the mixture's temperature f T_hot + (1 - f) T_cold = T (the run's
// T0 by default), so T_cold = T / (f r + 1 - f), T_hot = r T_cold. Its fourth cumulant
//   a2 = <V^4> / <V^4>_Maxwell - 1 = (f T_hot^2 + (1 - f) T_cold^2) / T^2 - 1 > 0
// is far from the homogeneous cooling state's, so a run from it shows how fast collisions erase a
// strongly non-Maxwellian start (the velocity distribution relaxes to the HCS in a few collisions
// per particle, the temperature follows Haff's law after that).
#include <cmath>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class BimodalMaxwellian final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "bimodal_maxwellian";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Two-temperature Maxwellian: a fraction f at T_hot, the rest at T_cold = T_hot / r";
  static constexpr const char* documentation =
      "f(v) = n [ f M(v; T_hot) + (1 - f) M(v; T_cold) ], M(v; T) = (m/2 pi T)^{3/2} exp(-m v^2/2T),\n"
      "at rest, positions uniform in the box. T_hot / T_cold = temperature_ratio (r) and\n"
      "f T_hot + (1 - f) T_cold = temperature (T): T_cold = T / (f r + 1 - f), T_hot = r T_cold.\n"
      "Each particle draws from its own stream (Streams::for_particle of its identity): whether it is\n"
      "hot (a uniform below f), its position and its velocity, so the state does not depend on the\n"
      "storage order. With exact_moments (default) the whole sample is shifted to zero momentum and\n"
      "rescaled to exactly T (which keeps the ratio r). Fourth cumulant of the mixture:\n"
      "  a2 = (f T_hot^2 + (1 - f) T_cold^2) / T^2 - 1   (published as 'initial_a2').\n"
      "r = 1 is the Maxwellian.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("temperature", "temperature T of the mixture").above(0.0).unit(gdsmc::Dimension::temperature).default_value(1.0),
            gdsmc::ParamSpec::real("hot_fraction", "fraction f of the particles in the hot population").range(0.0, 1.0).default_value(0.5),
            gdsmc::ParamSpec::real("temperature_ratio", "r = T_hot / T_cold").range(1.0, 1.0e4).default_value(9.0),
            gdsmc::ParamSpec::boolean("exact_moments", "shift to zero momentum and rescale to exactly T").default_value(true)};
  }
  explicit BimodalMaxwellian(const gdsmc::Params& p)
      : temperature_(p.real("temperature")),
        fraction_(p.real("hot_fraction")),
        ratio_(p.real("temperature_ratio")),
        exact_(p.boolean("exact_moments")) {
    t_cold_ = temperature_ / (fraction_ * ratio_ + 1.0 - fraction_);
    t_hot_ = ratio_ * t_cold_;
  }

  void publish(gdsmc::QuantityBoard& board) const override {
    board.publish("initial_a2", (fraction_ * t_hot_ * t_hot_ + (1.0 - fraction_) * t_cold_ * t_cold_) /
                                    (temperature_ * temperature_) - 1.0);
  }

  void generate(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, const gdsmc::ParticleSpan& p,
                const gdsmc::Streams& streams) override {
    const double sd_hot = std::sqrt(t_hot_ / sys.mass), sd_cold = std::sqrt(t_cold_ / sys.mass);
    for (std::size_t i = 0; i < p.count; ++i) {
      gdsmc::Rng rng = streams.for_particle(p.id[i]);
      const double sd = rng.uniform() < fraction_ ? sd_hot : sd_cold;
      gdsmc::place_uniformly(sys, p, i, rng);
      p.vx[i] = sd * rng.normal();
      p.vy[i] = sd * rng.normal();
      p.vz[i] = sd * rng.normal();
    }
    if (exact_) gdsmc::impose_exact_moments(p, temperature_);
  }

 private:
  double temperature_, fraction_, ratio_;
  bool exact_;
  double t_cold_ = 1, t_hot_ = 1;
};

}  // namespace

GDSMC_PLUGIN(BimodalMaxwellian)
