// The kinetic theory of a binary granular mixture (gdsmc/physics/mixture_theory.hpp): its pair
// collision moments against a Monte Carlo quadrature over two Maxwellians (independent of the sympy
// derivation), its one-species limits against the published first-Sonine cumulants (van Noije &
// Ernst 1998; Garzo & Dufty 1999 = paper 002 Eq. 18) and cooling rate, and the limits that hold
// exactly: elastic collisions conserve energy and give gamma = 1, identical species give
// gamma = 1, swapping the species inverts gamma, the tracer limit is the x_0 -> 0 limit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <gdsmc/physics.hpp>
#include <gdsmc/physics/mixture_theory.hpp>

namespace {

using gdsmc::BinaryMixture;
using gdsmc::MixtureApproximation;
using gdsmc::MixtureState;
using gdsmc::MixtureTheory;

BinaryMixture uniform_alpha(double alpha) {
  BinaryMixture m;
  for (auto& row : m.alpha)
    for (double& a : row) a = alpha;
  return m;
}

// c of the one-component HCS, first Sonine, linearised (van Noije & Ernst, Granular Matter 1, 57
// (1998); Garzo & Dufty 1999; paper 002 Eq. 18 as kinetic_theory.hpp has it), and of the gas
// driven by white noise: a2 = 16 (1-alpha)(1-2alpha^2) / (73 + 56d - 3alpha(35 + 8d)
// + 30 alpha^2 (1-alpha)) at d = 3 (van Noije & Ernst 1998), c = 2 a2.
double c_white_noise(double a) {
  return 2.0 * 16.0 * (1 - a) * (1 - 2 * a * a) / (241.0 - 177.0 * a + 30.0 * a * a * (1 - a));
}

TEST(MixtureTheory, OneSpeciesLimitIsTheFirstSonineGasOfVanNoijeAndErnst) {
  for (double alpha : {0.3, 0.5, 0.7, 0.8, 0.9, 0.95}) {
    for (double x0 : {0.5, 0.2}) {
      BinaryMixture m = uniform_alpha(alpha);
      m.fraction[0] = x0;
      m.fraction[1] = 1 - x0;
      m.mass[0] = m.mass[1] = 2.5;
      m.diameter[0] = m.diameter[1] = 0.7;
      const MixtureTheory h = gdsmc::mixture_theory(m, MixtureState::cooling, MixtureApproximation::first_sonine);
      ASSERT_TRUE(h.converged);
      EXPECT_NEAR(h.gamma, 1.0, 1e-12) << alpha;
      const double c = gdsmc::enskog_hcs_cumulant(alpha);
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(h.c[i], c, 1e-12) << alpha;
        EXPECT_NEAR(h.t_over_t[i], 1.0, 1e-12);
        // zeta* = zeta / (n sigma^2 v0), v0 = 2 sqrt(T/m): (2 sqrt(pi)/3)(1 - alpha^2)(1 + 3c/32)
        // (000 Eq. 2.16 with the 3 a2/16 of 001 Eq. 2.14, a2 = c/2)
        EXPECT_NEAR(h.zeta_star[i], 2.0 * std::sqrt(M_PI) / 3.0 * (1 - alpha * alpha) * (1 + 3.0 * c / 32.0), 1e-12);
      }
      const MixtureTheory w = gdsmc::mixture_theory(m, MixtureState::white_noise, MixtureApproximation::first_sonine);
      ASSERT_TRUE(w.converged);
      EXPECT_NEAR(w.gamma, 1.0, 1e-12);
      EXPECT_NEAR(w.c[0], c_white_noise(alpha), 1e-12) << alpha;
      EXPECT_NEAR(w.c[1], c_white_noise(alpha), 1e-12) << alpha;
    }
  }
}

TEST(MixtureTheory, ElasticMixturesAreInEquipartition) {
  for (double mr : {0.1, 1.0, 3.0, 50.0})
    for (double sr : {0.5, 1.0, 2.0})
      for (double x0 : {0.0, 0.3, 0.9}) {
        BinaryMixture m = uniform_alpha(1.0);
        m.mass[0] = mr;
        m.diameter[0] = sr;
        m.fraction[0] = x0;
        m.fraction[1] = 1 - x0;
        for (MixtureState s : {MixtureState::cooling, MixtureState::white_noise})
          for (MixtureApproximation a : {MixtureApproximation::maxwellian, MixtureApproximation::first_sonine}) {
            const MixtureTheory t = gdsmc::mixture_theory(m, s, a);
            ASSERT_TRUE(t.converged);
            EXPECT_NEAR(t.gamma, 1.0, 1e-12) << mr << " " << sr << " " << x0;
            EXPECT_NEAR(t.c[0], 0.0, 1e-12);
            EXPECT_NEAR(t.c[1], 0.0, 1e-12);
            EXPECT_NEAR(t.zeta_star[0], 0.0, 1e-12);
          }
      }
}

