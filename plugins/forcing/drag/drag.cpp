// Drag force F = -m gamma V on the (frictional) elastic hard spheres, gamma = zeta0/2 or refined;
// per layer in a slab (000 Eq. 4.12).
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class Drag final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "drag";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* summary =
      "Drag F = -m gamma V with gamma = zeta0(T)/2 (EHS, Eq. 4.22; per layer in a slab, Eq. 4.12) or the refined gamma";
  static constexpr const char* documentation =
      "The drag force of the (frictional) EHS gas, paper 000 Eq. (2.20): F = -m gamma V with V the\n"
      "velocity relative to the mean velocity u, and\n"
      "  gamma = zeta0 / 2,   zeta0 = 2 (1 - alpha^2) / (3 sqrt(pi) tau(T)),   tau(T) = lambda / sqrt(2T/m)\n"
      "(Eq. 2.16 with the local-equilibrium cooling rate). alpha: the restitution coefficient being\n"
      "mimicked; a negative value (the default, -1) takes the collision rule's published 'restitution'.\n"
      "Homogeneous system: T and u are those of all particles, computed at every apply (no lag),\n"
      "lambda = lambda0, and the step is integrated exactly at frozen T:\n"
      "  v <- u + (v - u) exp(-gamma dt)                                       (Eq. 4.22)\n"
      "Slab (Sec. IV.A): per layer I, with u_I, T_I, n_I the layer's moments as of the host's last\n"
      "moment update (run.moments_every; the paper updates them every 4 time steps),\n"
      "  v_i <- u_I + (v_i - u_I) exp(-zeta_I dt/2),   I the layer of particle i       (Eq. 4.12)\n"
      "with zeta_I the coarse-grained cooling rate, zeta0 at the local density and temperature:\n"
      "zeta_I = 2 (1 - alpha^2) / (3 sqrt(pi) tau_I), tau_I = lambda_I / sqrt(2 T_I/m), lambda_I =\n"
      "lambda0 n-bar / n_I = 1/(sqrt(2) pi n_I sigma^2) (Eqs. 2.12-2.13). Layers with fewer than 2\n"
      "particles (T_I = 0) are left unchanged.\n"
      "With refined: true (homogeneous systems only), gamma = (zeta0/2) <V12^3> / <V12^3>_0 (Sec. V.B-C)\n"
      "with <V12^3>_0 = 32/sqrt(pi) (T/m)^{3/2} (Eq. 2.15) and <V12^3> estimated from `pairs` random\n"
      "pairs i != j (Eq. 4.20) drawn from this forcing's stream for_unit(0) of the step, recomputed every\n"
      "`ratio_every` steps (held in between). In a slab refined: true is refused when the run starts\n"
      "(the refined gamma is defined for homogeneous systems only, Sec. V.B-C): use refined: false,\n"
      "which applies Eq. (4.12) per layer.\n"
      "Returns the kinetic energy it removed (negative), sum (1/2)(v'^2 - v^2) (m = 1), to the host's\n"
      "energy ledger. Conserves momentum (to round-off: V is relative to the mean; in a slab, of each\n"
      "layer as of the last moment update, so only approximately between updates), not energy: the\n"
      "kinetic energy of the peculiar motion falls by the factor exp(-2 gamma dt) per step. order() = 1:\n"
      "gamma depends on T, which the drag itself changes during the step (T(t) ~ T/(1 + gamma t)^2 vs\n"
      "exp(-2 gamma t)). Publishes 'drag_model' = 1 (gamma = zeta0/2) or 2 (refined) for diagnostics.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "restitution coefficient being mimicked; < 0: the collision rule's 'restitution'")
                .range(-1.0, 1.0)
                .default_value(-1.0),
            gdsmc::ParamSpec::boolean("refined",
                                      "gamma = (zeta0/2) <V12^3>/<V12^3>_0 instead of zeta0/2 (homogeneous systems only)")
                .default_value(false),
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

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const bool slab = ctx.system->geometry == gdsmc::Geometry::slab;
    if (slab && refined_)
      throw std::runtime_error(
          "drag: refined: true is defined for homogeneous systems only (000 Sec. V.B-C); use refined: false with layers");
    if (p.count == 0) return 0.0;
    resolve_alpha(ctx);
    return slab ? apply_layers(ctx, p) : apply_homogeneous(ctx, p);
  }
  gdsmc::Conservation conserves() const override { return {true, false}; }
  int order() const override { return 1; }
  // Checkpoints: alpha, resolved at the first apply, and the <V12^3> ratio held between
  // recomputations (refined, ratio_every > 1). factor_ is recomputed at every apply.
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("have_alpha", have_alpha_);
    out.write("alpha", alpha_);
    out.write("have_ratio", have_ratio_);
    out.write("ratio", ratio_);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("have_alpha", have_alpha_);
    in.read("alpha", alpha_);
    in.read("have_ratio", have_ratio_);
    in.read("ratio", ratio_);
  }

 private:
  void resolve_alpha(const gdsmc::StepContext& ctx) {
    if (have_alpha_) return;
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

  // v <- u + (v - u) f for particle i; returns (1/2)(v'^2 - v^2) (m = 1).
  static double relax(const gdsmc::ParticleSpan& p, std::size_t i, const double* u, double f) {
    const double dx = (p.vx[i] - u[0]) * (f - 1.0), dy = (p.vy[i] - u[1]) * (f - 1.0), dz = (p.vz[i] - u[2]) * (f - 1.0);
    const double de = dx * (p.vx[i] + 0.5 * dx) + dy * (p.vy[i] + 0.5 * dy) + dz * (p.vz[i] + 0.5 * dz);
    p.vx[i] = u[0] + (p.vx[i] - u[0]) * f;
    p.vy[i] = u[1] + (p.vy[i] - u[1]) * f;
    p.vz[i] = u[2] + (p.vz[i] - u[2]) * f;
    return de;
  }

  // Homogeneous: u and T of all particles now (Eq. 4.22), gamma = zeta0/2 or refined.
  double apply_homogeneous(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) {
    const double inv = 1.0 / static_cast<double>(p.count);
    const gdsmc::VelocitySums sums = gdsmc::velocity_sums(p);
    const double u[3] = {sums.sum[0] * inv, sums.sum[1] * inv, sums.sum[2] * inv};  // sum / N as sum * (1/N)
    const double c2 = gdsmc::peculiar_square_sum(p, u);
    const double T = c2 * inv / 3.0;  // m = 1
    if (!(T > 0)) return 0.0;
    const double tau = gdsmc::characteristic_time(ctx.system->mean_free_path0, T);  // tau(T), Eq. 4.22
    double gamma = 0.5 * gdsmc::cooling_rate0_times_tau(alpha_) / tau;             // zeta0/2, Eq. 2.16
    if (refined_) {
      if (!have_ratio_ || ctx.step % ratio_every_ == 0) {
        gdsmc::Rng rng = ctx.streams->for_unit(0);
        ratio_ = gdsmc::relative_speed_cube_ratio(p, T, pairs_, rng);  // Eq. 4.20
        have_ratio_ = true;
      }
      gamma *= ratio_;
    }
    const double f = std::exp(-gamma * ctx.dt);
    double energy = 0;
    for (std::size_t i = 0; i < p.count; ++i) energy += relax(p, i, u, f);
    return energy;
  }

  // Slab: Eq. (4.12) per layer with u_I, T_I, n_I of the last moment update.
  double apply_layers(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) {
    const double lambda0 = ctx.system->mean_free_path0, n_bar = ctx.system->number_density;
    const double zeta_tau = gdsmc::cooling_rate0_times_tau(alpha_);
    factor_.assign(ctx.cell_count, 1.0);
    for (std::size_t I = 0; I < ctx.cell_count; ++I) {
      const gdsmc::CellMoments& c = ctx.cells[I];
      if (c.count < 2 || !(c.temperature > 0) || !(c.number_density > 0)) continue;  // left unchanged
      const double tau_I = gdsmc::characteristic_time(lambda0 * n_bar / c.number_density, c.temperature);
      factor_[I] = std::exp(-0.5 * zeta_tau / tau_I * ctx.dt);  // exp(-zeta_I dt/2)
    }
    double energy = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      const std::uint32_t I = p.cell ? p.cell[i] : 0;  // homogeneous: one cell, no cell array
      if (factor_[I] != 1.0) energy += relax(p, i, ctx.cells[I].mean_velocity, factor_[I]);
    }
    return energy;
  }

  double alpha_param_;
  bool refined_;
  std::uint64_t pairs_, ratio_every_;
  bool have_alpha_ = false, have_ratio_ = false;
  double alpha_ = 1, ratio_ = 1;
  std::vector<double> factor_;  // exp(-zeta_I dt/2) per layer (slab)
};

}  // namespace

GDSMC_PLUGIN(Drag)
