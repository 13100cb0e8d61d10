// Steady (and transient) uniform shear flow of the BGK-like kinetic model of refs. [4, 7] of paper
// 000, written beside the measured values. The derivation is in docs/bgk-usf.md.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {


// Steady state of the BGK-like model in units of the steady temperature (m = 1, T_s = 1) and of the
// relaxation rate beta nu = 1. x = zeta0/(beta nu), at = a/(beta nu) (docs/bgk-usf.md).
struct BgkSteady {
  double x = 0, at = 0, beta = 1;
  // Velocity moment <V_x^p V_y^q V_z^r> / T_s^{k/2}, k = p+q+r, from the triangular recursion
  //   (1 + k x/2) M[p,q,r] = M0[p,q,r] - at p M[p-1,q+1,r]          (docs/bgk-usf.md, Sec. 5)
  static double double_factorial_odd(int n) {  // (n-1)!! for even n, 0 for odd n
    if (n % 2) return 0.0;
    double r = 1;
    for (int k = n - 1; k > 1; k -= 2) r *= k;
    return r;
  }
  double moment(int p, int q, int r) const {
    const int k = p + q + r;
    const double m0 = double_factorial_odd(p) * double_factorial_odd(q) * double_factorial_odd(r);
    const double shear = p > 0 ? at * p * moment(p - 1, q + 1, r) : 0.0;
    return (m0 - shear) / (1.0 + 0.5 * k * x);
  }
  double v4() const {
    return moment(4, 0, 0) + moment(0, 4, 0) + moment(0, 0, 4) + 2.0 * (moment(2, 2, 0) + moment(2, 0, 2) + moment(0, 2, 2));
  }
  double v6() const {
    return moment(6, 0, 0) + moment(0, 6, 0) + moment(0, 0, 6) +
           3.0 * (moment(4, 2, 0) + moment(4, 0, 2) + moment(2, 4, 0) + moment(0, 4, 2) + moment(2, 0, 4) + moment(0, 2, 4)) +
           6.0 * moment(2, 2, 2);
  }
};

