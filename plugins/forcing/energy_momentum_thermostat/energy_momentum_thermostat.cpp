// The thermostat of paper 001, Eq. 4.2: every step, total momentum back to zero and the kinetic
// energy per particle back to its prescribed initial value K0.
#include <cmath>
#include <stdexcept>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/moments.hpp>

namespace {

class EnergyMomentumThermostat final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "energy_momentum_thermostat";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Restores zero total momentum and the initial kinetic energy after every step (001 Eq. 4.2)";
  static constexpr const char* documentation =
      "Paper 001's Eq. (4.2): after the collisions and the other after-collision forcings of the step,\n"
      "  V <- sqrt(K0 / K') (V - u'),\n"
      "with u' the mean velocity and K' = (m/2N) sum (V - u')^2 the kinetic energy per particle at that\n"
      "moment, and K0 = (3/2) T0 the prescribed initial kinetic energy per particle (T0 the system's\n"
      "`temperature`). Total momentum becomes zero and the kinetic energy (3/2) N T0, to round-off.\n"
      "It stands for the thermostat force F_th = (xi/2) V + beta of Eqs. 3.3-3.5 (3.18) and absorbs the\n"
      "velocity-independent part of the heat-flux force (text after Eq. 4.2). A forcing of its own,\n"
      "for any pipeline that wants a homogeneous state at fixed temperature: list it after the\n"
      "forcings it compensates (001 order: collisions, then heat_flux_force, then this).\n"
      "Stage after_collisions; exact (order 0); declares neither momentum nor energy conserved (it\n"
      "sets both); returns the kinetic energy it added (m = 1).";

  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit EnergyMomentumThermostat(const gdsmc::Params&) {}

  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {}; }
  int order() const override { return 0; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (p.count == 0) return 0.0;
    const double n = static_cast<double>(p.count);
    const gdsmc::VelocitySums sums = gdsmc::velocity_sums(p);
    double u[3];
    sums.mean(u);
    const double before = sums.square;
    const double peculiar = gdsmc::peculiar_square_sum(p, u);  // 2 N K' / m, from the differences (no cancellation)
    const double target = 3.0 * n * ctx.system->initial_temperature;  // 2 N K0 / m, K0 = (3/2) T0
    if (!(peculiar > 0))
      throw std::runtime_error("energy_momentum_thermostat: every particle has the mean velocity; the kinetic "
                               "energy cannot be restored by scaling (Eq. 4.2)");
    const double scale = std::sqrt(target / peculiar);  // Eq. 4.2
    double after = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] = scale * (p.vx[i] - u[0]);
      p.vy[i] = scale * (p.vy[i] - u[1]);
      p.vz[i] = scale * (p.vz[i] - u[2]);
      after += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
    return 0.5 * (after - before);
  }
};

}  // namespace

GDSMC_PLUGIN(EnergyMomentumThermostat)
