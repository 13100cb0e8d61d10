// <V12^3> / <V12^3>_0 from N_p random pairs (000 Eq. 4.20 over Eq. 2.15).
#include <cmath>
#include <cstdio>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class RelativeSpeedCube final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "relative_speed_cube";
  static constexpr const char* version = "1.3.0";
  static constexpr const char* summary = "<V12^3>/<V12^3>_0 from N_p random pairs (Eq. 4.20), i.e. zeta/zeta0 of IHS";
  static constexpr const char* documentation =
      "At each sample, N_p = `pairs` pairs i != j are drawn at random (with replacement) from the\n"
      "N(N-1)/2 pairs, and <V12^3> = (1/N_p) sum |V_i - V_j|^3 (paper 000, Eq. 4.20) is divided by its\n"
      "local-equilibrium value <V12^3>_0 = 32/sqrt(pi) (T/m)^{3/2} (Eq. 2.15) at the current T. For IHS\n"
      "the ratio is zeta/zeta0, the true over the local-equilibrium cooling rate (Eq. 2.10). T and a2\n"
      "are the host's moments of the sample (ctx.moments); in a slab V is the velocity relative to the\n"
      "particle's layer flow u_I (ctx.cells, as of the host's last moment update) and T is T-bar\n"
      "(Eq. 4.8). The pairs are drawn from this diagnostic\n"
      "instance's own stream (ctx.streams->for_unit(0) of the sample's step), so it never disturbs the\n"
      "dynamics and two instances never share draws. Series: ratio (window mean), a2 (Eq. 4.17, for\n"
      "the empirical relation ratio ~ 1 + 0.27 a2 of Sec. V.C) and ratio_minus_one_over_a2. After the\n"
      "run: scalars ratio_mean, ratio_standard_error, a2_mean, a2_standard_error over the samples in\n"
      "the run's steady averaging window (run.average_after; ctx.in_average_window, no parameter of\n"
      "its own) (batch means), and slope = (ratio_mean - 1)/a2_mean.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("pairs", "number N_p of random pairs per sample (Eq. 4.20)").range(1.0, 1e9).default_value(25000)};
  }
  explicit RelativeSpeedCube(const gdsmc::Params& p) : pairs_(static_cast<std::uint64_t>(p.integer("pairs"))) {}

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    window_.declare(out, {{"ratio", "1", "<V12^3>/<V12^3>_0 (Eqs. 4.20, 2.15)"},
                          {"a2", "1", "fourth cumulant (Eq. 4.17)"},
                          {"ratio_minus_one_over_a2", "1", "(ratio - 1)/a2 (about 0.27 in USF, 3/16 in isotropic states)"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    gdsmc::Rng rng = ctx.streams->for_unit(0);
    const double ratio = ctx.system->geometry == gdsmc::Geometry::slab
                             ? slab_ratio(ctx, p, m.temperature, rng)
                             : gdsmc::relative_speed_cube_ratio(p, m.temperature, pairs_, rng);  // Eq. 4.20
    const double a2 = m.a2();
    window_.add({ratio, a2, (ratio - 1.0) / a2});
    if (ctx.in_average_window) {
      ratio_avg_.add(ratio);
      a2_avg_.add(a2);
    }
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.scalar("ratio_mean", ratio_avg_.mean(), "1", "<V12^3>/<V12^3>_0 averaged over the averaging window");
    out.scalar("ratio_standard_error", ratio_avg_.standard_error(), "1", "batch-means standard error of ratio_mean");
    out.scalar("a2_mean", a2_avg_.mean(), "1", "a2 averaged over the averaging window");
    out.scalar("a2_standard_error", a2_avg_.standard_error(), "1", "batch-means standard error of a2_mean");
    const double slope = (ratio_avg_.mean() - 1.0) / a2_avg_.mean();
    out.scalar("slope", slope, "1", "(ratio_mean - 1)/a2_mean; paper 000 Sec. V.C finds about 0.27 in steady USF");
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "relative_speed_cube: in the averaging window (%zu samples): <V12^3>/<V12^3>_0 = %.4f +- %.4f, a2 = %.4f +- %.4f, "
                  "(ratio-1)/a2 = %.3f (paper: ~0.27)",
                  ratio_avg_.count(), ratio_avg_.mean(), ratio_avg_.standard_error(), a2_avg_.mean(),
                  a2_avg_.standard_error(), slope);
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    window_.save(out);
    ratio_avg_.save(out, "ratio_avg");
    a2_avg_.save(out, "a2_avg");
  }
  void load_state(gdsmc::StateReader& in) override {
    window_.load(in);
    ratio_avg_.load(in, "ratio_avg");
    a2_avg_.load(in, "a2_avg");
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  const void* extension(const char* id) const override { return gdsmc::offer_bracketed_sampling(id); }
 private:
  // Eq. (4.20) in a slab: the same estimator on the peculiar velocities V_i = v_i - u_I relative to
  // each particle's layer (ctx.cells: u_I as of the last moment update).
  double slab_ratio(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, double temperature, gdsmc::Rng& rng) {
    const std::size_t n = p.count;
    peculiar_.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const double* u = ctx.cells[p.cell[i]].mean_velocity;
      peculiar_[i] = p.vx[i] - u[0];
      peculiar_[n + i] = p.vy[i] - u[1];
      peculiar_[2 * n + i] = p.vz[i] - u[2];
    }
    gdsmc::ParticleSpan V;
    V.count = n;
    V.vx = peculiar_.data();
    V.vy = peculiar_.data() + n;
    V.vz = peculiar_.data() + 2 * n;
    return gdsmc::relative_speed_cube_ratio(V, temperature, pairs_, rng);
  }

  std::uint64_t pairs_;
  std::vector<double> peculiar_;  // V_x, V_y, V_z of every particle (slab)
  gdsmc::WindowAverage window_;
  gdsmc::BatchMeans ratio_avg_, a2_avg_;
};

}  // namespace

GDSMC_PLUGIN(RelativeSpeedCube)
