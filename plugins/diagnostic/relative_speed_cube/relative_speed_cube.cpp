// <V12^3> / <V12^3>_0 from N_p random pairs (000 Eq. 4.20 over Eq. 2.15).
#include <cmath>
#include <cstdio>

#include <gdsmc/gdsmc.hpp>

namespace {

class RelativeSpeedCube final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "relative_speed_cube";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "<V12^3>/<V12^3>_0 from N_p random pairs (Eq. 4.20), i.e. zeta/zeta0 of IHS";
  static constexpr const char* documentation =
      "At each sample, N_p = `pairs` pairs i != j are drawn at random (with replacement) from the\n"
      "N(N-1)/2 pairs, and <V12^3> = (1/N_p) sum |V_i - V_j|^3 (paper 000, Eq. 4.20) is divided by its\n"
      "local-equilibrium value <V12^3>_0 = 32/sqrt(pi) (T/m)^{3/2} (Eq. 2.15) at the current T. For IHS\n"
      "the ratio is zeta/zeta0, the true over the local-equilibrium cooling rate (Eq. 2.10). The\n"
      "random stream is ctx.rng(diagnostic, unit 0x0512 + 2^16 stream) at each sample's step, so\n"
      "it never disturbs the dynamics. Series: ratio (window mean), a2 (Eq. 4.17, for the empirical\n"
      "relation ratio ~ 1 + 0.27 a2 of Sec. V.C) and ratio_minus_one_over_a2. After the run: scalars\n"
      "ratio_mean, ratio_standard_error, a2_mean, a2_standard_error over the samples with\n"
      "s >= average_after (batch means), and slope = (ratio_mean - 1)/a2_mean.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("pairs", "number N_p of random pairs per sample (Eq. 4.20)").range(1.0, 1e9).default_value(25000),
            gdsmc::ParamSpec::real("average_after", "collisions per particle s after which the steady averages are taken")
                .at_least(0.0)
                .default_value(20.0),
            gdsmc::ParamSpec::integer("stream", "random-stream index (distinct instances should differ)").range(0.0, 65535.0).default_value(0)};
  }
  explicit RelativeSpeedCube(const gdsmc::Params& p)
      : pairs_(static_cast<std::uint64_t>(p.integer("pairs"))),
        average_after_(p.real("average_after")),
        unit_(0x0512u + (static_cast<std::uint32_t>(p.integer("stream")) << 16)) {}

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    window_.declare(out, {{"ratio", "1", "<V12^3>/<V12^3>_0 (Eqs. 4.20, 2.15)"},
                          {"a2", "1", "fourth cumulant (Eq. 4.17)"},
                          {"ratio_minus_one_over_a2", "1", "(ratio - 1)/a2 (about 0.27 in USF, 3/16 in isotropic states)"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const auto m = gdsmc::velocity_moments(p);
    gdsmc::Rng rng = ctx.rng(gdsmc::StreamPurpose::diagnostic, unit_);
    const double ratio = gdsmc::relative_speed_cube_ratio(p, m.temperature, pairs_, rng);  // Eq. 4.20
    const double a2 = m.a2();
    window_.add({ratio, a2, (ratio - 1.0) / a2});
    if (ctx.collisions_per_particle() >= average_after_) {
      ratio_avg_.add(ratio);
      a2_avg_.add(a2);
    }
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.scalar("ratio_mean", ratio_avg_.mean(), "1", "<V12^3>/<V12^3>_0 averaged over s >= average_after");
    out.scalar("ratio_standard_error", ratio_avg_.standard_error(), "1", "batch-means standard error of ratio_mean");
    out.scalar("a2_mean", a2_avg_.mean(), "1", "a2 averaged over s >= average_after");
    out.scalar("a2_standard_error", a2_avg_.standard_error(), "1", "batch-means standard error of a2_mean");
    const double slope = (ratio_avg_.mean() - 1.0) / a2_avg_.mean();
    out.scalar("slope", slope, "1", "(ratio_mean - 1)/a2_mean; paper 000 Sec. V.C finds about 0.27 in steady USF");
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "relative_speed_cube: over s >= %g (%zu samples): <V12^3>/<V12^3>_0 = %.4f +- %.4f, a2 = %.4f +- %.4f, "
                  "(ratio-1)/a2 = %.3f (paper: ~0.27)",
                  average_after_, ratio_avg_.count(), ratio_avg_.mean(), ratio_avg_.standard_error(), a2_avg_.mean(),
                  a2_avg_.standard_error(), slope);
    out.summary(buf);
  }

 private:
  std::uint64_t pairs_;
  double average_after_;
  std::uint32_t unit_;
  gdsmc::WindowAverage window_;
  gdsmc::BatchMeans ratio_avg_, a2_avg_;
};

}  // namespace

GDSMC_PLUGIN(RelativeSpeedCube)
