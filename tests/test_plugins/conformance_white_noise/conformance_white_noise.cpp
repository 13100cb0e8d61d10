// A white-noise thermostat (conformance test): v += sqrt(2 D dt) xi per component, xi Gaussian
// from the particle's own stream, D = strength T0 / tau0. It declares its mean heating rate
// dE/dt = (3/2) 2 D N = 3 N D (m = 1) through expected_energy_rate(): `gdsmc conformance` must
// report forcing.expected_energy PASS (and the whole plugin conforming).
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {
class WhiteNoise final : public gdsmc::Forcing {
 public:
#ifdef GDSMC_WHITE_NOISE_HALF_RATE
  static constexpr const char* name = "conformance_white_noise_half";
#else
  static constexpr const char* name = "conformance_white_noise";
#endif
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a white-noise thermostat that declares its heating rate";
  static constexpr const char* documentation =
      "v += sqrt(2 D dt) xi per component (Euler-Maruyama, weak order 1), D = strength T0/tau0; declares "
      "the mean energy input 3 N D per unit time.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("strength", "noise strength D in units of T0/(m tau0)").at_least(0).default_value(0.1)};
  }
  explicit WhiteNoise(const gdsmc::Params& p) : strength_(p.real("strength")) {}
  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {}; }  // neither: random kicks
  int order() const override { return 1; }                       // weak order of Euler-Maruyama
  bool expected_energy_rate(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, double& rate) const override {
    rate = declared_fraction() * 3.0 * static_cast<double>(p.count) * diffusion(ctx);
    return true;
  }
  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double a = std::sqrt(2.0 * diffusion(ctx) * ctx.dt);
    double energy = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      gdsmc::Rng rng = ctx.streams->for_particle(p.id[i]);
      const double dx = a * rng.normal(), dy = a * rng.normal(), dz = a * rng.normal();
      energy += dx * (p.vx[i] + 0.5 * dx) + dy * (p.vy[i] + 0.5 * dy) + dz * (p.vz[i] + 0.5 * dz);
      p.vx[i] += dx;
      p.vy[i] += dy;
      p.vz[i] += dz;
    }
    return energy;
  }

 private:
  double diffusion(const gdsmc::StepContext& ctx) const {
    return strength_ * ctx.system->initial_temperature / ctx.system->time_unit0;
  }
#ifdef GDSMC_WHITE_NOISE_HALF_RATE
  static constexpr double declared_fraction() { return 0.5; }  // the bug: half the true rate
#else
  static constexpr double declared_fraction() { return 1.0; }
#endif
  double strength_;
};
}  // namespace

GDSMC_PLUGIN(WhiteNoise)
