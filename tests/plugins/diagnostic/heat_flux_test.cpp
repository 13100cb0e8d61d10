// The heat_flux diagnostic (paper 001) driven directly, without its forcing: N = 200000 velocities
// drawn exactly (by rejection from the Maxwellian) from the first-order distribution
//   f = f_M(c) [1 + eps* c_x (b1 L_1^(3/2)(c^2) + b2 L_2^(3/2)(c^2))],   |c| < 4,
// whose Sonine coefficients are b1, b2 (b3 = 0) by Eq. 3.10 and, by the Appendix, also by Eq. 3.12,
// with marginal phi(c_x^2) = b1 L_1^(1/2)(c_x^2) + b2 L_2^(1/2)(c_x^2) (Eq. A.10). Every tolerance
// is argued beside its check. Also: the first-Sonine theory scalars, the route attribute, and the
// refusal of a run without the heat-flux forcing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "config/system_info.hpp"
#include "engine/particle_store.hpp"
#include "engine/streams.hpp"
#include "output/diagnostic_output.hpp"
#include "plugins/loader.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

constexpr double kEps = 0.05, kB1 = 1.6, kB2 = 0.3;
// Cut of |c|: the factor 1 + eps* c_x Phi(c^2) stays positive up to |c| = 4.179 for these
// values (checked below), and the Maxwellian tail beyond 4 moves b1, b2 by < 6e-4 (a radial
// quadrature of c_x^2 Phi L_k over c > 4), far below their standard errors (~0.04).
constexpr double kCut = 4.0;

// Hand-expanded Laguerre polynomials (independent of the plugin's generic expansion).
double L1_32(double x) { return 2.5 - x; }
double L2_32(double x) { return 35.0 / 8.0 - 3.5 * x + 0.5 * x * x; }
double L3_32(double x) { return 105.0 / 16.0 - 63.0 / 8.0 * x + 9.0 / 4.0 * x * x - x * x * x / 6.0; }
double L1_12(double x) { return 1.5 - x; }
double L2_12(double x) { return 15.0 / 8.0 - 2.5 * x + 0.5 * x * x; }
double L3_12(double x) { return 35.0 / 16.0 - 35.0 / 8.0 * x + 7.0 / 4.0 * x * x - x * x * x / 6.0; }
double Phi(double c2) { return kB1 * L1_32(c2) + kB2 * L2_32(c2); }

std::string pipeline_yaml(const std::string& diagnostic, const std::string& forcings = "forcings: []\n") {
  return "run:\n  seed: 5\n  particles: 1000\n  time_step: {value: 0.01, unit: tau0}\n"
         "  stop: {collisions_per_particle: 1}\n"
         "system: {density: 1.0e-3, sigma: 1, temperature: 1.0}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n" +
         forcings + "diagnostics:\n  - " + diagnostic + "\noutput: {file: unused.h5}\n";
}

// The diagnostic as the engine holds it, with its sink.
struct Bench : t::DiagnosticBench {
  Bench(const t::TempDir& dir, const std::string& diagnostic, std::size_t particles)
      : DiagnosticBench(dir, pipeline_yaml(diagnostic), "heat_flux", particles) {}
};

// The drawn sample and the estimators' own standard errors, computed from the sample.
struct Drawn {
  std::vector<double> cx, cy, cz;
  t::MeanError full[3], marginal[3];
};

