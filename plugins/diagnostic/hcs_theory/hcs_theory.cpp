// Homogeneous cooling state: Haff's law and the first-Sonine a2, written beside the measured values.
#include <cmath>
#include <cstdio>
#include <limits>
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

// The HCS in the second Sonine approximation, d = 3: phi = phi_M (1 + a2 S2(c^2) + a3 S3(c^2)),
// c = V / sqrt(2T/m). The collisional moments mu_p = -int dc c^p J*[phi, phi] are exact bilinear
// forms in (1, a2, a3) with coefficients polynomial in lambda = (1 + alpha)/2, derived exactly by
// scripts/hcs_sonine_moments.py (sympy; it also reproduces van Noije & Ernst's first-Sonine a2 and
// the 3/16 of 001 Eq. 2.14). The HCS conditions mu_4 = 5 (1 + a2) mu_2 and
// mu_6 = (105/4)(1 + 3 a2 - a3) mu_2 (moments of the scaled Boltzmann equation, 000 Eq. 2.8 with
// a = 0), linearised in a2 and a3, are the two equations L4, L6 below.
struct SecondSonine {
  double a2, a3;
};
SecondSonine second_sonine(double alpha) {
  const double l = 0.5 * (1.0 + alpha), l2 = l * l, l3 = l2 * l, l4 = l3 * l, l5 = l4 * l, l6 = l5 * l;
  // L4: p2 a2 + q2 a3 + r2 = 0
  const double p2 = -15 * l4 + 30 * l3 - 167.0 / 8 * l2 + 79.0 / 8 * l;
  const double q2 = 5.0 / 4 * l4 - 5.0 / 2 * l3 + 177.0 / 32 * l2 - 169.0 / 32 * l;
  const double r2 = -16 * l4 + 32 * l3 - 18 * l2 + 2 * l;
  // L6: p3 a2 + q3 a3 + r3 = 0
  const double p3 = -210 * l6 + 630 * l5 - 4695.0 / 4 * l4 + 2691.0 / 2 * l3 - 44979.0 / 64 * l2 + 9987.0 / 64 * l;
  const double q3 = 105.0 / 2 * l6 - 315.0 / 2 * l5 + 5895.0 / 16 * l4 - 4083.0 / 8 * l3 + 87267.0 / 256 * l2 -
                    32691.0 / 256 * l;
  const double r3 = -96 * l6 + 288 * l5 - 468 * l4 + 456 * l3 - 801.0 / 4 * l2 + 81.0 / 4 * l;
  const double det = p2 * q3 - q2 * p3;
  if (!(std::fabs(det) > 0)) return {0.0, 0.0};  // alpha = 1: both equations are 0 = 0, a2 = a3 = 0
  return {(q2 * r3 - r2 * q3) / det, (r2 * p3 - p2 * r3) / det};
}

// zeta*/zeta*_M = mu_2 / mu_2^M for phi truncated after a3, exactly (scripts/hcs_sonine_moments.py):
//   1 + 3 a2/16 + a3/64 + 9 a2^2/1024 + 15 a2 a3/2048 + 35 a3^2/16384.
// The first four terms are the relation of issue 29 (zeta_ratio_from_cumulants); the last two are
// written separately (zeta_ratio_from_cumulants_bilinear) so the size of what it neglects is seen.
double zeta_ratio_issue(double a2, double a3) { return 1.0 + 3.0 * a2 / 16.0 + a3 / 64.0 + 9.0 * a2 * a2 / 1024.0; }
double zeta_ratio_bilinear(double a2, double a3) {
  return zeta_ratio_issue(a2, a3) + 15.0 * a2 * a3 / 2048.0 + 35.0 * a3 * a3 / 16384.0;
}