// Elastic collisions conserve the energy of every pair, for any temperatures and any cumulants:
// sum_i x_i T_i zeta_i = 0. This ties the cross coefficients z_i, z_j of the two species together.
TEST(MixtureTheory, ElasticCollisionsConserveEnergyAtAnyTemperaturesAndCumulants) {
  BinaryMixture m = uniform_alpha(1.0);
  m.mass[0] = 3.7;
  m.diameter[0] = 1.8;
  m.fraction[0] = 0.35;
  m.fraction[1] = 0.65;
  for (double gamma : {0.2, 0.9, 4.0})
    for (double c0 : {-0.3, 0.0, 0.2})
      for (double c1 : {-0.1, 0.4}) {
        const double c[2] = {c0, c1};
        double z[2], tau[2];
        gdsmc::mixture_cooling_rates(m, gamma, c, z);
        gdsmc::detail::mixture_taus(m, gamma, tau);
        EXPECT_NEAR(m.fraction[0] * tau[0] * z[0] + m.fraction[1] * tau[1] * z[1], 0.0, 1e-13)
            << gamma << " " << c0 << " " << c1;
        EXPECT_GT(std::fabs(z[0]), 1e-3);  // energy does flow between the species
      }
}

TEST(MixtureTheory, SwappingTheSpeciesInvertsGamma) {
  BinaryMixture m;
  m.mass[0] = 0.3;
  m.diameter[0] = 1.4;
  m.fraction[0] = 0.25;
  m.fraction[1] = 0.75;
  m.alpha[0][0] = 0.7;
  m.alpha[1][1] = 0.9;
  m.alpha[0][1] = m.alpha[1][0] = 0.8;
  BinaryMixture s;
  for (int i = 0; i < 2; ++i) {
    s.mass[i] = m.mass[1 - i];
    s.diameter[i] = m.diameter[1 - i];
    s.fraction[i] = m.fraction[1 - i];
    for (int j = 0; j < 2; ++j) s.alpha[i][j] = m.alpha[1 - i][1 - j];
  }
  for (MixtureState st : {MixtureState::cooling, MixtureState::white_noise})
    for (MixtureApproximation a : {MixtureApproximation::maxwellian, MixtureApproximation::first_sonine}) {
      const MixtureTheory t = gdsmc::mixture_theory(m, st, a), u = gdsmc::mixture_theory(s, st, a);
      ASSERT_TRUE(t.converged && u.converged);
      EXPECT_GT(std::fabs(t.gamma - 1.0), 0.05);  // a real mixture
      EXPECT_NEAR(t.gamma * u.gamma, 1.0, 1e-12);
      // zeta* is reduced by nu = n sigma_12^2 v0, symmetric in the species
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(t.c[i], u.c[1 - i], 1e-12);
        EXPECT_NEAR(t.zeta_star[i], u.zeta_star[1 - i], 1e-12);
        EXPECT_NEAR(t.t_over_t[i], u.t_over_t[1 - i], 1e-12);
      }
      if (st == MixtureState::cooling) EXPECT_NEAR(t.zeta_star[0], t.zeta_star[1], 1e-12);  // zeta_1 = zeta_2
      else EXPECT_NEAR(t.zeta_star[0] * t.gamma / m.mass[0], t.zeta_star[1] / m.mass[1], 1e-12);
    }
}

// Species 0 as a tracer: the x_0 -> 0 limit is continuous, and the gas of species 1 is the pure gas.
TEST(MixtureTheory, TracerLimitIsTheLimitOfVanishingFraction) {
  BinaryMixture m = uniform_alpha(0.8);
  m.mass[0] = 5.0;
  m.diameter[0] = 2.0;
  m.alpha[0][1] = m.alpha[1][0] = 0.9;
  for (MixtureState st : {MixtureState::cooling, MixtureState::white_noise}) {
    const MixtureTheory t = gdsmc::mixture_tracer_theory(m, st, MixtureApproximation::first_sonine);
    ASSERT_TRUE(t.converged);
    BinaryMixture near = m;
    near.fraction[0] = 1e-9;
    near.fraction[1] = 1 - 1e-9;
    const MixtureTheory n = gdsmc::mixture_theory(near, st, MixtureApproximation::first_sonine);
    EXPECT_NEAR(n.gamma, t.gamma, 1e-7 * t.gamma);
    EXPECT_NEAR(t.t_over_t[1], 1.0, 1e-15);
    EXPECT_NEAR(t.c[1], st == MixtureState::cooling ? gdsmc::enskog_hcs_cumulant(0.8) : c_white_noise(0.8), 1e-12);
    // the pure gas 1: zeta_1 = (4 sqrt(pi)/3) n sigma_1^2 sqrt(T_1/m_1)(1 - alpha^2)(1 + 3 c_1/32), over
    // nu = n sigma_12^2 sqrt(2 T (m_0 + m_1)/(m_0 m_1)), T = T_1
    const double s12 = 1.5, v0 = std::sqrt(2.0 * 6.0 / 5.0);
    EXPECT_NEAR(t.zeta_star[1], 4.0 * std::sqrt(M_PI) / 3.0 * 0.36 * (1 + 3.0 * t.c[1] / 32.0) / (s12 * s12 * v0), 1e-12);
  }
}