Drawn draw(std::size_t n) {
  // The bound B of the acceptance factor over |c| < kCut: |c_x Phi| <= |c| |Phi(c^2)|.
  double bound = 0, lowest = 1;
  for (int k = 0; k <= 40000; ++k) {
    const double c = kCut * k / 40000.0, m = kEps * c * std::fabs(Phi(c * c));
    bound = std::max(bound, 1 + m);
    lowest = std::min(lowest, 1 - m);
  }
  EXPECT_GT(lowest, 0.0) << "the first-order distribution must be positive for |c| < " << kCut;
  bound *= 1.01;  // the scan's grid is fine (1e-4); any draw above the bound fails below
  Rng rng = host::StreamFactory::standalone(2024, 0);
  Drawn d;
  const double sd = std::sqrt(0.5);  // f_M ~ exp(-c^2): each component N(0, 1/2)
  std::size_t above = 0;
  while (d.cx.size() < n) {
    const double x = sd * rng.normal(), y = sd * rng.normal(), z = sd * rng.normal();
    const double c2 = x * x + y * y + z * z;
    if (c2 >= kCut * kCut) continue;
    const double factor = 1 + kEps * x * Phi(c2);
    if (factor > bound) ++above;
    if (rng.uniform() * bound < factor) {
      d.cx.push_back(x);
      d.cy.push_back(y);
      d.cz.push_back(z);
    }
  }
  EXPECT_EQ(above, 0u) << "the rejection bound was exceeded";
  // Per-particle terms of Eqs. 3.10 and 3.12 with the paper's prefactors, for the standard errors.
  const double pf[3] = {4.0 / 5.0, 16.0 / 35.0, 32.0 / 105.0}, pm[3] = {4.0 / 3.0, 16.0 / 15.0, 32.0 / 35.0};
  std::vector<double> yf[3], ym[3];
  for (std::size_t i = 0; i < n; ++i) {
    const double c2 = d.cx[i] * d.cx[i] + d.cy[i] * d.cy[i] + d.cz[i] * d.cz[i], x2 = d.cx[i] * d.cx[i];
    const double lf[3] = {L1_32(c2), L2_32(c2), L3_32(c2)}, lm[3] = {L1_12(x2), L2_12(x2), L3_12(x2)};
    for (int k = 0; k < 3; ++k) {
      yf[k].push_back(pf[k] * d.cx[i] * lf[k] / kEps);
      ym[k].push_back(pm[k] * d.cx[i] * lm[k] / kEps);
    }
  }
  for (int k = 0; k < 3; ++k) {
    d.full[k] = t::mean_error(yf[k]);
    d.marginal[k] = t::mean_error(ym[k]);
  }
  return d;
}

// The whole sample: velocities v = u + sqrt(2T) c with a flow u and T = 1.7 (the diagnostic must
// subtract the flow and rescale), one sample in the averaging window, one record, finish.
// Returns the sample's temperature (the diagnostic's T).
double feed(Bench& b, const Drawn& d, double eps_star, double route, double alpha) {
  const std::size_t n = d.cx.size();
  b.board.publish("heat_flux_epsilon_star", eps_star);
  b.board.publish("heat_flux_route", route);
  b.board.publish("restitution", alpha);
  b.diag->begin(b.sys, b.board, *b.out);
  host::ParticleStore store;
  store.allocate(n, {});
  const ParticleSpan p = store.span();
  const double T = 1.7, v0 = std::sqrt(2 * T), u[3] = {0.3, -0.2, 0.1};
  for (std::size_t i = 0; i < n; ++i) p.set_velocity(i, {u[0] + v0 * d.cx[i], u[1] + v0 * d.cy[i], u[2] + v0 * d.cz[i]});
  SampledMoments sm;
  sm.local = velocity_moments(p);
  sm.cell_mean_velocity = sm.local.mean;
  sm.number_density = b.sys.number_density;
  StepContext ctx;
  ctx.system = &b.sys;
  ctx.moments = &sm;
  ctx.quantities = &b.board;
  ctx.in_average_window = true;
  b.diag->sample(ctx, p);
  ctx.moments = nullptr;
  b.out->begin_record(0, 0);
  b.diag->record(ctx, *b.out);
  b.out->check_record("heat_flux");
  b.diag->finish(ctx, *b.out);
  return sm.local.temperature;
}

class HeatFluxDiagnostic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { drawn_ = new Drawn(draw(200000)); }
  static void TearDownTestSuite() {
    delete drawn_;
    drawn_ = nullptr;
  }
  static Drawn* drawn_;
};
Drawn* HeatFluxDiagnostic::drawn_ = nullptr;

