// The homogeneous steady heat flow of paper 001 (a weak heat-flux force eps* along x, Sec. III):
// q_x, kappa'/kappa0 (or kappa/kappa0), the Sonine coefficients b_k by Eqs. 3.10 and 3.12, the
// marginal g(c_x), its odd part g1, phi(c_x^2) of Eq. 4.3 beside its truncated Sonine series
// (Eq. 4.5), beta1(X) of Eq. 4.6, and the first-Sonine theory of Sec. II (d = 3).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- First-Sonine theory, d = 3 (paper 001, Sec. II) ---------------------------------------
// a2 of the HCS, Eq. 2.16 with d = 3: 25 + 24 d = 97, 57 - 8 d = 33.
double theory_a2(double alpha) {
  return 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha) / (97.0 - 33.0 * alpha - 2.0 * (1.0 - alpha) * alpha * alpha);
}
// zeta0 / nu0, Eq. 2.14 with d = 3: (d + 2)/(4 d) = 5/12.
double theory_zeta_over_nu0(double alpha) {
  return 5.0 / 12.0 * (1.0 - alpha * alpha) * (1.0 + 3.0 * theory_a2(alpha) / 16.0);
}
// nu_kappa / nu0 = nu_kappa' / nu0, Eq. 2.46 with d = 3: (d-1)/2 = 1, (3/16)(d+8) = 33/16,
// 4 + 5d - 3(4 - d) alpha = 19 - 3 alpha.
double theory_nu_kappa_over_nu0(double alpha) {
  return (1.0 + alpha) / 3.0 * (1.0 + 33.0 / 16.0 * (1.0 - alpha) + (19.0 - 3.0 * alpha) / 512.0 * theory_a2(alpha));
}
// kappa' / kappa0: Eq. 2.42 over Eq. 2.47 ((d+2)/2 over d(d+2)/(2(d-1)) = 2/3 for d = 3).
double theory_kappa_prime(double alpha) {
  return 2.0 / 3.0 * (1.0 + 1.5 * theory_a2(alpha)) / (theory_nu_kappa_over_nu0(alpha) - 1.5 * theory_zeta_over_nu0(alpha));
}
// kappa / kappa0: Eq. 2.41 over Eq. 2.47.
double theory_kappa(double alpha) {
  return 2.0 / 3.0 * (1.0 + 2.0 * theory_a2(alpha)) / (theory_nu_kappa_over_nu0(alpha) - 2.0 * theory_zeta_over_nu0(alpha));
}
// b1 = (kappa / kappa0) (15 sqrt(pi) / 16): Eq. 2.45 with kappa0 = (75 sqrt(pi)/64) n lambda v0 (Eq. 2.47).
constexpr double kB1PerConductivity = 15.0 / 16.0;  // times sqrt(pi)
// The first-Sonine curves over alpha in [0, 1] (Figs. 3-4 of 001; kappa and mu beside them), with
// b1 (Eq. 2.45) of the run's route.
void write_theory_curves(gdsmc::OutputSink& out, bool kappa_route) {
  constexpr std::size_t kPoints = 101;
  std::vector<double> alpha(kPoints), kp(kPoints), kk(kPoints), mu(kPoints), b1(kPoints);
  for (std::size_t i = 0; i < kPoints; ++i) {
    alpha[i] = static_cast<double>(i) / static_cast<double>(kPoints - 1);
    kp[i] = theory_kappa_prime(alpha[i]);
    kk[i] = theory_kappa(alpha[i]);
    mu[i] = 2.0 * (kk[i] - kp[i]);
    b1[i] = kB1PerConductivity * std::sqrt(kPi) * (kappa_route ? kk[i] : kp[i]);
  }
  out.array("theory_alpha_grid", alpha, {kPoints}, "1", "restitution coefficients alpha of the curves theory_*_vs_alpha");
  out.array("theory_kappa_prime_over_kappa0_vs_alpha", kp, {kPoints}, "1", "first-Sonine kappa'/kappa0 at theory_alpha_grid, Eq. 2.42 over Eq. 2.47");
  out.array("theory_kappa_over_kappa0_vs_alpha", kk, {kPoints}, "1", "first-Sonine kappa/kappa0 at theory_alpha_grid, Eq. 2.41 over Eq. 2.47");
  out.array("theory_mu_n_over_T_kappa0_vs_alpha", mu, {kPoints}, "1",
            "first-Sonine mu n/(T kappa0) = 2 (kappa - kappa')/kappa0 at theory_alpha_grid, Eq. 2.38");
  out.array("theory_b1_vs_alpha", b1, {kPoints}, "1",
            "first-Sonine b1 = (15 sqrt(pi)/16) x the route's kappa/kappa0 at theory_alpha_grid (Eq. 2.45)");
  for (const char* curve : {"theory_kappa_prime_over_kappa0_vs_alpha", "theory_kappa_over_kappa0_vs_alpha",
                            "theory_mu_n_over_T_kappa0_vs_alpha", "theory_b1_vs_alpha"})
    out.axis(curve, "theory_alpha_grid");
}

