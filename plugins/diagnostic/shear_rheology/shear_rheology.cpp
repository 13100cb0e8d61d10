// Rheology of uniform shear flow: a* = a tau_eta, eta*, Psi_1, Psi_2 and the viscous heating rate.
#include <cmath>
#include <cstdio>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class ShearRheology final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "shear_rheology";
  static constexpr const char* version = "1.3.2";
  static constexpr const char* summary = "USF rheology: a* = a tau_eta, -P_xy/nT, normal stress differences, eta*, Psi_1, Psi_2";
  static constexpr const char* documentation =
      "Uses the shear rate a published as 'shear_rate' (uniform_shear forcing, or a lees_edwards\n"
      "boundary in a slab) and, at each sample,\n"
      "the temperature T and kinetic pressure tensor P = n m <V V> of the particles (paper 000,\n"
      "Eqs. 4.15-4.16; in a slab T-bar and P-bar of Eqs. 4.8-4.9, V relative to each layer's flow), from\n"
      "the host's moments of the sample (ctx.moments):\n"
      "  tau(T)   = lambda0 / sqrt(2T/m)                       (Eqs. 2.12, 4.22)\n"
      "  tau_eta  = 1.016 (5 sqrt(pi)/8) tau(T)                  (Eq. 2.18)\n"
      "  a*       = a tau_eta                                   (Eq. 5.2)\n"
      "  eta*     = -(P_xy/nT) / a*,  Psi_1 = (P_yy - P_xx)/(nT a*^2),  Psi_2 = (P_zz - P_yy)/(nT a*^2)  (Sec. V.C)\n"
      "  heating_rate = -(2a/3n) P_xy / T  [1/tau0], the viscous heating per unit T; heating_rate_tau is\n"
      "  the same times tau(T). In a steady state heating_rate = zeta (energy balance): compare with\n"
      "  cooling_rate's zeta (IHS) or with zeta0 tau = 2(1-alpha^2)/(3 sqrt(pi)) (EHS with gamma = zeta0/2).\n"
      "Series (window means): temperature [T0], a_star, minus_Pxy_over_nT, N1_over_nT = (P_xx-P_yy)/nT,\n"
      "N2_over_nT = (P_zz-P_yy)/nT, eta_star, Psi1, Psi2, heating_rate, heating_rate_tau. After the run:\n"
      "<column>_mean and <column>_standard_error over the samples in the run's steady averaging window\n"
      "(run.average_after; ctx.in_average_window, no parameter of its own) (batch means), and a\n"
      "summary line. For an elastic gas (published restitution 1) also eta_star_chapman_enskog (1.016034\n"
      "eta0 in this unit) and eta_star_thermostatted_bgk (times 1/(1+g)^2, g(1+g)^2 = 2a*^2/3: a gas held at\n"
      "fixed T).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit ShearRheology(const gdsmc::Params&) {}

  static constexpr int kColumns = 10;
  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    // What it measures is a steady state: `gdsmc plot` draws the steady means of its series.
    out.attribute("stationary", "all");
    const double* a = board.find("shear_rate");
    if (!a)
      throw gdsmc::ParameterError("plugin", "shear_rheology needs a plugin that publishes 'shear_rate' (uniform_shear or lees_edwards)");
    a_ = *a;
    const double* alpha = board.find("restitution");
    restitution_ = alpha ? *alpha : std::nan("");
    lambda0_ = sys.mean_free_path0;
    tau0_ = sys.time_unit0;
    t0_ = sys.initial_temperature;
    names_ = {"temperature", "a_star", "minus_Pxy_over_nT", "N1_over_nT", "N2_over_nT", "eta_star", "Psi1", "Psi2",
              "heating_rate", "heating_rate_tau"};
    window_.declare(out, {{names_[0], "T0", "temperature T/T0 (Eq. 4.15)"},
                          {names_[1], "1", "reduced shear rate a* = a tau_eta(T) (Eqs. 2.18, 5.2)"},
                          {names_[2], "1", "reduced shear stress -P_xy/(nT)"},
                          {names_[3], "1", "(P_xx - P_yy)/(nT)"},
                          {names_[4], "1", "(P_zz - P_yy)/(nT)"},
                          {names_[5], "1", "eta* = -(P_xy/nT)/a* (Sec. V.C)"},
                          {names_[6], "1", "Psi_1 = (P_yy - P_xx)/(nT a*^2) (Sec. V.C)"},
                          {names_[7], "1", "Psi_2 = (P_zz - P_yy)/(nT a*^2) (Sec. V.C)"},
                          {names_[8], "1/tau0", "viscous heating rate -(2a/3n) P_xy / T"},
                          {names_[9], "1", "heating_rate times tau(T) = lambda0/sqrt(2T/m)"}});
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", a_ * tau0_);
    out.attribute("shear_rate_tau0", buf);
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const double T = m.temperature;
    const double tau = gdsmc::characteristic_time(lambda0_, T);
    const double a_star = a_ * gdsmc::viscosity_time_over_tau() * tau;  // a tau_eta, Eqs. 2.18, 5.2
    const double pxy = m.second[0][1] / T, n1 = (m.second[0][0] - m.second[1][1]) / T, n2 = (m.second[2][2] - m.second[1][1]) / T;
    const double heating = -(2.0 * a_ / 3.0) * m.second[0][1] / T;  // P/n = <V V> (m = 1)
    const double v[kColumns] = {T / t0_, a_star, -pxy, n1, n2, -pxy / a_star, -n1 / (a_star * a_star), n2 / (a_star * a_star),
                                heating * tau0_, heating * tau};
    window_.add(std::vector<double>(v, v + kColumns));
    if (ctx.in_average_window)
      for (int k = 0; k < kColumns; ++k) avg_[k].add(v[k]);
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    for (int k = 0; k < kColumns; ++k) {
      out.scalar(names_[k] + "_mean", avg_[k].mean(), k == 0 ? "T0" : k == 8 ? "1/tau0" : "1", names_[k] + " averaged over the averaging window");
      out.scalar(names_[k] + "_standard_error", avg_[k].standard_error(), k == 0 ? "T0" : k == 8 ? "1/tau0" : "1",
                 "batch-means standard error of " + names_[k] + "_mean");
    }
    if (restitution_ == 1.0) {
      // The elastic gas's theory beside eta*: Chapman-Enskog at a* -> 0 in this eta*'s unit (tau_eta
      // with 1.016), and with the O(a*^2) shear thinning of a thermostatted gas at the measured a*.
      const double ce = gdsmc::chapman_enskog_viscosity_factor / 1.016;
      out.scalar("eta_star_chapman_enskog", ce, "1",
                 "Chapman-Enskog eta of elastic hard spheres (1.016034 eta0) in the unit of eta_star: the a* -> 0 limit");
      out.scalar("eta_star_thermostatted_bgk", ce * gdsmc::thermostatted_shear_viscosity_ratio(avg_[1].mean()), "1",
                 "eta_star_chapman_enskog times eta(a*)/eta(0) of a thermostatted elastic gas (Grad/BGK, "
                 "1 - 4a*^2/3 + ...) at a_star_mean: the value for elastic USF at fixed T");
      out.theory("eta_star_chapman_enskog", "eta_star, eta_star_mean", "Chapman-Enskog, 1.016034 eta0 (000 Eq. 2.18)");
      out.theory("eta_star_thermostatted_bgk", "eta_star, eta_star_mean", "Grad/BGK thermostatted USF, 1 - 4a*^2/3 + ...");
    }
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "shear_rheology: in the averaging window (a tau0 = %g, %zu samples): a* = %.4f +- %.4f, -P_xy/nT = %.4f +- %.4f, "
                  "(P_xx-P_yy)/nT = %.4f +- %.4f, (P_zz-P_yy)/nT = %.4f +- %.4f, eta* = %.4f, Psi1 = %.4f, Psi2 = %.4f",
                  a_ * tau0_, avg_[1].count(), avg_[1].mean(), avg_[1].standard_error(), avg_[2].mean(),
                  avg_[2].standard_error(), avg_[3].mean(), avg_[3].standard_error(), avg_[4].mean(), avg_[4].standard_error(),
                  avg_[5].mean(), avg_[6].mean(), avg_[7].mean());
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    window_.save(out);
    for (int k = 0; k < kColumns; ++k) avg_[k].save(out, "avg." + names_[k]);
  }
  void load_state(gdsmc::StateReader& in) override {
    window_.load(in);
    for (int k = 0; k < kColumns; ++k) avg_[k].load(in, "avg." + names_[k]);
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  double a_ = 0, lambda0_ = 1, tau0_ = 1, t0_ = 1, restitution_ = 0;
  std::vector<std::string> names_;
  gdsmc::WindowAverage window_;
  gdsmc::BatchMeans avg_[kColumns];
};

}  // namespace

GDSMC_PLUGIN(ShearRheology)

// What `gdsmc conformance` runs it in when no --context is given.
// A uniformly sheared gas (the forcing publishes the shear rate).
GDSMC_CONFORMANCE_CONTEXT(
    "forcings: [{plugin: uniform_shear, shear_rate: 0.1}]")