class BgkUsfTheory final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "bgk_usf_theory";
  static constexpr const char* version = "1.3.2";
  static constexpr const char* summary =
      "BGK-like kinetic model of USF (refs. [4, 7] of paper 000): steady a*, stresses, a2, a3 and the transient";
  static constexpr const char* documentation =
      "The kinetic model the paper compares with (000 Sec. V.B; Santos & Astillero, ref. [4]; Brey,\n"
      "Dufty & Santos, ref. [7]) replaces the IHS collision operator by\n"
      "  J -> -beta nu (f - f0) + (zeta0/2) d/dV . (V f),   nu = nT/eta0 = 1/tau_eta,\n"
      "tau_eta = c (5 sqrt(pi)/8) tau(T) (Eq. 2.18, c = viscosity_factor = 1.016), zeta0 of Eq. 2.16,\n"
      "beta = (1+alpha)/2 (or the EHS rule's 'rate_factor'). Its pressure tensor obeys closed moment\n"
      "equations; the steady state has, with x = zeta0/(beta nu) = (1-alpha^2) c 5/(12 beta),\n"
      "  (a/(beta nu))^2 = (3/2) x (1+x)^2,   a* = a tau_eta = beta a/(beta nu),\n"
      "  -P_xy/nT = (a/beta nu)/(1+x)^2,  (P_xx-P_yy)/nT = 3x/(1+x),  P_zz = P_yy,\n"
      "  eta* = 1/(beta (1+x)^2),  Psi_1 = -2/(beta^2 (1+x)^3),  T_s/T0 = (a tau0 c 5 sqrt(pi)/8 / a*)^2,\n"
      "and the higher moments follow from a triangular recursion, giving a2 and a3 (derivation:\n"
      "docs/bgk-usf.md). Written as scalars, with summary lines: the model's steady values bgk_a_star,\n"
      "bgk_minus_Pxy_over_nT, bgk_N1_over_nT, bgk_N2_over_nT, bgk_eta_star, bgk_Psi1, bgk_a2, bgk_a3\n"
      "[1] and bgk_temperature [T0], bgk_x = zeta0/(beta nu) and bgk_beta [1]; beside them the measured\n"
      "time averages over the samples in the run's steady averaging window (run.average_after;\n"
      "ctx.in_average_window, no parameter of its own), each as <name>_mean and <name>_standard_error:\n"
      "measured_a_star, measured_minus_Pxy_over_nT, measured_N1_over_nT, measured_N2_over_nT,\n"
      "measured_eta_star, measured_Psi1, measured_a2, measured_a3 [1] and measured_temperature [T0].\n"
      "The measured moments are the host's of each sample (ctx.moments).\n"
      "With transient: true the model's moment equations\n"
      "  dP_ij/dt = -a (delta_ix P_yj + delta_jx P_yi) - beta nu(T) (P_ij - nT delta_ij) - zeta0(T) P_ij\n"
      "are integrated (RK4, sub-steps <= 0.01/(beta nu + zeta0 + |a|)) from the pressure tensor measured\n"
      "at the first sample, giving the dotted BGK curves of Figs. 5, 7, 8, 10: series temperature_bgk\n"
      "[T0], minus_Pxy_over_nT_bgk, N1_over_nT_bgk, a_star_bgk, eta_star_bgk, s0_bgk (= (1/sqrt(pi))\n"
      "int dt/tau(T_bgk), the BGK clock the paper plots against s and s'/beta), beside the measured\n"
      "temperature, minus_Pxy_over_nT, N1_over_nT. Needs 'restitution' (collision rule) and reads\n"
      "'shear_rate' (uniform_shear or lees_edwards; 0 if none).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("viscosity_factor", "c in tau_eta = c (5 sqrt(pi)/8) tau (Eq. 2.18: 1.016)").range(0.5, 2.0).default_value(1.016),
            gdsmc::ParamSpec::choice("beta_model", {"from_collision", "linear", "quadratic"},
                                     "beta in the model: the rule's 'rate_factor' (else linear), (1+alpha)/2, or (1+alpha)(2+alpha)/6")
                .default_value("from_collision"),
            gdsmc::ParamSpec::boolean("transient", "integrate the model's moment equations beside the run").default_value(true)};
  }
  explicit BgkUsfTheory(const gdsmc::Params& p)
      : c_eta_(p.real("viscosity_factor")),
        beta_model_(p.string("beta_model")),
        transient_(p.boolean("transient")) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* alpha = board.find("restitution");
    if (!alpha) throw gdsmc::ParameterError("plugin", "bgk_usf_theory needs a collision rule that publishes 'restitution'");
    alpha_ = *alpha;
    const double* a = board.find("shear_rate");
    a_ = a ? *a : 0.0;
    const double* rf = board.find("rate_factor");
    if (beta_model_ == "quadratic") beta_ = (1.0 + alpha_) * (2.0 + alpha_) / 6.0;
    else if (beta_model_ == "from_collision" && rf) beta_ = *rf;
    else beta_ = 0.5 * (1.0 + alpha_);
    lambda0_ = sys.mean_free_path0;
    tau0_ = sys.time_unit0;
    t0_ = sys.initial_temperature;

    // Steady state (docs/bgk-usf.md, Secs. 3-4).
    st_.beta = beta_;
    st_.x = (1.0 - alpha_ * alpha_) * c_eta_ * 5.0 / (12.0 * beta_);
    st_.at = std::sqrt(1.5 * st_.x) * (1.0 + st_.x);
    const double x = st_.x, at = st_.at;
    steady_[0] = beta_ * at;                        // a*
    steady_[1] = at / ((1 + x) * (1 + x));          // -P_xy/nT
    steady_[2] = 3 * x / (1 + x);                   // (P_xx - P_yy)/nT
    steady_[3] = 0;                                 // (P_zz - P_yy)/nT
    steady_[4] = 1.0 / (beta_ * (1 + x) * (1 + x)); // eta*
    steady_[5] = -2.0 / (beta_ * beta_ * std::pow(1 + x, 3));  // Psi_1
    steady_[6] = st_.v4() / 15.0 - 1.0;            // a2
    steady_[7] = -st_.v6() / 105.0 + 1.0 + 3.0 * steady_[6];  // a3
    const double a_tau0 = a_ * tau0_;
    steady_T_ = a_ != 0 ? std::pow(a_tau0 * gdsmc::viscosity_time_over_tau(c_eta_) / steady_[0], 2) : std::nan("");

    if (transient_) {
      ids_ = {out.series("temperature_bgk", "T0", "BGK-model T/T0 from the moment equations"),
              out.series("minus_Pxy_over_nT_bgk", "1", "BGK-model -P_xy/nT"),
              out.series("N1_over_nT_bgk", "1", "BGK-model (P_xx - P_yy)/nT"),
              out.series("a_star_bgk", "1", "BGK-model a* = a tau_eta(T_bgk)"),
              out.series("eta_star_bgk", "1", "BGK-model eta* = -(P_xy/nT)/a*"),
              out.series("s0_bgk", "1", "(1/sqrt(pi)) int dt/tau(T_bgk) (Eq. 3.13 with the BGK temperature)"),
              out.series("temperature", "T0", "measured T/T0"),
              out.series("minus_Pxy_over_nT", "1", "measured -P_xy/nT"),
              out.series("N1_over_nT", "1", "measured (P_xx - P_yy)/nT")};
      for (const char* n : {"temperature", "minus_Pxy_over_nT", "N1_over_nT"})
        out.theory(std::string(n) + "_bgk", n, "docs/bgk-usf.md, Secs. 2 and 4");
      for (const char* n : {"a_star_bgk", "eta_star_bgk", "s0_bgk"}) out.theory(n, "", "docs/bgk-usf.md, Secs. 2 and 4");
    }
  }

  double tau_of(double T) const { return gdsmc::characteristic_time(lambda0_, T); }
  // State y = {P_xx, P_yy, P_zz, P_xy, s0} per unit density (m = 1).
  using State = std::array<double, 5>;
  State rhs(const State& y) const {
    const double T = (y[0] + y[1] + y[2]) / 3.0;
    const double tau = tau_of(T);
    const double nu = beta_ / (gdsmc::viscosity_time_over_tau(c_eta_) * tau);
    const double z = gdsmc::cooling_rate0_times_tau(alpha_) / tau;
    return {-2.0 * a_ * y[3] - nu * (y[0] - T) - z * y[0], -nu * (y[1] - T) - z * y[1], -nu * (y[2] - T) - z * y[2],
            -a_ * y[1] - nu * y[3] - z * y[3], 1.0 / (std::sqrt(M_PI) * tau)};
  }
  void advance(double t) {
    while (bgk_time_ < t) {
      const double T = (y_[0] + y_[1] + y_[2]) / 3.0;
      const double tau = tau_of(T);
      const double rate = beta_ / (gdsmc::viscosity_time_over_tau(c_eta_) * tau) + gdsmc::cooling_rate0_times_tau(alpha_) / tau + std::fabs(a_);
      const double h = std::min(t - bgk_time_, 0.01 / rate);
      auto add = [](const State& u, const State& k, double c) {
        State r;
        for (int i = 0; i < 5; ++i) r[i] = u[i] + c * k[i];
        return r;
      };
      const State k1 = rhs(y_), k2 = rhs(add(y_, k1, 0.5 * h)), k3 = rhs(add(y_, k2, 0.5 * h)), k4 = rhs(add(y_, k3, h));
      for (int i = 0; i < 5; ++i) y_[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      bgk_time_ += h;
    }
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const double T = m.temperature;
    const double pxy = -m.second[0][1] / T, n1 = (m.second[0][0] - m.second[1][1]) / T;
    if (transient_) {
      if (!started_) {
        y_ = {m.second[0][0], m.second[1][1], m.second[2][2], m.second[0][1], 0.0};
        bgk_time_ = ctx.time;
        started_ = true;
      } else {
        advance(ctx.time);
      }
      const double Tb = (y_[0] + y_[1] + y_[2]) / 3.0;
      const double a_star = a_ * gdsmc::viscosity_time_over_tau(c_eta_) * tau_of(Tb);
      const double s[kSeries] = {Tb / t0_, -y_[3] / Tb, (y_[0] - y_[1]) / Tb, a_star, -y_[3] / Tb / a_star, y_[4], T / t0_, pxy, n1};
      for (int k = 0; k < kSeries; ++k) sums_[k] += s[k];
      ++samples_;
    }
    if (ctx.in_average_window) {
      const double a_star = a_ * gdsmc::viscosity_time_over_tau(c_eta_) * tau_of(T);
      const double n2 = (m.second[2][2] - m.second[1][1]) / T;
      const double v[kMeasured] = {a_star, pxy, n1, n2, pxy / a_star, -n1 / (a_star * a_star), m.a2(), m.a3(), T / t0_};
      for (int k = 0; k < kMeasured; ++k) measured_[k].add(v[k]);
    }
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    if (!transient_) return;
    for (int k = 0; k < kSeries; ++k) {
      out.append(ids_[k], samples_ ? sums_[k] / static_cast<double>(samples_) : std::nan(""));
      sums_[k] = 0;
    }
    samples_ = 0;
  }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    static const char* names[kMeasured] = {"a_star", "minus_Pxy_over_nT", "N1_over_nT", "N2_over_nT", "eta_star", "Psi1", "a2", "a3", "temperature"};
    static const char* docs[kMeasured] = {"a* = a tau_eta (Eq. 5.2)", "-P_xy/nT", "(P_xx - P_yy)/nT", "(P_zz - P_yy)/nT",
                                          "eta* = -(P_xy/nT)/a*", "Psi_1 = (P_yy - P_xx)/(nT a*^2)", "fourth cumulant a2",
                                          "sixth cumulant a3", "T/T0"};
    for (int k = 0; k < kMeasured; ++k) {
      const double bgk = k < 8 ? steady_[k] : steady_T_;
      const std::string n = names[k];
      out.scalar("bgk_" + n, bgk, k == 8 ? "T0" : "1", std::string("steady BGK-model ") + docs[k] + " (docs/bgk-usf.md)");
      out.scalar("measured_" + n + "_mean", measured_[k].mean(), k == 8 ? "T0" : "1",
                 std::string("measured ") + docs[k] + " averaged over the averaging window");
      out.scalar("measured_" + n + "_standard_error", measured_[k].standard_error(), k == 8 ? "T0" : "1",
                 "batch-means standard error");
      // The steady value is theory for the measured mean and, at long times, for the series.
      const bool series = transient_ && (k == 1 || k == 2 || k == 8);
      out.theory("bgk_" + n, "measured_" + n + "_mean" + (series ? ", " + n : ""),
                 k == 6 || k == 7 ? "docs/bgk-usf.md, Sec. 5" : "docs/bgk-usf.md, Sec. 3");
    }
    out.scalar("bgk_x", st_.x, "1", "zeta0/(beta nu) of the model");
    out.scalar("bgk_beta", beta_, "1", "beta used in the model");
    out.theory("bgk_x", "", "docs/bgk-usf.md, Sec. 3");
    out.theory("bgk_beta", "", "beta = (1+alpha)/2, 000 Sec. V.B (or the beta_model / the rule's rate_factor)");
    char buf[400];
    std::snprintf(buf, sizeof buf, "bgk_usf_theory: alpha = %g, beta = %g: steady BGK (docs/bgk-usf.md) vs measured in the averaging window (%zu samples):",
                  alpha_, beta_, measured_[0].count());
    out.summary(buf);
    for (int k = 0; k < kMeasured; ++k) {
      const double bgk = k < 8 ? steady_[k] : steady_T_;
      std::snprintf(buf, sizeof buf, "  %-18s BGK %9.5f   measured %9.5f +- %.5f", names[k], bgk, measured_[k].mean(),
                    measured_[k].standard_error());
      out.summary(buf);
    }
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("started", started_);
    out.write("bgk_state", y_.data(), y_.size());
    out.write("bgk_time", bgk_time_);
    out.write("sums", sums_, kSeries);
    out.write("samples", static_cast<std::uint64_t>(samples_));
    for (int k = 0; k < kMeasured; ++k) measured_[k].save(out, "measured" + std::to_string(k));
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("started", started_);
    in.read("bgk_state", y_.data(), y_.size());
    in.read("bgk_time", bgk_time_);
    in.read("sums", sums_, kSeries);
    std::uint64_t samples = 0;
    in.read("samples", samples);
    samples_ = static_cast<std::size_t>(samples);
    for (int k = 0; k < kMeasured; ++k) measured_[k].load(in, "measured" + std::to_string(k));
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  static constexpr int kSeries = 9;
  static constexpr int kMeasured = 9;
  double c_eta_;
  std::string beta_model_;
  bool transient_;
  double alpha_ = 1, a_ = 0, beta_ = 1, lambda0_ = 1, tau0_ = 1, t0_ = 1;
  BgkSteady st_;
  double steady_[8] = {};
  double steady_T_ = 0;
  std::array<std::size_t, kSeries> ids_{};
  bool started_ = false;
  State y_{};
  double bgk_time_ = 0;
  double sums_[kSeries] = {};
  std::size_t samples_ = 0;
  gdsmc::BatchMeans measured_[kMeasured];
};

}  // namespace

GDSMC_PLUGIN(BgkUsfTheory)