// b_k by Eqs. 3.10 and 3.12 recover the chosen b1, b2 and b3 = 0 within 4 standard errors of the
// sample (the estimators' own scatter / sqrt(N)); the series value (one sample) is the steady mean.
TEST_F(HeatFluxDiagnostic, SonineCoefficientsRecoverTheDistribution) {
  t::TempDir dir;
  Bench b(dir, "{plugin: heat_flux, c_max: 5.0, bins: 100}", drawn_->cx.size());
  feed(b, *drawn_, kEps, 0, 0.8);
  const double expected[3] = {kB1, kB2, 0.0};
  const char* full[3] = {"b1_full", "b2_full", "b3_full"};
  const char* marg[3] = {"b1_marginal", "b2_marginal", "b3_marginal"};
  for (int k = 0; k < 3; ++k) {
    const double f = b.series(full[k]).at(0), m = b.series(marg[k]).at(0);
    const double sf = drawn_->full[k].standard_error, smg = drawn_->marginal[k].standard_error;
    std::printf("  %s = %.4f +- %.4f, %s = %.4f +- %.4f (chosen %.2f)\n", full[k], f, sf, marg[k], m, smg, expected[k]);
    EXPECT_NEAR(f, expected[k], 4 * sf) << full[k];
    EXPECT_NEAR(m, expected[k], 4 * smg) << marg[k];
    // The diagnostic's estimate equals the test's own (from the drawn c) up to the effect of the
    // sample's mean and temperature, which the diagnostic subtracts and rescales: O(1/sqrt N)
    // relative shifts of c, well under one standard error.
    EXPECT_NEAR(f, drawn_->full[k].mean, sf) << full[k];
    EXPECT_NEAR(m, drawn_->marginal[k].mean, smg) << marg[k];
    EXPECT_DOUBLE_EQ(b.scalar(std::string(full[k]) + "_mean"), f);  // one sample in the window
  }
  // The error bars are what a 4-sigma test needs to be meaningful: b1 and b2 to a few per cent.
  EXPECT_LT(drawn_->full[0].standard_error, 0.06);
  EXPECT_LT(drawn_->full[1].standard_error, 0.08);
}

// kappa'/kappa0 = -q_x/(T eps kappa0) equals (16/(15 sqrt pi)) b1_full (Eq. 2.45 with <c_x> = 0
// exactly for peculiar velocities): to round-off. q_x is reported in n T0 sqrt(2T0/m) = (n/2) v0(T0)^3:
// with T the sample's temperature (about 1.7 T0), q_x/(n T0 v0(T0)) = (1/2) n v0(T)^3 <c^2 c_x> /
// ((n/2) v0(T0)^3) = (T/T0)^{3/2} <c^2 c_x>.
TEST_F(HeatFluxDiagnostic, ConductivityIsB1TimesItsPrefactor) {
  t::TempDir dir;
  Bench b(dir, "{plugin: heat_flux, c_max: 5.0, bins: 100}", drawn_->cx.size());
  const double T = feed(b, *drawn_, kEps, 0, 0.8);
  EXPECT_NEAR(T, 1.7, 0.02);
  const double b1 = b.series("b1_full").at(0), kappa = b.series("conductivity_over_kappa0").at(0);
  EXPECT_NEAR(kappa, 16.0 / (15.0 * std::sqrt(M_PI)) * b1, 1e-10 * std::fabs(b1));
  // <c^2 c_x> = -(5/4) eps* b1 (Eq. 3.10 with <c_x> = 0), so q_x = -(5/4) (T/T0)^{3/2} eps* b1.
  EXPECT_NEAR(b.series("q_x").at(0), -1.25 * std::pow(T, 1.5) * kEps * b1, 1e-10);
  EXPECT_EQ(b.out->attributes.at("route"), "kappa_prime");
  EXPECT_NEAR(b.scalar("conductivity_over_kappa0_mean"), kappa, 1e-14);
}

