// The homogeneous heat-flux force of paper 001: F'_eps = G'(V).eps (Eqs. 3.2, 2.32) for the
// modified thermal conductivity kappa', or F_eps = G(V).eps (Eqs. 3.16, 2.37) for kappa; its
// velocity-dependent part over one step (Eq. 4.1 and its analogue for G).
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/moments.hpp>

namespace {

class HeatFluxForce final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "heat_flux_force";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Velocity-dependent force producing a heat flux without gradients, eps along x (001 Eqs. 3.2/3.16, 4.1)";
  static constexpr const char* documentation =
      "Paper 001 (Montanero, Santos, Garzo) measures the Navier-Stokes heat-flux distribution of a\n"
      "granular gas in a homogeneous state: a weak force F = G(V).eps with a constant vector eps (which\n"
      "plays the role of grad ln T) makes the deviation from the homogeneous cooling state obey, to\n"
      "first order in eps, the same linear integral equation as a real temperature gradient.\n"
      "eps points along x. Two routes (parameter `route`):\n"
      "  kappa_prime (default): G'_ij = (T/2m) delta_ij - V_i V_j / 2 (Eqs. 3.2, 2.32), for the\n"
      "    modified conductivity kappa' = kappa - n mu / 2T; the distribution solves Eq. 3.1 with\n"
      "    forces only. Velocity part per step (Eq. 4.1): V <- V - (1/2) V (V.eps) dt.\n"
      "  kappa: G_ij = -(V^2/4 - T/m) delta_ij - V_i V_j / 4 (Eq. 2.37 with d = 3), for kappa itself;\n"
      "    Eq. 3.17 also needs the cloning-annihilation term (1/2) zeta (f - f0): add the forcing\n"
      "    cloning_annihilation. Velocity part per step: V_x <- V_x - (V^2 + V_x^2) eps dt / 4,\n"
      "    V_y,z <- V_y,z - V_y,z V_x eps dt / 4.\n"
      "The velocity-independent parts of G (T/2m eps or T/m eps along x) and the momentum term beta\n"
      "of the thermostat (Eqs. 3.4, 3.18) only shift the mean velocity: energy_momentum_thermostat,\n"
      "which must follow this forcing, removes that shift and restores the energy (Eq. 4.2). V is the\n"
      "velocity relative to the mean velocity of the gas at the start of the step (zero after the\n"
      "thermostat). Euler step: order 1.\n"
      "Strength: epsilon_star = lambda eps, the reduced field of 001 (text after Eq. 3.11), with\n"
      "lambda = 1 / (sqrt(2) pi n sigma^2), the mean free path of 001 Sec. IV (tau = lambda / v0) and of\n"
      "000 Eq. 4.1. This lambda is the paper's: with it Eq. 2.45, kappa' = (5/4) n lambda v0 b'_1,\n"
      "gives the elastic first-Sonine conductivity kappa0 of Eq. 2.47 (75/(64 sigma^2) sqrt(T/(pi m)))\n"
      "for b'_1 = 15 sqrt(pi)/16, so the b'_k of Eqs. 3.10, 3.12 (divided by epsilon_star) and\n"
      "kappa'/kappa0 of Eq. 3.9 are mutually consistent only with it. The temperature is held at T0 by\n"
      "the thermostat, so lambda is that of the initial state. The paper uses epsilon_star = 0.025\n"
      "(0.05 for the linearity check of its Fig. 1).\n"
      "Publishes 'heat_flux_epsilon_star' and 'heat_flux_route' (0 kappa_prime, 1 kappa) for the\n"
      "diagnostic heat_flux. Returns the kinetic energy it added (m = 1).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("epsilon_star", "reduced field strength lambda eps (001 text after Eq. 3.11)")
                .range(0.0, 1.0)
                .default_value(0.025),
            gdsmc::ParamSpec::choice("route", {"kappa_prime", "kappa"},
                                     "kappa_prime: force G' (Eq. 3.2); kappa: force G (Eq. 3.16), with cloning_annihilation")
                .default_value("kappa_prime")};
  }
  explicit HeatFluxForce(const gdsmc::Params& p)
      : epsilon_star_(p.real("epsilon_star")), kappa_route_(p.string("route") == "kappa") {}

  void publish(gdsmc::QuantityBoard& board) const override {
    board.publish("heat_flux_epsilon_star", epsilon_star_);
    board.publish("heat_flux_route", kappa_route_ ? 1.0 : 0.0);
  }
  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {}; }
  int order() const override { return 1; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (p.count == 0) return 0.0;
    const double k = epsilon_star_ / ctx.system->mean_free_path0 * ctx.dt;  // eps dt, eps = eps*/lambda
    double u[3];
    gdsmc::velocity_sums(p).mean(u);
    double energy = 0;  // sum (1/2)(v'^2 - v^2), m = 1
    for (std::size_t i = 0; i < p.count; ++i) {
      const double X = p.vx[i] - u[0], Y = p.vy[i] - u[1], Z = p.vz[i] - u[2];
      double dx, dy, dz;
      if (kappa_route_) {  // G . eps, velocity part (Eq. 2.37, d = 3)
        dx = -0.25 * (X * X + Y * Y + Z * Z + X * X) * k;
        dy = -0.25 * Y * X * k;
        dz = -0.25 * Z * X * k;
      } else {  // Eq. 4.1
        dx = -0.5 * X * X * k;
        dy = -0.5 * Y * X * k;
        dz = -0.5 * Z * X * k;
      }
      energy += dx * (p.vx[i] + 0.5 * dx) + dy * (p.vy[i] + 0.5 * dy) + dz * (p.vz[i] + 0.5 * dz);
      p.vx[i] += dx;
      p.vy[i] += dy;
      p.vz[i] += dz;
    }
    return energy;
  }

 private:
  double epsilon_star_;
  bool kappa_route_;
};

}  // namespace

GDSMC_PLUGIN(HeatFluxForce)