class HcsTheory final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "hcs_theory";
  static constexpr const char* version = "1.3.2";
  static constexpr const char* summary =
      "Haff's law, first- and second-Sonine a2, a3 of the HCS and the cooling rate's cumulant expansion, beside the measured T, a2, a3";
  static constexpr const char* documentation =
      "For a freely cooling gas of inelastic hard spheres (restitution alpha, read from the\n"
      "collision rule's published 'restitution'):\n"
      "  Haff's law  T(t) = T1 / (1 + zeta(T1) (t - t1) / 2)^2, with T1 the temperature measured at\n"
      "  the first sample (time t1) and zeta = zeta0 (1 + 3 a2 / 16), zeta0 tau = 2 (1 - alpha^2) /\n"
      "  (3 sqrt(pi)) (paper 001, Eqs. 2.14-2.15 with d = 3; paper 000, Eq. 2.16);\n"
      "  a2 = 16 (1-alpha)(1-2 alpha^2) / (25 + 24d - alpha(57 - 8d) - 2(1-alpha) alpha^2)  (001, 2.16).\n"
      "Second Sonine (phi truncated after a3, the HCS moment conditions for p = 4, 6 linearised in a2, a3;\n"
      "exact collision moments from scripts/hcs_sonine_moments.py): a2_second_sonine, a3_second_sonine,\n"
      "and zeta_ratio_second_sonine = zeta*/zeta*_M = <V12^3>/<V12^3>_0 (000 Eq. 2.10) at those a2, a3.\n"
      "From the measured a2 and a3 (000 Eqs. 4.17-4.18) at every sample: zeta_ratio_from_cumulants =\n"
      "1 + 3a2/16 + a3/64 + 9a2^2/1024 (issue 29) and zeta_ratio_from_cumulants_bilinear (+ 15 a2 a3/2048\n"
      "+ 35 a3^2/16384: exact for a distribution with a_k = 0, k >= 4), to set beside the measured\n"
      "cooling rate (cooling_rate's zeta_over_zeta0).\n"
      "Series: temperature [T0] (measured), temperature_haff [T0], a2 (measured), a2_sonine, a3 (measured),\n"
      "a2_second_sonine, a3_second_sonine, zeta_ratio_second_sonine, zeta_ratio_from_cumulants,\n"
      "zeta_ratio_from_cumulants_bilinear, tail_rate (all dimensionless but T).\n"
      "tail_rate: A of the high-velocity tail phi(c) ~ exp(-A c) of the scaled HCS, A = 3 pi / mu_2 with\n"
      "mu_2 = sqrt(2 pi)(1 - alpha^2) zeta*/zeta*_M at second Sonine (van Noije & Ernst, Granular Matter 1,\n"
      "57 (1998)), NaN at alpha = 1 (a Maxwellian has no exponential tail); velocity_marginals' F(C) =\n"
      "4 pi C^2 phi(C) tests it.\n"
      "T and a2 are the host's moments of the sample (ctx.moments). Scalars after the run: a2_mean and\n"
      "a2_standard_error over the samples in the run's steady averaging window (run.average_after;\n"
      "ctx.in_average_window, no parameter of its own) (batch means), likewise\n"
      "zeta_ratio_from_cumulants_mean and _standard_error, temperature_ratio_to_haff at the last sample.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit HcsTheory(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* alpha = board.find("restitution");
    if (!alpha)
      throw gdsmc::ParameterError("plugin", "hcs_theory needs a collision rule that publishes 'restitution' "
                                            "(for example inelastic_hard_spheres)");
    alpha_ = *alpha;
    a2_theory_ = sonine_a2(alpha_);
    const SecondSonine ss = second_sonine(alpha_);
    a2_second_ = ss.a2;
    a3_second_ = ss.a3;
    zeta_ratio_second_ = zeta_ratio_bilinear(ss.a2, ss.a3);
    // High-velocity tail of the scaled HCS: at c >> 1 the loss term of J* is pi c phi (the unit
    // sphere's hemisphere integral of g.sigma), and the scaled equation (mu_2/3) d/dc.(c phi) = J*
    // gives phi ~ exp(-A c), A = 3 pi / mu_2, mu_2 = sqrt(2 pi)(1 - alpha^2) zeta*/zeta*_M (van Noije
    // & Ernst, Granular Matter 1, 57 (1998), in these units); zeta*/zeta*_M at second Sonine.
    tail_rate_ = (alpha_ < 1.0) ? 3.0 * M_PI / (std::sqrt(2.0 * M_PI) * (1.0 - alpha_ * alpha_) * zeta_ratio_second_)
                                : std::numeric_limits<double>::quiet_NaN();  // elastic: no exponential tail
    t0_ = sys.initial_temperature;
    tau0_ = sys.time_unit0;
    // zeta(T0) tau0 = 2 (1 - alpha^2)(1 + 3 a2 / 16) / (3 sqrt(pi))     (001 Eq. 2.14, 000 Eq. 2.16)
    zeta0_tau0_ = gdsmc::cooling_rate0_times_tau(alpha_) * (1.0 + 3.0 * a2_theory_ / 16.0);
    window_.declare(out, {{"temperature", "T0", "measured T / T0"},
                          {"temperature_haff", "T0", "Haff's law T / T0 (001 Eqs. 2.14-2.15)"},
                          {"a2", "1", "measured fourth cumulant (000 Eq. 4.17)"},
                          {"a2_sonine", "1", "first-Sonine HCS a2 (001 Eq. 2.16)"},
                          {"a3", "1", "measured sixth cumulant (000 Eq. 4.18)"},
                          {"a2_second_sonine", "1", "second-Sonine HCS a2 (linearised in a2, a3; scripts/hcs_sonine_moments.py)"},
                          {"a3_second_sonine", "1", "second-Sonine HCS a3 (linearised in a2, a3; scripts/hcs_sonine_moments.py)"},
                          {"zeta_ratio_second_sonine", "1", "zeta*/zeta*_M at the second-Sonine a2, a3 (mu_2 with a_k = 0, k >= 4)"},
                          {"zeta_ratio_from_cumulants", "1", "1 + 3a2/16 + a3/64 + 9a2^2/1024 from the measured a2, a3 (issue 29)"},
                          {"zeta_ratio_from_cumulants_bilinear", "1", "the same + 15 a2 a3/2048 + 35 a3^2/16384 (all of mu_2 for a_k = 0, k >= 4)"},
                          {"tail_rate", "1", "A of the HCS tail phi ~ exp(-A c), c = V/sqrt(2T/m): 3 pi / mu_2 (van Noije & Ernst 1998)"}});
    out.theory("temperature_haff", "temperature", "001 Eqs. 2.14-2.15");
    out.theory("a2_sonine", "a2", "001 Eq. 2.16");
    out.theory("a2_second_sonine", "a2", "second Sonine, scripts/hcs_sonine_moments.py");
    out.theory("a3_second_sonine", "a3", "second Sonine, scripts/hcs_sonine_moments.py");
    out.theory("zeta_ratio_second_sonine", "zeta_ratio_from_cumulants, zeta_ratio_from_cumulants_bilinear",
               "000 Eq. 2.10 at the second-Sonine a2, a3");
    out.theory("tail_rate", "", "van Noije & Ernst, Granular Matter 1, 57 (1998)");
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
    const double a3 = m.a3();
    if (ctx.in_average_window) {
      a2_avg_.add(a2);
      zeta_ratio_avg_.add(zeta_ratio_issue(a2, a3));
    }
    window_.add({T, haff(ctx.time), a2, a2_theory_, a3, a2_second_, a3_second_, zeta_ratio_second_, zeta_ratio_issue(a2, a3),
                 zeta_ratio_bilinear(a2, a3), tail_rate_});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double ratio = last_T_ / haff(last_time_);
    out.scalar("a2_mean", a2_avg_.mean(), "1", "time average of the measured a2 over the averaging window");
    out.scalar("a2_standard_error", a2_avg_.standard_error(), "1", "batch-means standard error of a2_mean");
    out.scalar("zeta_ratio_from_cumulants_mean", zeta_ratio_avg_.mean(), "1",
               "time average of 1 + 3a2/16 + a3/64 + 9a2^2/1024 (measured a2, a3) over the averaging window");
    out.scalar("zeta_ratio_from_cumulants_standard_error", zeta_ratio_avg_.standard_error(), "1",
               "batch-means standard error of zeta_ratio_from_cumulants_mean");
    out.scalar("temperature_ratio_to_haff", ratio, "1", "measured T / Haff's-law T at the last sample");
    char buf[256];
    std::snprintf(buf, sizeof buf, "hcs_theory: at t = %.4g tau0 (s = %.4g): T/T0 = %.6g, Haff's law %.6g (ratio %.4f)",
                  last_time_ / tau0_, last_s_, last_T_, haff(last_time_), ratio);
    out.summary(buf);
    std::snprintf(buf, sizeof buf, "hcs_theory: a2 in the averaging window (%zu samples): %.5f +- %.5f; first Sonine, 001 Eq. (2.16): %.5f (alpha = %g)",
                  a2_avg_.count(), a2_avg_.mean(), a2_avg_.standard_error(), a2_theory_, alpha_);
    out.summary(buf);
    std::snprintf(buf, sizeof buf, "hcs_theory: second Sonine (linearised): a2 = %.5f, a3 = %.5f, zeta*/zeta*_M = %.5f",
                  a2_second_, a3_second_, zeta_ratio_second_);
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
    zeta_ratio_avg_.save(out, "zeta_ratio_avg");
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
    zeta_ratio_avg_.load(in, "zeta_ratio_avg");
    window_.load(in);
  }

  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  double alpha_ = 1, a2_theory_ = 0, t0_ = 1, tau0_ = 1, zeta0_tau0_ = 0;
  double a2_second_ = 0, a3_second_ = 0, zeta_ratio_second_ = 1, tail_rate_ = 0;
  bool have_first_ = false;
  double t1_ = 1, time1_ = 0, last_T_ = 1, last_time_ = 0, last_s_ = 0;
  gdsmc::BatchMeans a2_avg_, zeta_ratio_avg_;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(HcsTheory)
