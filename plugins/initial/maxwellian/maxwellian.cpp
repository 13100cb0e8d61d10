// Maxwellian initial state at rest (homogeneous), positions uniform in the box.
#include <cmath>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class Maxwellian final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "maxwellian";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary = "Maxwellian velocities at temperature T, at rest; uniform positions";
  static constexpr const char* documentation =
      "Velocities drawn from f0(v) = n (m / 2 pi T)^{3/2} exp(-m v^2 / 2T) (paper 000, Eq. 2.14)\n"
      "with mean velocity zero; positions uniform in the box. With exact_moments (default) the\n"
      "sample is shifted to zero total momentum and rescaled to the exact temperature T, so the\n"
      "run starts at T/T0 = 1 to round-off. Each particle is drawn from its own stream\n"
      "(Streams::for_particle of its identity), so the state does not depend on the storage order.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("temperature", "initial temperature T").above(0.0).unit(gdsmc::Dimension::temperature).default_value(1.0),
            gdsmc::ParamSpec::boolean("exact_moments", "shift to zero momentum and rescale to exactly T").default_value(true)};
  }
  explicit Maxwellian(const gdsmc::Params& p) : temperature_(p.real("temperature")), exact_(p.boolean("exact_moments")) {}

  void generate(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, const gdsmc::ParticleSpan& p,
                const gdsmc::Streams& streams) override {
    gdsmc::sample_maxwellian(sys, p, temperature_, streams);
    if (exact_) gdsmc::impose_exact_moments(p, temperature_);
  }

 private:
  double temperature_;
  bool exact_;
};

}  // namespace

GDSMC_PLUGIN(Maxwellian)