// beta1(X) (Eq. 4.6, from the particles) tends to b1 of Eq. 3.12; g integrates to 1; phi at
// low c_x agrees with b1 L_1^(1/2) + b2 L_2^(1/2) (Eq. A.10) within its counting errors.
TEST_F(HeatFluxDiagnostic, MarginalPhiAndBeta1) {
  t::TempDir dir;
  Bench b(dir, "{plugin: heat_flux, c_max: 5.0, bins: 100}", drawn_->cx.size());
  feed(b, *drawn_, kEps, 0, 0.8);
  const double b1m = b.series("b1_marginal").at(0);
  EXPECT_EQ(b.scalar("fraction_outside"), 0.0);  // |c| < 4 < c_max
  EXPECT_NEAR(b.scalar("beta1_infinity"), b1m, 1e-10 * std::fabs(b1m));
  const auto& beta = b.array("beta1");
  const auto& X = b.array("beta1_X");
  ASSERT_EQ(beta.size(), 51u);
  EXPECT_NEAR(X.back(), 25.0, 1e-12);
  EXPECT_NEAR(beta.back(), b1m, 1e-10 * std::fabs(b1m));  // no particle beyond c_max
  EXPECT_EQ(beta.front(), 0.0);
  EXPECT_NEAR(b.array("beta1_over_b1").back(), 1.0, 1e-10);
  // beta1(6)/b1 of this distribution: a number between 0 and 1 (87% for alpha = 1 in 001).
  const double b6 = b.scalar("beta1_6_over_b1");
  EXPECT_GT(b6, 0.5);
  EXPECT_LT(b6, 1.0);
  // g integrates to 1 (nothing outside).
  const auto& g = b.histogram("g");
  ASSERT_EQ(g.edges.size(), 101u);
  EXPECT_EQ(g.edges[50], 0.0);
  double integral = 0;
  for (std::size_t k = 0; k < g.values.size(); ++k) integral += g.values[k] * (g.edges[k + 1] - g.edges[k]);
  EXPECT_NEAR(integral, 1.0, 1e-12);
  // phi against the exact marginal phi (Eq. A.10) at the bin centres with c_x < 2 (20 bins),
  // each within 4 of its counting errors (independent particles: here the errors are exact).
  const auto& phi = b.histogram("phi");
  const auto& err = b.histogram("phi_error");
  ASSERT_EQ(phi.edges.size(), 51u);
  double chi2 = 0;
  int bins = 0;
  for (std::size_t j = 0; j < phi.values.size(); ++j) {
    const double c = 0.5 * (phi.edges[j] + phi.edges[j + 1]);
    if (c > 2.0) break;
    const double exact = kB1 * L1_12(c * c) + kB2 * L2_12(c * c);
    EXPECT_NEAR(phi.values[j], exact, 4 * err.values[j]) << "c_x = " << c;
    chi2 += std::pow((phi.values[j] - exact) / err.values[j], 2);
    ++bins;
  }
  std::printf("  phi vs b1 L1 + b2 L2 over %d bins (c_x < 2): chi^2 = %.1f\n", bins, chi2);
  EXPECT_LT(chi2, bins + 5 * std::sqrt(2.0 * bins));  // mean bins, sd sqrt(2 bins)
  // phi_2 is the truncated series with the measured b1, b2 (Eq. 4.5).
  const double mb1 = b.scalar("b1_full_mean"), mb2 = b.scalar("b2_full_mean"), mb3 = b.scalar("b3_full_mean");
  const auto& phi2 = b.histogram("phi_2");
  const auto& phi3 = b.histogram("phi_3");
  for (std::size_t j : {0u, 10u, 30u}) {
    const double c = 0.5 * (phi.edges[j] + phi.edges[j + 1]), x = c * c;
    EXPECT_NEAR(b.histogram("phi_1").values[j], mb1 * L1_12(x), 1e-12);
    EXPECT_NEAR(phi2.values[j], mb1 * L1_12(x) + mb2 * L2_12(x), 1e-12);
    EXPECT_NEAR(phi3.values[j], mb1 * L1_12(x) + mb2 * L2_12(x) + mb3 * L3_12(x), 1e-10);
  }
  // g1 is odd.
  const auto& g1 = b.histogram("g1");
  for (std::size_t k = 0; k < 50; ++k) EXPECT_EQ(g1.values[k], -g1.values[99 - k]);
}

