// Drag force F = -m gamma V on the (frictional) elastic hard spheres, gamma = zeta0/2 or refined.
#include <cmath>
#include <stdexcept>

#include <gdsmc/gdsmc.hpp>

namespace {

class Drag final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "drag";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Drag F = -m gamma V with gamma = zeta0(T)/2 (EHS, Eq. 4.22) or the refined gamma";
  static constexpr const char* documentation =
      "The drag force of the (frictional) EHS gas, paper 000 Eq. (2.20): F = -m gamma V with V the\n"
      "velocity relative to the mean velocity u of all particles, and\n"
      "  gamma = zeta0 / 2,   zeta0 = 2 (1 - alpha^2) / (3 sqrt(pi) tau(T)),   tau(T) = lambda0 / sqrt(2T/m)\n"
      "(Eq. 2.16 with the local-equilibrium cooling rate, tau as in Eq. 4.22). T and u are computed from\n"
      "the particles at every apply (no lag), and the step is integrated exactly at frozen T:\n"
      "  v <- u + (v - u) exp(-gamma dt)                                       (Eq. 4.22)\n"
      "With refined: true, gamma = (zeta0/2) <V12^3> / <V12^3>_0 (Sec. V.B-C) with\n"
      "<V12^3>_0 = 32/sqrt(pi) (T/m)^{3/2} (Eq. 2.15) and <V12^3> estimated from `pairs` random\n"
      "pairs i != j (Eq. 4.20) drawn from this forcing's random stream, recomputed every\n"
      "`ratio_every` steps (held in between). alpha: the restitution coefficient being mimicked;\n"
      "a negative value (the default, -1) takes the collision rule's published 'restitution'.\n"
      "Conserves momentum (to round-off: V is relative to the mean), not energy: the kinetic energy\n"
      "falls by the factor exp(-2 gamma dt) per step. order() = 1: gamma depends on T, which the\n"
      "drag itself changes during the step (T(t) ~ T/(1 + gamma t)^2 vs exp(-2 gamma t)).\n"
      "Publishes 'drag_model' = 1 (gamma = zeta0/2) or 2 (refined) for diagnostics.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "restitution coefficient being mimicked; < 0: the collision rule's 'restitution'")
                .range(-1.0, 1.0)
                .default_value(-1.0),
            gdsmc::ParamSpec::boolean("refined", "gamma = (zeta0/2) <V12^3>/<V12^3>_0 instead of zeta0/2").default_value(false),
            gdsmc::ParamSpec::integer("pairs", "random pairs N_p for <V12^3> (Eq. 4.20; refined only)")
                .range(1.0, 1e9)
                .default_value(25000),
            gdsmc::ParamSpec::integer("ratio_every", "recompute <V12^3>/<V12^3>_0 every this many steps (refined only)")
                .range(1.0, 1e9)
                .default_value(1)};
  }
  explicit Drag(const gdsmc::Params& p)
      : alpha_param_(p.real("alpha")),
        refined_(p.boolean("refined")),
        pairs_(static_cast<std::uint64_t>(p.integer("pairs"))),
        ratio_every_(static_cast<std::uint64_t>(p.integer("ratio_every"))) {}

  void publish(gdsmc::QuantityBoard& board) const override { board.publish("drag_model", refined_ ? 2.0 : 1.0); }

  void apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, gdsmc::Rng& rng) override {
    if (p.count == 0) return;
    if (!have_alpha_) {
      if (alpha_param_ >= 0) {
        alpha_ = alpha_param_;
      } else {
        const double* a = ctx.quantities ? ctx.quantities->find("restitution") : nullptr;
        if (!a)
          throw std::runtime_error("drag: no alpha given and the collision rule publishes no 'restitution'; "
                                   "set drag.alpha or use equivalent_elastic_hard_spheres");
        alpha_ = *a;
      }
      have_alpha_ = true;
    }
    // Mean velocity and temperature of the particles now.
    const double inv = 1.0 / static_cast<double>(p.count);
    double ux = 0, uy = 0, uz = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      ux += p.vx[i];
      uy += p.vy[i];
      uz += p.vz[i];
    }
    ux *= inv;
    uy *= inv;
    uz *= inv;
    double c2 = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      const double cx = p.vx[i] - ux, cy = p.vy[i] - uy, cz = p.vz[i] - uz;
      c2 += cx * cx + cy * cy + cz * cz;
    }
    const double T = c2 * inv / 3.0;  // m = 1
    if (!(T > 0)) return;
    const double tau = gdsmc::characteristic_time(ctx.system->mean_free_path0, T);  // tau(T), Eq. 4.22
    const double zeta0 = gdsmc::cooling_rate0_times_tau(alpha_) / tau;                 // Eq. 2.16
    double gamma = 0.5 * zeta0;
    if (refined_) {
      if (!have_ratio_ || ctx.step % ratio_every_ == 0) {
        ratio_ = gdsmc::relative_speed_cube_ratio(p, T, pairs_, rng);  // Eq. 4.20
        have_ratio_ = true;
      }
      gamma *= ratio_;
    }
    const double f = std::exp(-gamma * ctx.dt);
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] = ux + (p.vx[i] - ux) * f;
      p.vy[i] = uy + (p.vy[i] - uy) * f;
      p.vz[i] = uz + (p.vz[i] - uz) * f;
    }
  }
  gdsmc::Conservation conserves() const override { return {true, false}; }
  int order() const override { return 1; }

 private:
  double alpha_param_;
  bool refined_;
  std::uint64_t pairs_, ratio_every_;
  bool have_alpha_ = false, have_ratio_ = false;
  double alpha_ = 1, ratio_ = 1;
};

}  // namespace

GDSMC_PLUGIN(Drag)
