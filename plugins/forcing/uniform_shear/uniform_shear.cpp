// Uniform shear flow in the Lagrangian frame: the inertial force -m a V_y x_hat.
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {

class UniformShear final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "uniform_shear";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Uniform shear flow in the Lagrangian frame: force -m a V_y x_hat";
  static constexpr const char* documentation =
      "Homogeneous uniform shear flow (paper 000, Sec. III and IV.B). Velocities are peculiar\n"
      "velocities V = v - a y x_hat (Eq. 3.2); the streaming term becomes -a V_y dV_x (Eq. 3.4), i.e.\n"
      "the non-conservative inertial force F = -m a V_y x_hat, integrated as (Eq. 4.21)\n"
      "  V_x(t + dt) = V_x(t) - a V_y(t) dt.\n"
      "This is exact for the force alone (V_y does not change under it), so order() = 0. It heats the\n"
      "gas at the rate dE/dt = -a Omega P_xy (viscous heating; -(2a/3n) P_xy = zeta T in a steady\n"
      "state). Total momentum changes by -a dt sum V_y: conserved only if the mean V_y is zero (it\n"
      "stays zero in a USF run, but the forcing does not enforce it), so nothing is declared\n"
      "conserved. apply() returns the kinetic energy it added, sum (1/2)(V_x'^2 - V_x^2) (m = 1), for\n"
      "the host's energy ledger. shear_rate: a bare number is a tau0 (a in units of 1/tau0), or give\n"
      "{value: X, unit: 1/tau0 | reduced}. Publishes 'shear_rate' (reduced units) for diagnostics\n"
      "(shear_rheology, bgk_usf_theory). Combined with drag (Eq. 4.22) the order of the two forcings\n"
      "does not matter: the drag scales V_x and V_y by the same factor.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("shear_rate", "imposed shear rate a (bare numbers: a tau0)")
                .unit(gdsmc::Dimension::inverse_time)};
  }
  explicit UniformShear(const gdsmc::Params& p) : a_(p.real("shear_rate")) {}

  void publish(gdsmc::QuantityBoard& board) const override { board.publish("shear_rate", a_); }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double k = a_ * ctx.dt;
    const gdsmc::Column<double> vx = p.vx, vy = p.vy;
    double energy = 0;  // sum (1/2)(V_x'^2 - V_x^2) = sum dV_x (V_x + dV_x/2), m = 1
    for (std::size_t i = 0; i < p.count; ++i) {
      const double dvx = -k * vy[i];  // Eq. (4.21)
      energy += dvx * (vx[i] + 0.5 * dvx);
      vx[i] += dvx;
    }
    return energy;
  }
  gdsmc::Conservation conserves() const override { return {}; }
  int order() const override { return 0; }

 private:
  double a_;
};

}  // namespace

GDSMC_PLUGIN(UniformShear)