// The pair moments against a Monte Carlo quadrature: v1, v2 drawn from Maxwellians with
// a = m/(2T) = a_i, a_j, sigma uniform on the sphere; the integrand 4 pi Theta(g.s)(g.s)(|v1'|^p -
// |v1|^p) (times S_2(a_i v1^2) or S_2(a_j v2^2) for the coefficients of A_i, A_j). 2e6 draws;
// each estimate within 5 of its own standard errors (a false alarm once in ~1e5 per check).
TEST(MixtureTheory, PairMomentsMatchAMonteCarloQuadrature) {
  struct Case {
    double ai, aj, mu, alpha;
  };
  std::mt19937_64 gen(20260528);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unif(0.0, 1.0);
  for (const Case& k : {Case{0.7, 2.3, 0.35, 0.6}, Case{1.0, 1.0, 0.5, 0.9}, Case{3.0, 0.4, 0.8, 0.75}}) {
    const double w = k.ai / (k.ai + k.aj), l = (1 + k.alpha) * k.mu, vij = std::sqrt(1 / k.ai + 1 / k.aj);
    const gdsmc::MixturePairMoments exact = gdsmc::mixture_pair_moments(w, l);
    // the reduced moments: z = -(2 a_i / 3) E2 / v_ij, w = -(2/15) a_i^2 E4 / v_ij
    const double fz = -2.0 * k.ai / 3.0 / vij, fw = -2.0 / 15.0 * k.ai * k.ai / vij;
    const double expect[6] = {exact.z0, exact.zi, exact.zj, exact.w0, exact.wi, exact.wj};
    double sum[6] = {0}, sum2[6] = {0};
    const int n = 2000000;
    auto S2 = [](double x) { return 0.5 * x * x - 2.5 * x + 15.0 / 8.0; };
    for (int d = 0; d < n; ++d) {
      double v1[3], v2[3], s[3];
      for (int c = 0; c < 3; ++c) {
        v1[c] = normal(gen) / std::sqrt(2 * k.ai);
        v2[c] = normal(gen) / std::sqrt(2 * k.aj);
      }
      const double cz = 2 * unif(gen) - 1, ph = 2 * M_PI * unif(gen), sz = std::sqrt(1 - cz * cz);
      s[0] = sz * std::cos(ph);
      s[1] = sz * std::sin(ph);
      s[2] = cz;
      const double gs = (v1[0] - v2[0]) * s[0] + (v1[1] - v2[1]) * s[1] + (v1[2] - v2[2]) * s[2];
      double e[6] = {0, 0, 0, 0, 0, 0};
      if (gs > 0) {
        double b2 = 0, a2 = 0, q2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double after = v1[c] - k.mu * (1 + k.alpha) * gs * s[c];
          b2 += v1[c] * v1[c];
          a2 += after * after;
          q2 += v2[c] * v2[c];
        }
        const double base = 4 * M_PI * gs, si = S2(k.ai * b2), sj = S2(k.aj * q2);
        const double d2 = fz * base * (a2 - b2), d4 = fw * base * (a2 * a2 - b2 * b2);
        const double v[6] = {d2, d2 * si, d2 * sj, d4, d4 * si, d4 * sj};
        for (int q = 0; q < 6; ++q) e[q] = v[q];
      }
      for (int q = 0; q < 6; ++q) {
        sum[q] += e[q];
        sum2[q] += e[q] * e[q];
      }
    }
    for (int q = 0; q < 6; ++q) {
      const double mean = sum[q] / n, se = std::sqrt((sum2[q] / n - mean * mean) / (n - 1));
      EXPECT_NEAR(mean, expect[q], 5 * se) << "case ai = " << k.ai << ", moment " << q << ": " << mean << " +- " << se;
    }
  }
}

}  // namespace