// First-Sonine theory, written independently here for general d (001 Eqs. 2.14-2.16, 2.41-2.47)
// and evaluated at d = 3.
struct Sonine {
  double a2, zeta, nu, kp, k;
};
Sonine sonine(double alpha) {
  const double d = 3;
  Sonine s;
  s.a2 = 16 * (1 - alpha) * (1 - 2 * alpha * alpha) / (25 + 24 * d - alpha * (57 - 8 * d) - 2 * (1 - alpha) * alpha * alpha);
  s.zeta = (d + 2) / (4 * d) * (1 - alpha * alpha) * (1 + 3 * s.a2 / 16);
  s.nu = (1 + alpha) / d * ((d - 1) / 2 + 3.0 / 16 * (d + 8) * (1 - alpha) + (4 + 5 * d - 3 * (4 - d) * alpha) / 512 * s.a2);
  const double kappa0 = d * (d + 2) / (2 * (d - 1));  // Eq. 2.47 in n T/(m nu0)
  s.kp = (d + 2) / 2 * (1 + 1.5 * s.a2) / (s.nu - 1.5 * s.zeta) / kappa0;
  s.k = (d + 2) / 2 * (1 + 2 * s.a2) / (s.nu - 2 * s.zeta) / kappa0;
  return s;
}

TEST(HeatFluxTheory, FirstSonineScalars) {
  t::TempDir dir;
  for (double alpha : {1.0, 0.5}) {
    for (int route : {0, 1}) {
      Bench b(dir, "heat_flux", 1000);
      b.board.publish("heat_flux_epsilon_star", 0.025);
      b.board.publish("heat_flux_route", route);
      b.board.publish("restitution", alpha);
      b.diag->begin(b.sys, b.board, *b.out);
      const Sonine s = sonine(alpha);
      const double kp = b.scalar("theory_kappa_prime_over_kappa0"), k = b.scalar("theory_kappa_over_kappa0");
      EXPECT_NEAR(b.scalar("theory_a2"), s.a2, 1e-14);
      EXPECT_NEAR(b.scalar("theory_zeta0_over_nu0"), s.zeta, 1e-14);
      EXPECT_NEAR(b.scalar("theory_nu_kappa_over_nu0"), s.nu, 1e-14);
      EXPECT_NEAR(kp, s.kp, 1e-13);
      EXPECT_NEAR(k, s.k, 1e-13);
      EXPECT_NEAR(b.scalar("theory_mu_n_over_T_kappa0"), 2 * (s.k - s.kp), 1e-13);
      const double route_value = route ? s.k : s.kp;
      EXPECT_NEAR(b.scalar("theory_conductivity_over_kappa0"), route_value, 1e-13);
      EXPECT_NEAR(b.scalar("theory_b1"), 15 * std::sqrt(M_PI) / 16 * route_value, 1e-13);
      EXPECT_EQ(b.scalar("elastic_reference_kappa_over_kappa0"), 1.025218);
      EXPECT_EQ(b.out->attributes.at("route"), route ? "kappa" : "kappa_prime");
      if (alpha == 1.0) {  // both reduce to the elastic first-Sonine kappa0: exactly 1
        EXPECT_DOUBLE_EQ(kp, 1.0);
        EXPECT_DOUBLE_EQ(k, 1.0);
        EXPECT_EQ(b.scalar("theory_a2"), 0.0);
        EXPECT_EQ(b.scalar("theory_zeta0_over_nu0"), 0.0);
        EXPECT_EQ(b.scalar("theory_mu_n_over_T_kappa0"), 0.0);
      } else {  // alpha = 0.5, the numbers (computed separately in Python from the same equations)
        EXPECT_NEAR(b.scalar("theory_a2"), 0.0498442367601, 1e-12);
        EXPECT_NEAR(b.scalar("theory_zeta0_over_nu0"), 0.315420560748, 1e-12);
        EXPECT_NEAR(b.scalar("theory_nu_kappa_over_nu0"), 1.01647683022, 1e-11);
        EXPECT_NEAR(kp, 1.31870100784, 1e-10);
        EXPECT_NEAR(k, 1.90108341222, 1e-10);
        EXPECT_NEAR(b.scalar("theory_mu_n_over_T_kappa0"), 1.16476480877, 1e-10);
      }
    }
  }
}

