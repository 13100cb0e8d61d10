// A white-noise (stochastic) thermostat: every particle receives an independent Gaussian kick
// at every step,
//   v_i(t + dt) = v_i(t) + sqrt(2 D dt) xi_i,   xi_i a vector of three standard normals,
// the Euler-Maruyama step of dv = sqrt(2D) dW (Williams & MacKintosh, Phys. Rev. E 54, R9 (1996);
// van Noije & Ernst, Granular Matter 1, 57 (1998)). The mean kinetic energy per particle grows by
// (m/2) <|sqrt(2 D dt) xi|^2> = 3 m D dt, i.e. dT/dt = 2 m D for T = (m/3)<V^2>; with inelastic
// collisions the gas reaches the steady state where this heating balances the collisional
// cooling zeta(T) T (zeta ~ sqrt(T)). The step is the Euler-Maruyama step, order() 1 as the SDK
// asks a white-noise forcing to declare (for this pure additive noise it is even exact in
// distribution: two independent kicks of dt/2 make a kick of dt). It declares its mean energy
// input, 3 N m D per unit time (expected_energy_rate), which `gdsmc conformance` checks.
//
// D is given as the initial heating rate h = (dT/dt) / (T0/tau0) (a bare number, so that the same
// value means the same physics at any density): D = h T0 / (2 m tau0).
#include <cmath>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class WhiteNoiseThermostat final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "white_noise_heating";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Stochastic thermostat: independent Gaussian kicks v += sqrt(2 D dt) xi";
  static constexpr const char* documentation =
      "White-noise thermostat (Williams & MacKintosh, PRE 54, R9 (1996); van Noije & Ernst,\n"
      "Granular Matter 1, 57 (1998)). After the collisions of every step each particle i gets\n"
      "  v_i += sqrt(2 D dt) xi_i,   xi_i three independent standard normals\n"
      "from its own stream (Streams::for_particle(id)), so the result does not depend on the\n"
      "storage order. Heating: d<(m/2)v^2>/dt = 3 m D, dT/dt = 2 m D. The parameter is the heating\n"
      "rate h = (dT/dt) / (T0/tau0), i.e. D = h T0 / (2 m tau0). apply() returns the kinetic energy\n"
      "it added, sum (m/2)(v'^2 - v^2) (random, mean 3 N m D dt). It conserves neither momentum nor\n"
      "energy (each kick is independent: the total momentum diffuses). Declares its mean energy input\n"
      "3 N m D per unit time (expected_energy_rate). Euler-Maruyama, order() 1 (for this additive\n"
      "noise exact in distribution for any dt).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("heating_rate", "heating rate h = (dT/dt) / (T0/tau0); D = h T0 / (2 m tau0)")
                .range(0.0, 100.0)
                .default_value(0.1)};
  }
  explicit WhiteNoiseThermostat(const gdsmc::Params& p) : heating_rate_(p.real("heating_rate")) {}

  Stage stage() const override { return Stage::after_collisions; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::SystemInfo& sys = *ctx.system;
    const double D = strength(sys);
    const double kick = std::sqrt(2.0 * D * ctx.dt);
    if (!(kick > 0)) return 0.0;
    double added = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      gdsmc::Rng rng = ctx.streams->for_particle(p.id[i]);
      const double dx = kick * rng.normal(), dy = kick * rng.normal(), dz = kick * rng.normal();
      // (m/2)((v + d)^2 - v^2) = m (v.d + d^2/2), computed from the kick itself (no cancellation)
      added += sys.mass * (p.vx[i] * dx + p.vy[i] * dy + p.vz[i] * dz + 0.5 * (dx * dx + dy * dy + dz * dz));
      p.vx[i] += dx;
      p.vy[i] += dy;
      p.vz[i] += dz;
    }
    return added;
  }
  // The mean of what apply() returns, per unit time: N (m/2) <|sqrt(2 D dt) xi|^2> / dt = 3 N m D.
  bool expected_energy_rate(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, double& rate) const override {
    rate = 3.0 * static_cast<double>(p.count) * ctx.system->mass * strength(*ctx.system);
    return true;
  }
  gdsmc::Conservation conserves() const override { return {}; }
  int order() const override { return 1; }

 private:
  // D = h T0 / (2 m tau0), velocity^2 per unit time per component.
  double strength(const gdsmc::SystemInfo& sys) const {
    return heating_rate_ * sys.initial_temperature / (2.0 * sys.mass * sys.time_unit0);
  }
  double heating_rate_;
};

}  // namespace

GDSMC_PLUGIN(WhiteNoiseThermostat)
