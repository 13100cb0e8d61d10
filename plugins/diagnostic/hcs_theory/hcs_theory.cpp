// Homogeneous cooling state: Haff's law and the first-Sonine a2, written beside the measured values.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

// a2 of the HCS in the first Sonine approximation, d = 3 (paper 001, Eq. 2.16).
double sonine_a2(double alpha) {
  constexpr double d = 3.0;
  return 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha) /
         (25.0 + 24.0 * d - alpha * (57.0 - 8.0 * d) - 2.0 * (1.0 - alpha) * alpha * alpha);
}

class HcsTheory final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "hcs_theory";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* summary = "Haff's law and first-Sonine a2 of the HCS beside the measured T and a2";
  static constexpr const char* documentation =
      "For a freely cooling gas of inelastic hard spheres (restitution alpha, read from the\n"
      "collision rule's published 'restitution'):\n"
      "  Haff's law  T(t) = T1 / (1 + zeta(T1) (t - t1) / 2)^2, with T1 the temperature measured at\n"
      "  the first sample (time t1) and zeta = zeta0 (1 + 3 a2 / 16), zeta0 tau = 2 (1 - alpha^2) /\n"
      "  (3 sqrt(pi)) (paper 001, Eqs. 2.14-2.15 with d = 3; paper 000, Eq. 2.16);\n"
      "  a2 = 16 (1-alpha)(1-2 alpha^2) / (25 + 24d - alpha(57 - 8d) - 2(1-alpha) alpha^2)  (001, 2.16).\n"
      "Series: temperature [T0] (measured), temperature_haff [T0], a2 (measured), a2_sonine.\n"
      "T and a2 are the host's moments of the sample (ctx.moments). Scalars after the run: a2_mean and\n"
      "a2_standard_error over the samples in the run's steady averaging window (run.average_after;\n"
      "ctx.in_average_window, no parameter of its own) (batch means), temperature_ratio_to_haff at the\n"
      "last sample.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit HcsTheory(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* alpha = board.find("restitution");
    if (!alpha)
      throw gdsmc::ParameterError("plugin", "hcs_theory needs a collision rule that publishes 'restitution' "
                                            "(for example inelastic_hard_spheres)");
    alpha_ = *alpha;
    a2_theory_ = sonine_a2(alpha_);
    t0_ = sys.initial_temperature;
    tau0_ = sys.time_unit0;
    // zeta(T0) tau0 = 2 (1 - alpha^2)(1 + 3 a2 / 16) / (3 sqrt(pi))     (001 Eq. 2.14, 000 Eq. 2.16)
    zeta0_tau0_ = gdsmc::cooling_rate0_times_tau(alpha_) * (1.0 + 3.0 * a2_theory_ / 16.0);
    window_.declare(out, {{"temperature", "T0", "measured T / T0"},
                          {"temperature_haff", "T0", "Haff's law T / T0 (001 Eqs. 2.14-2.15)"},
                          {"a2", "1", "measured fourth cumulant (000 Eq. 4.17)"},
                          {"a2_sonine", "1", "first-Sonine HCS a2 (001 Eq. 2.16)"}});
  }

  double haff(double t) const {
    // T/T0 with zeta(T) = zeta(T0) sqrt(T/T0): T(t) = T1 / (1 + zeta(T1)(t - t1)/2)^2
    const double zeta1 = zeta0_tau0_ * std::sqrt(t1_) / tau0_;
    const double f = 1.0 + 0.5 * zeta1 * (t - time1_);
    return t1_ / (f * f);
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const double T = m.temperature / t0_;
    if (!have_first_) {
      t1_ = T;
      time1_ = ctx.time;
      have_first_ = true;
    }
    last_T_ = T;
    last_time_ = ctx.time;
    last_s_ = ctx.collisions_per_particle();
    const double a2 = m.a2();
    if (ctx.in_average_window) a2_avg_.add(a2);
    window_.add({T, haff(ctx.time), a2, a2_theory_});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double ratio = last_T_ / haff(last_time_);
    out.scalar("a2_mean", a2_avg_.mean(), "1", "time average of the measured a2 over the averaging window");
    out.scalar("a2_standard_error", a2_avg_.standard_error(), "1", "batch-means standard error of a2_mean");
    out.scalar("temperature_ratio_to_haff", ratio, "1", "measured T / Haff's-law T at the last sample");
    char buf[256];
    std::snprintf(buf, sizeof buf, "hcs_theory: at t = %.4g tau0 (s = %.4g): T/T0 = %.6g, Haff's law %.6g (ratio %.4f)",
                  last_time_ / tau0_, last_s_, last_T_, haff(last_time_), ratio);
    out.summary(buf);
    std::snprintf(buf, sizeof buf, "hcs_theory: a2 in the averaging window (%zu samples): %.5f +- %.5f; first Sonine, 001 Eq. (2.16): %.5f (alpha = %g)",
                  a2_avg_.count(), a2_avg_.mean(), a2_avg_.standard_error(), a2_theory_, alpha_);
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("have_first", have_first_);
    out.write("T1", t1_);
    out.write("time1", time1_);
    out.write("last_T", last_T_);
    out.write("last_time", last_time_);
    out.write("last_s", last_s_);
    a2_avg_.save(out, "a2_avg");
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("have_first", have_first_);
    in.read("T1", t1_);
    in.read("time1", time1_);
    in.read("last_T", last_T_);
    in.read("last_time", last_time_);
    in.read("last_s", last_s_);
    a2_avg_.load(in, "a2_avg");
    window_.load(in);
  }

 private:
  double alpha_ = 1, a2_theory_ = 0, t0_ = 1, tau0_ = 1, zeta0_tau0_ = 0;
  bool have_first_ = false;
  double t1_ = 1, time1_ = 0, last_T_ = 1, last_time_ = 0, last_s_ = 0;
  gdsmc::BatchMeans a2_avg_;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(HcsTheory)