// ---- Generalized Laguerre polynomials and Sonine prefactors ---------------------------------
// Coefficients of L_k^(a)(x) = sum_{i=0..k} (-1)^i binom(k + a, k - i) x^i / i!  (k <= 3).
std::array<double, 4> laguerre(int k, double a) {
  std::array<double, 4> c{0, 0, 0, 0};
  for (int i = 0; i <= k; ++i) {
    double binom = 1.0;  // binom(k + a, k - i) for real k + a
    for (int l = 0; l < k - i; ++l) binom *= (k + a - l) / (l + 1.0);
    double factorial = 1.0;
    for (int l = 2; l <= i; ++l) factorial *= l;
    c[i] = (i % 2 ? -1.0 : 1.0) * binom / factorial;
  }
  return c;
}
// 2 Gamma(1 + a) k! / Gamma(k + 1 + a): Eq. 3.10 with a = d/2 = 3/2 (4/5, 16/35, 32/105) and
// Eq. 3.12 with a = 1/2 (4/3, 16/15, 32/35).
double sonine_prefactor(int k, double a) {
  return 2.0 * std::tgamma(1.0 + a) * std::tgamma(k + 1.0) / std::tgamma(k + 1.0 + a);
}

class HeatFlux final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "heat_flux";
  static constexpr const char* version = "1.3.1";
  static constexpr const char* summary =
      "Heat-flux state of paper 001: q_x, kappa'/kappa0 (or kappa/kappa0), b_k (Eqs. 3.10, 3.12), g1, phi, beta1 and first-Sonine theory";
  static constexpr const char* documentation =
      "The measurements of paper 001 (homogeneous steady heat flow driven by a weak heat-flux force of\n"
      "reduced strength eps* = lambda eps along x, Sec. III; d = 3, m = 1). Needs a heat-flux forcing\n"
      "(heat_flux_force) publishing 'heat_flux_epsilon_star' (eps* > 0) and 'heat_flux_route' (0: the\n"
      "force G' of Eq. 3.2, measuring kappa'; 1: the force G of Eq. 3.16 with the cloning-annihilation\n"
      "term of Eq. 3.17, measuring kappa); refuses a run without it. 'restitution' (alpha, from the\n"
      "collision rule) is used for the theory; without it alpha = 1. lambda = 1/(sqrt 2 pi n sigma^2)\n"
      "is the run's lambda0, eps = eps*/lambda. Reduced velocity c = (v - u)/v0, v0 = sqrt(2T/m)\n"
      "(Eq. 2.11), u and T the local flow and temperature of the sampled state (ctx.moments).\n"
      "Series (each record: the mean over the samples since the previous record; the host adds\n"
      "<name>.steady_mean/.steady_stderr over run.average_after):\n"
      "  q_x [n0 T0 sqrt(2T0/m)]: heat flux (m/2) n <|V|^2 V_x> (Eq. 2.7), n = n0 the system density;\n"
      "  conductivity_over_kappa0 [1]: -q_x / (T eps kappa0(T)) (Eq. 3.9), kappa0 = (15/4) n T/(m nu0)\n"
      "    (Eq. 2.47), nu0 = (16/5) sqrt(pi) n sigma^2 sqrt(T/m) (Eq. 2.15): kappa'(t)/kappa0 on route 0,\n"
      "    kappa(t)/kappa0 on route 1 (the group attribute 'route' says kappa_prime or kappa). It equals\n"
      "    (16/(15 sqrt pi)) b1_full exactly (Eq. 2.45);\n"
      "  b1_full, b2_full, b3_full [1]: b_k = [2 Gamma(5/2) k!/Gamma(k+5/2)] <c_x L_k^(3/2)(c^2)>/eps*\n"
      "    (Eq. 3.10; prefactors 4/5, 16/35, 32/105);\n"
      "  b1_marginal, b2_marginal, b3_marginal [1]: b_k = [2 Gamma(3/2) k!/Gamma(k+3/2)]\n"
      "    <c_x L_k^(1/2)(c_x^2)>/eps* (Eq. 3.12; 4/3, 16/15, 32/35). L_k^(a)(x) = sum_i (-1)^i\n"
      "    binom(k+a, k-i) x^i/i!. Eqs. 3.10 and 3.12 agree in the linear regime (Appendix).\n"
      "Steady scalars (samples with ctx.in_average_window): <series>_mean and <series>_standard_error\n"
      "(batch means over the samples of the window; with run.realizations > 1 the host's _stderr\n"
      "over realizations is the honest error).\n"
      "Histograms of the window (c_max, bins: edges c_x = -c_max .. c_max, 0 an edge), values [1]:\n"
      "  g: marginal density of c_x, counts/(samples N width), integrating to 1 over all c_x (the\n"
      "    scalar fraction_outside is the part beyond |c_x| >= c_max);\n"
      "  g1: [g(c_x) - g(-c_x)]/2 (Eq. 3.15), and g1_error;\n"
      "  on the positive half (edges 0 .. c_max): phi = g1 sqrt(pi) exp(c_x^2)/(c_x eps*) (Eq. 4.3 with g\n"
      "    in c_x units), estimated per bin as g1's bin average over the bin average of\n"
      "    eps* c_x exp(-c_x^2)/sqrt(pi) (exact integral; no O(width^2) bias from the Gaussian), i.e.\n"
      "    phi at the bin centre; phi_error; phi_1, phi_2, phi_3: the truncated series\n"
      "    sum_{k<=p} b_k L_k^(1/2)(c_x^2) at the bin centres (Eq. 4.5) with the steady b_k_full.\n"
      "    g1_error and phi_error are counting (multinomial) errors of the pooled counts, treating every\n"
      "    particle of every sample as independent: a lower bound when samples are correlated; with\n"
      "    run.realizations > 1 the host writes g1_stderr, phi_stderr over realizations.\n"
      "beta1 (Eq. 4.6), computed from the particles, not the histogram: with phi of Eq. 4.3 the\n"
      "integrand reduces to beta1(X) = (4/(3 eps*)) <c_x (3/2 - c_x^2) 1{|c_x| < sqrt X}>. Arrays over\n"
      "the positive-half edges: beta1_X [1] (X = c_x^2 of each edge), beta1 [1], beta1_over_b1 [1]\n"
      "(divided by beta1_infinity, the X -> infinity limit = b1 of Eq. 3.12 over the window, also a\n"
      "scalar); scalar beta1_6_over_b1 = beta1(6)/beta1(infinity) (001: 0.87 at alpha = 1, 0.66 at 0.3).\n"
      "Theory scalars (first Sonine, d = 3, at alpha) [1]: theory_a2 (Eq. 2.16), theory_zeta0_over_nu0\n"
      "(Eq. 2.14), theory_nu_kappa_over_nu0 (Eq. 2.46), theory_kappa_prime_over_kappa0 (Eq. 2.42/2.47),\n"
      "theory_kappa_over_kappa0 (Eq. 2.41/2.47), theory_mu_n_over_T_kappa0 = 2(kappa - kappa')/kappa0\n"
      "(Eq. 2.38), theory_conductivity_over_kappa0 (the route's), theory_b1 = (15 sqrt(pi)/16) x the\n"
      "route's value (Eq. 2.45), elastic_reference_kappa_over_kappa0 = 1.025218 (converged Sonine,\n"
      "001 Ref. 37), nu0_tau0 = nu0(T0) tau0 (Eq. 2.15; 8/(5 sqrt pi)). Theory arrays: theory_alpha_grid [1]\n"
      "(101 alpha in [0, 1]) and over it theory_kappa_prime_over_kappa0_vs_alpha, theory_kappa_over_kappa0_vs_alpha,\n"
      "theory_mu_n_over_T_kappa0_vs_alpha, theory_b1_vs_alpha (the route's) [1]. Every theory dataset carries\n"
      "role = theory and its equation. Also epsilon_star, route (0 or 1), restitution, samples_in_window.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("c_max", "histogram range |c_x| < c_max (reduced velocity c = V/sqrt(2T/m))")
                .range(2.0, 8.0)
                .default_value(4.0),
            gdsmc::ParamSpec::integer("bins", "bins of the c_x histograms over [-c_max, c_max] (even, so that c_x = 0 is an edge)")
                .range(10.0, 1000.0)
                .default_value(80)};
  }
  explicit HeatFlux(const gdsmc::Params& p) : c_max_(p.real("c_max")), bins_(static_cast<std::size_t>(p.integer("bins"))) {
    if (bins_ % 2 != 0) throw gdsmc::ParameterError("bins", "bins must be even so that c_x = 0 is a bin edge (g1 of Eq. 3.15 mirrors bins)");
    half_ = bins_ / 2;
    width_ = 2.0 * c_max_ / static_cast<double>(bins_);
    counts_.assign(bins_, 0.0);
    beta_bins_.assign(half_, 0.0);
  }

  enum Column { kQx, kConductivity, kB1F, kB2F, kB3F, kB1M, kB2M, kB3M, kColumns };

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    // What it measures is a steady state: `gdsmc plot` draws the steady means of its series.
    out.attribute("stationary", "all");
    const double* eps = board.find("heat_flux_epsilon_star");
    if (!eps) throw gdsmc::ParameterError("plugin", "heat_flux needs a heat-flux forcing: add heat_flux_force to forcings");
    if (!(*eps > 0) || !std::isfinite(*eps))
      throw gdsmc::ParameterError("plugin", "heat_flux needs a positive heat_flux_epsilon_star (published " + std::to_string(*eps) +
                                                 "); every b_k and kappa is divided by it");
    eps_star_ = *eps;
    const double* route = board.find("heat_flux_route");
    route_ = route ? static_cast<int>(std::lround(*route)) : 0;
    if (route && (*route != 0.0 && *route != 1.0))
      throw gdsmc::ParameterError("plugin", "heat_flux: heat_flux_route must be 0 (kappa', force G' of Eq. 3.2) or 1 (kappa, "
                                            "Eq. 3.16/3.17), not " + std::to_string(*route));
    const double* alpha = board.find("restitution");
    alpha_ = alpha ? *alpha : 1.0;
    n_ = sys.number_density;
    sigma_ = sys.sigma;
    lambda_ = sys.mean_free_path0;
    t0_ = sys.initial_temperature;
    slab_ = sys.geometry == gdsmc::Geometry::slab;
    for (int k = 1; k <= 3; ++k) {
      full_poly_[k - 1] = laguerre(k, 1.5);
      marg_poly_[k - 1] = laguerre(k, 0.5);
      full_pref_[k - 1] = sonine_prefactor(k, 1.5);
      marg_pref_[k - 1] = sonine_prefactor(k, 0.5);
    }
    const bool kappa = route_ == 1;
    out.attribute("route", kappa ? "kappa" : "kappa_prime");
    out.attribute("route_description", kappa ? "kappa/kappa0: force G of Eq. 3.16 with the cloning-annihilation term of Eq. 3.17"
                                             : "kappa'/kappa0: force G' of Eq. 3.2 (kappa' = kappa - n mu / 2T)");
    const std::string what = kappa ? "kappa(t)/kappa0" : "kappa'(t)/kappa0";
    const std::vector<std::array<std::string, 3>> cols = {
        {"q_x", gdsmc::units::heat_flux, "heat flux q_x = (m/2) n <|V|^2 V_x> (Eq. 2.7)"},
        {"conductivity_over_kappa0", "1",
         what + " = -q_x/(T eps kappa0(T)) (Eq. 3.9), kappa0 = (15/4) n T/(m nu0) (Eq. 2.47); route attribute: " +
             (kappa ? "kappa" : "kappa_prime")},
        {"b1_full", "1", "b_1 = (4/5) <c_x L_1^(3/2)(c^2)>/eps* (Eq. 3.10)"},
        {"b2_full", "1", "b_2 = (16/35) <c_x L_2^(3/2)(c^2)>/eps* (Eq. 3.10)"},
        {"b3_full", "1", "b_3 = (32/105) <c_x L_3^(3/2)(c^2)>/eps* (Eq. 3.10)"},
        {"b1_marginal", "1", "b_1 = (4/3) <c_x L_1^(1/2)(c_x^2)>/eps* (Eq. 3.12)"},
        {"b2_marginal", "1", "b_2 = (16/15) <c_x L_2^(1/2)(c_x^2)>/eps* (Eq. 3.12)"},
        {"b3_marginal", "1", "b_3 = (32/35) <c_x L_3^(1/2)(c_x^2)>/eps* (Eq. 3.12)"}};
    for (int k = 0; k < kColumns; ++k) {
      names_[k] = cols[k][0];
      units_[k] = cols[k][1];
      docs_[k] = cols[k][2];
      ids_[k] = out.series(cols[k][0], cols[k][1], cols[k][2]);
    }
    // Theory beside the data (first Sonine, d = 3).
    const double kp = theory_kappa_prime(alpha_), kk = theory_kappa(alpha_);
    const double route_value = kappa ? kk : kp;
    theory_ = route_value;
    auto put = [&](const char* n, double v, const char* doc) { out.scalar(n, v, "1", doc); };
    put("epsilon_star", eps_star_, "reduced field strength eps* = lambda eps (published by the forcing)");
    put("route", route_, "0: kappa' (force G', Eq. 3.2); 1: kappa (force G, Eqs. 3.16-3.17)");
    put("restitution", alpha_, "coefficient of normal restitution alpha used by the theory (1 if not published)");
    put("theory_a2", theory_a2(alpha_), "HCS fourth cumulant a2, Eq. 2.16 (d = 3)");
    put("theory_zeta0_over_nu0", theory_zeta_over_nu0(alpha_), "zeta0/nu0, Eq. 2.14 (d = 3)");
    put("theory_nu_kappa_over_nu0", theory_nu_kappa_over_nu0(alpha_), "nu_kappa/nu0 = nu_kappa'/nu0 (first Sonine), Eq. 2.46");
    put("theory_kappa_prime_over_kappa0", kp, "first-Sonine kappa'/kappa0, Eq. 2.42 over Eq. 2.47");
    put("theory_kappa_over_kappa0", kk, "first-Sonine kappa/kappa0, Eq. 2.41 over Eq. 2.47");
    put("theory_mu_n_over_T_kappa0", 2.0 * (kk - kp), "first-Sonine mu n/(T kappa0) = 2 (kappa - kappa')/kappa0, Eq. 2.38");
    put("theory_conductivity_over_kappa0", route_value, "first-Sonine value of this route (kappa' on route 0, kappa on route 1)");
    put("theory_b1", kB1PerConductivity * std::sqrt(kPi) * route_value,
        "first-Sonine b1 = (15 sqrt(pi)/16) x the route's kappa/kappa0 (Eq. 2.45)");
    put("elastic_reference_kappa_over_kappa0", gdsmc::chapman_enskog_conductivity_factor, "converged Sonine kappa/kappa0 at alpha = 1 (001, Ref. 37)");
    // nu0 (Eq. 2.15) at T0 times tau0 = lambda0 / sqrt(2 T0/m): the time unit's collision frequency.
    put("nu0_tau0", 16.0 / 5.0 * std::sqrt(kPi) * n_ * sigma_ * sigma_ * std::sqrt(t0_) * lambda_ / std::sqrt(2.0 * t0_),
        "nu0 tau0 at T0 (Eq. 2.15, tau0 = lambda0/sqrt(2 T0/m)): zeta tau0 = (zeta0/nu0) nu0 tau0");
    write_theory_curves(out, kappa);
    for (double& s : sums_) s = 0;
    samples_ = 0;
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::SampledMoments& sm = *ctx.moments;
    const gdsmc::VelocityMoments& m = sm.local;
    const double T = m.temperature;
    if (p.count == 0 || !(T > 0)) return;
    const double v0 = std::sqrt(2.0 * T);  // m = 1 (Eq. 2.11)
    const double scale = 1.0 / v0;
    const bool window = ctx.in_average_window;
    const double wt = gdsmc::bracket_weight(ctx);  // 1/2 for each side of a bracketed step: counts stay one per particle a step
    const double* cell_u = sm.cell_mean_velocity;
    double s_c2cx = 0, s_full[3] = {0, 0, 0}, s_marg[3] = {0, 0, 0};
    double outside = 0, beta_out = 0, beta_six = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      const double* u = (slab_ && cell_u) ? cell_u + 3 * static_cast<std::size_t>(p.cell[i]) : m.mean;  // the local flow
      const double cx = (p.vx[i] - u[0]) * scale, cy = (p.vy[i] - u[1]) * scale, cz = (p.vz[i] - u[2]) * scale;
      const double c2 = cx * cx + cy * cy + cz * cz, x2 = cx * cx;
      s_c2cx += c2 * cx;  // q_x (Eq. 2.7)
      for (int k = 0; k < 3; ++k) {
        const auto& a = full_poly_[k];
        const auto& b = marg_poly_[k];
        s_full[k] += cx * (a[0] + c2 * (a[1] + c2 * (a[2] + c2 * a[3])));  // c_x L_k^(3/2)(c^2), Eq. 3.10
        s_marg[k] += cx * (b[0] + x2 * (b[1] + x2 * (b[2] + x2 * b[3])));  // c_x L_k^(1/2)(c_x^2), Eq. 3.12
      }
      if (window) {
        const double w = cx * (1.5 - x2);  // the integrand of beta1 (Eq. 4.6, see finish())
        const double j = std::floor(std::fabs(cx) / width_);
        if (j < static_cast<double>(half_)) {
          const std::size_t jj = static_cast<std::size_t>(j);
          counts_[cx >= 0 ? half_ + jj : half_ - 1 - jj] += wt;  // mirrored bins exactly (Eq. 3.15)
          beta_bins_[jj] += wt * w;
        } else {
          outside += wt;
          beta_out += wt * w;
        }
        if (x2 < 6.0) beta_six += wt * w;
      }
    }
    const double N = static_cast<double>(p.count);
    double v[kColumns];
    // q_x = (m/2) n <V^2 V_x> = (1/2) n v0^3 <c^2 c_x> (Eq. 2.7), reported in n0 T0 sqrt(2T0/m).
    const double qx = 0.5 * n_ * v0 * v0 * v0 * s_c2cx / N;
    v[kQx] = qx / (n_ * t0_ * std::sqrt(2.0 * t0_));
    // kappa'/kappa0 (or kappa/kappa0) = -q_x/(T eps kappa0) (Eq. 3.9), eps = eps*/lambda;
    // nu0 = (16/5) sqrt(pi) n sigma^2 sqrt(T/m) (Eq. 2.15), kappa0 = (15/4) n T/(m nu0) (Eq. 2.47).
    const double nu0 = 16.0 / 5.0 * std::sqrt(kPi) * n_ * sigma_ * sigma_ * std::sqrt(T);
    const double kappa0 = 15.0 / 4.0 * n_ * T / nu0;
    v[kConductivity] = -qx / (T * (eps_star_ / lambda_) * kappa0);
    for (int k = 0; k < 3; ++k) {
      v[kB1F + k] = full_pref_[k] * s_full[k] / (N * eps_star_);  // Eq. 3.10
      v[kB1M + k] = marg_pref_[k] * s_marg[k] / (N * eps_star_);  // Eq. 3.12
    }
    for (int k = 0; k < kColumns; ++k) sums_[k] += v[k];
    ++samples_;
    if (window) {
      for (int k = 0; k < kColumns; ++k) steady_[k].add(v[k]);
      outside_ += outside;
      beta_outside_ += beta_out;
      beta_six_ += beta_six;
      total_ += wt * N;
      ++window_samples_;
    }
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double ns = samples_ ? static_cast<double>(samples_) : std::nan("");
    for (int k = 0; k < kColumns; ++k) out.append(ids_[k], sums_[k] / ns);
    for (double& s : sums_) s = 0;
    samples_ = 0;
  }

  // The first-Sonine scalars of begin() as theory, once the measured means exist (finish).
  static void tag_theory(gdsmc::OutputSink& out) {
    out.theory("theory_conductivity_over_kappa0", "conductivity_over_kappa0, conductivity_over_kappa0_mean",
               "001 Eqs. 2.41-2.42, 2.47");
    out.theory("theory_b1", "b1_full, b1_marginal, b1_full_mean, b1_marginal_mean", "001 Eq. 2.45");
    out.theory("theory_a2", "", "001 Eq. 2.16");
    out.theory("theory_zeta0_over_nu0", "", "001 Eq. 2.14");
    out.theory("theory_nu_kappa_over_nu0", "", "001 Eq. 2.46");
    out.theory("theory_kappa_prime_over_kappa0", "", "001 Eqs. 2.42, 2.47");
    out.theory("theory_kappa_over_kappa0", "", "001 Eqs. 2.41, 2.47");
    out.theory("theory_mu_n_over_T_kappa0", "", "001 Eq. 2.38");
    out.theory("elastic_reference_kappa_over_kappa0", "", "001 Ref. 37");
    out.theory("nu0_tau0", "", "001 Eq. 2.15");
    out.theory("theory_kappa_prime_over_kappa0_vs_alpha", "", "001 Eqs. 2.42, 2.47");
    out.theory("theory_kappa_over_kappa0_vs_alpha", "", "001 Eqs. 2.41, 2.47");
    out.theory("theory_mu_n_over_T_kappa0_vs_alpha", "", "001 Eq. 2.38");
    out.theory("theory_b1_vs_alpha", "", "001 Eq. 2.45");
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    for (int k = 0; k < kColumns; ++k) {
      out.scalar(names_[k] + "_mean", steady_[k].mean(), units_[k], "steady mean over the samples of the averaging window: " + docs_[k]);
      out.scalar(names_[k] + "_standard_error", steady_[k].standard_error(), units_[k],
                 "batch-means standard error of " + names_[k] + "_mean (NaN with fewer than 4 batches)");
    }
    out.scalar("samples_in_window", static_cast<double>(window_samples_), "1", "samples accumulated in the averaging window");
    tag_theory(out);
    const double nan = std::nan("");
    const double M = total_;  // particle samples in the window
    const double fraction_outside = M > 0 ? outside_ / M : nan;
    out.scalar("fraction_outside", fraction_outside, "1", "fraction of the window's particle samples with |c_x| >= c_max (not in g)");

    // g, g1 (Eq. 3.15) over [-c_max, c_max]; counting errors of the multinomial counts.
    std::vector<double> edges(bins_ + 1), g(bins_), g1(bins_), g1_error(bins_);
    for (std::size_t b = 0; b <= bins_; ++b) edges[b] = -c_max_ + width_ * static_cast<double>(b);
    edges[half_] = 0.0;
    edges[bins_] = c_max_;
    const double norm = M > 0 ? 1.0 / (M * width_) : nan;
    for (std::size_t b = 0; b < bins_; ++b) {
      const double np = counts_[b], nm = counts_[bins_ - 1 - b];
      g[b] = np * norm;
      g1[b] = 0.5 * (np - nm) * norm;  // Eq. 3.15
      // Var(n+ - n-) = M (p+ + p- - (p+ - p-)^2) for multinomial counts.
      g1_error[b] = M > 0 ? 0.5 * std::sqrt(std::max(0.0, np + nm - (np - nm) * (np - nm) / M)) * norm : nan;
    }
    // phi (Eq. 4.3) and the truncated series phi_p (Eq. 4.5) on the positive half.
    double b_steady[3];
    for (int k = 0; k < 3; ++k) b_steady[k] = steady_[kB1F + k].mean();
    std::vector<double> pedges(half_ + 1), phi(half_), phi_error(half_), phi_p[3];
    for (auto& v : phi_p) v.assign(half_, 0.0);
    for (std::size_t j = 0; j <= half_; ++j) pedges[j] = edges[half_ + j];
    for (std::size_t j = 0; j < half_; ++j) {
      const double a = pedges[j], b = pedges[j + 1], centre = 0.5 * (a + b), x = centre * centre;
      // Bin average of eps* c_x exp(-c_x^2)/sqrt(pi) = eps* (e^{-a^2} - e^{-b^2}) / (2 sqrt(pi) (b - a)).
      const double weight = eps_star_ * (std::exp(-a * a) - std::exp(-b * b)) / (2.0 * std::sqrt(kPi) * (b - a));
      phi[j] = g1[half_ + j] / weight;  // Eq. 4.3: g1 = pi^{-1/2} e^{-c_x^2} c_x phi eps*
      phi_error[j] = g1_error[half_ + j] / weight;
      double partial = 0;
      for (int k = 0; k < 3; ++k) {
        const auto& c = marg_poly_[k];
        partial += b_steady[k] * (c[0] + x * (c[1] + x * (c[2] + x * c[3])));  // Eq. 4.5
        phi_p[k][j] = partial;
      }
    }
    out.histogram("g", edges, g, "1", "1", "marginal density g(c_x) of the window, integrating to 1 - fraction_outside");
    out.histogram("g1", edges, g1, "1", "1", "g1(c_x) = [g(c_x) - g(-c_x)]/2 (Eq. 3.15)");
    out.histogram("g1_error", edges, g1_error, "1", "1",
                  "counting (multinomial) error of g1, particles of every sample taken as independent (a lower bound)");
    out.histogram("phi", pedges, phi, "1", "1",
                  "phi(c_x^2) = g1 sqrt(pi) exp(c_x^2)/(c_x eps*) (Eq. 4.3) at the bin centres (g1 over the bin average of "
                  "eps* c_x exp(-c_x^2)/sqrt(pi))");
    out.histogram("phi_error", pedges, phi_error, "1", "1", "counting error of phi (from g1_error)");
    out.histogram("phi_1", pedges, phi_p[0], "1", "1", "b1 L_1^(1/2)(c_x^2) at the bin centres, steady b1_full (Eq. 4.5)");
    out.histogram("phi_2", pedges, phi_p[1], "1", "1", "sum_{k<=2} b_k L_k^(1/2)(c_x^2), steady b_k_full (Eq. 4.5)");
    out.histogram("phi_3", pedges, phi_p[2], "1", "1", "sum_{k<=3} b_k L_k^(1/2)(c_x^2), steady b_k_full (Eq. 4.5)");
    out.attribute("histogram_edges", "reduced velocity c_x = V_x/sqrt(2T/m)");

    // beta1(X) of Eq. 4.6 from the particles. With phi from Eq. 4.3 the integrand of 4.6,
    // (8/(3 sqrt pi)) u^2 (3/2 - u^2) e^{-u^2} phi(u^2), equals (8/(3 eps*)) u (3/2 - u^2) g1(u) for
    // u > 0. u (3/2 - u^2) is odd and g1 is the odd part of g (Eq. 3.15), so
    // int_0^{sqrt X} u (3/2 - u^2) g1(u) du = (1/2) int_{-sqrt X}^{sqrt X} u (3/2 - u^2) g1(u) du
    // = (1/2) int_{-sqrt X}^{sqrt X} u (3/2 - u^2) g(u) du (the even part g0 integrates to 0 against
    // an odd function over a symmetric interval). Hence
    //   beta1(X) = (4/(3 eps*)) < c_x (3/2 - c_x^2) 1{|c_x| < sqrt X} >,
    // and beta1(infinity) = (4/(3 eps*)) <c_x L_1^(1/2)(c_x^2)> = b1 of Eq. 3.12.
    const double bnorm = M > 0 ? 4.0 / (3.0 * eps_star_ * M) : nan;
    std::vector<double> X(half_ + 1), beta(half_ + 1), beta_ratio(half_ + 1);
    double running = 0;
    for (std::size_t j = 0; j <= half_; ++j) {
      X[j] = pedges[j] * pedges[j];
      beta[j] = running * bnorm;  // particles with |c_x| < edge j
      if (j < half_) running += beta_bins_[j];
    }
    const double beta_inf = (running + beta_outside_) * bnorm;
    for (std::size_t j = 0; j <= half_; ++j) beta_ratio[j] = beta[j] / beta_inf;
    const double beta6 = beta_six_ * bnorm / beta_inf;
    out.array("beta1_X", X, {half_ + 1}, "1", "X = c_x^2 at the positive-half edges, where beta1 is evaluated");
    out.array("beta1", beta, {half_ + 1}, "1",
              "beta1(X) = (4/(3 eps*)) <c_x (3/2 - c_x^2) 1{|c_x| < sqrt X}> (Eq. 4.6), from the particles");
    out.array("beta1_over_b1", beta_ratio, {half_ + 1}, "1", "beta1(X)/beta1_infinity (Fig. 7 of 001)");
    out.axis("beta1", "beta1_X");
    out.axis("beta1_over_b1", "beta1_X");
    out.scalar("beta1_infinity", beta_inf, "1", "beta1(X -> infinity) = b1 of Eq. 3.12 over the window (all particles)");
    out.scalar("beta1_6_over_b1", beta6, "1", "beta1(6)/beta1_infinity (001: 0.87 at alpha = 1, 0.66 at alpha = 0.3)");

    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "heat_flux (%s route, eps* = %.4g, alpha = %.4g): %s/kappa0 = %.4g +- %.2g (first Sonine %.4g); "
                  "b1 = %.4g, b2 = %.4g, b3 = %.4g (Eq. 3.10); beta1(6)/b1 = %.3g; %zu samples in the window",
                  route_ ? "kappa" : "kappa'", eps_star_, alpha_, route_ ? "kappa" : "kappa'", steady_[kConductivity].mean(),
                  steady_[kConductivity].standard_error(), theory_, b_steady[0], b_steady[1], b_steady[2], beta6, window_samples_);
    out.summary(buf);
  }
  // counts_ and beta_bins_ are sized by the constructor (bins); the exact-count reads check them.
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("sums", sums_, kColumns);
    out.write("samples", static_cast<std::uint64_t>(samples_));
    for (int k = 0; k < kColumns; ++k) steady_[k].save(out, "steady." + names_[k]);
    out.write("histogram", counts_);
    out.write("beta_bins", beta_bins_);
    const double window[4] = {outside_, beta_outside_, beta_six_, total_};
    out.write("window_sums", window, 4);
    out.write("window_samples", static_cast<std::uint64_t>(window_samples_));
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("sums", sums_, kColumns);
    std::uint64_t count = 0;
    in.read("samples", count);
    samples_ = static_cast<std::size_t>(count);
    for (int k = 0; k < kColumns; ++k) steady_[k].load(in, "steady." + names_[k]);
    in.read("histogram", counts_.data(), counts_.size());
    in.read("beta_bins", beta_bins_.data(), beta_bins_.size());
    double window[4];
    in.read("window_sums", window, 4);
    outside_ = window[0];
    beta_outside_ = window[1];
    beta_six_ = window[2];
    total_ = window[3];
    in.read("window_samples", count);
    window_samples_ = static_cast<std::size_t>(count);
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  const void* extension(const char* id) const override { return gdsmc::offer_bracketed_sampling(id); }
 private:
  double c_max_;
  std::size_t bins_, half_ = 0;
  double width_ = 0;
  double eps_star_ = 0, alpha_ = 1, n_ = 0, sigma_ = 1, lambda_ = 1, t0_ = 1, theory_ = 0;
  int route_ = 0;
  bool slab_ = false;
  std::array<double, 4> full_poly_[3], marg_poly_[3];
  double full_pref_[3] = {}, marg_pref_[3] = {};
  std::string names_[kColumns], units_[kColumns], docs_[kColumns];
  std::size_t ids_[kColumns] = {};
  double sums_[kColumns] = {};
  std::size_t samples_ = 0;
  gdsmc::BatchMeans steady_[kColumns];
  // Steady window accumulators: counts per c_x bin, beta1 partial sums per |c_x| bin.
  std::vector<double> counts_, beta_bins_;
  double outside_ = 0, beta_outside_ = 0, beta_six_ = 0, total_ = 0;
  std::size_t window_samples_ = 0;
};

}  // namespace

GDSMC_PLUGIN(HeatFlux)

// What `gdsmc conformance` runs it in when no --context is given.
// The heat-flux forcing it reads, with the thermostat that keeps the state steady.
GDSMC_CONFORMANCE_CONTEXT(
    "forcings: [{plugin: heat_flux_force, epsilon_star: 0.025}, energy_momentum_thermostat]")