// The curves over alpha (101 points of [0, 1]) against the independent sonine() above, the run's alpha
// on the grid equal to the scalars bit for bit (one formula), and nu0 tau0 = 8/(5 sqrt pi) (Eq. 2.15).
TEST(HeatFluxTheory, FirstSonineCurvesOverAlpha) {
  t::TempDir dir;
  for (int route : {0, 1}) {
    Bench b(dir, "heat_flux", 1000);
    b.board.publish("heat_flux_epsilon_star", 0.025);
    b.board.publish("heat_flux_route", route);
    b.board.publish("restitution", 0.3);
    b.diag->begin(b.sys, b.board, *b.out);
    const auto& alpha = b.array("theory_alpha_grid");
    const auto& kp = b.array("theory_kappa_prime_over_kappa0_vs_alpha");
    const auto& k = b.array("theory_kappa_over_kappa0_vs_alpha");
    const auto& mu = b.array("theory_mu_n_over_T_kappa0_vs_alpha");
    const auto& b1 = b.array("theory_b1_vs_alpha");
    ASSERT_EQ(alpha.size(), 101u);
    for (const auto* curve : {&kp, &k, &mu, &b1}) ASSERT_EQ(curve->size(), 101u);
    EXPECT_EQ(alpha.front(), 0.0);
    EXPECT_EQ(alpha.back(), 1.0);
    for (std::size_t i = 0; i < alpha.size(); ++i) {
      EXPECT_NEAR(alpha[i], 0.01 * static_cast<double>(i), 1e-15);
      const Sonine s = sonine(alpha[i]);
      EXPECT_NEAR(kp[i], s.kp, 1e-12) << "alpha = " << alpha[i];
      EXPECT_NEAR(k[i], s.k, 1e-12) << "alpha = " << alpha[i];
      EXPECT_NEAR(mu[i], 2 * (s.k - s.kp), 1e-12) << "alpha = " << alpha[i];
      EXPECT_NEAR(b1[i], 15 * std::sqrt(M_PI) / 16 * (route ? s.k : s.kp), 1e-12) << "alpha = " << alpha[i];
    }
    EXPECT_EQ(alpha[30], 0.3);
    EXPECT_EQ(kp[30], b.scalar("theory_kappa_prime_over_kappa0"));
    EXPECT_EQ(k[30], b.scalar("theory_kappa_over_kappa0"));
    EXPECT_EQ(mu[30], b.scalar("theory_mu_n_over_T_kappa0"));
    EXPECT_EQ(b1[30], b.scalar("theory_b1"));
    EXPECT_NEAR(b.scalar("nu0_tau0"), 8 / (5 * std::sqrt(M_PI)), 1e-14);
  }
}

// Without a heat-flux forcing the diagnostic refuses, naming the forcing to add: directly, and
// when the host sets up a run.
TEST(HeatFluxTheory, RefusesARunWithoutTheForcing) {
  t::TempDir dir;
  Bench b(dir, "heat_flux", 1000);
  b.board.publish("restitution", 0.9);
  try {
    b.diag->begin(b.sys, b.board, *b.out);
    ADD_FAILURE() << "begin() accepted a board without heat_flux_epsilon_star";
  } catch (const ParameterError& e) {
    EXPECT_TRUE(t::contains(e.what(), "heat_flux needs a heat-flux forcing: add heat_flux_force to forcings")) << e.what();
  }
  host::Pipeline p = t::load_yaml(dir, pipeline_yaml("heat_flux"), {}, "run.yaml");
  try {
    host::Engine e(p);
    ADD_FAILURE() << "the engine set up a run of heat_flux without the forcing";
  } catch (const std::exception& e) {
    EXPECT_TRUE(t::contains(e.what(), "add heat_flux_force to forcings")) << e.what();
  }
  // An odd bin count is refused (0 must be an edge).
  try {
    Bench odd(dir, "{plugin: heat_flux, bins: 81}", 1000);
    ADD_FAILURE() << "bins = 81 accepted";
  } catch (const std::exception& e) {
    EXPECT_TRUE(t::contains(e.what(), "even")) << e.what();
  }
}

}  // namespace
