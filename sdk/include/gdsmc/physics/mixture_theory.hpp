// gdsmc SDK: kinetic theory of a dilute binary mixture of smooth inelastic hard spheres (d = 3,
// Boltzmann, chi = 1): the partial cooling rates zeta_i, the fourth cumulants c_i and the
// temperature ratio gamma = T1/T2 of the homogeneous cooling state (HCS; Garzo & Dufty, Phys. Rev.
// E 60, 5706 (1999), "GD99") and of the steady state driven by a white-noise thermostat that gives
// every species the same acceleration variance xi0^2 dt per component (Barrat & Trizac, Granular
// Matter 4, 57 (2002); Dahl, Hrenya, Garzo & Dufty, Phys. Rev. E 66, 041301 (2002)).
//
// Species i (i = 0, 1 here; 1 and 2 in the papers) has mass m_i, diameter sigma_i, number fraction
// x_i, temperature T_i = m_i <V^2>_i / 3; T = x_1 T_1 + x_2 T_2; sigma_ij = (sigma_i + sigma_j)/2.
// Its distribution in the first Sonine approximation is (GD99)
//   f_i = f_i,M(V) [1 + (c_i/2) S_2(m_i V^2 / (2 T_i))],  S_2(x) = x^2/2 - 5x/2 + 15/8,
// i.e. c_i = 2 a_2,i = (8/15) m_i^2 <V^4>_i / (4 T_i^2) - 2 (the cumulant of GD99; c = 2 a2 as in
// kinetic_theory.hpp's enskog_hcs_cumulant). The Maxwellian approximation is c_i = 0.
//
// The collisional moments of a pair of species (i, j) below are exact for these distributions to
// first order in c_i, c_j; they were derived with sympy by scripts/mixture_sonine_moments.py (which
// also checks their one-species limits against van Noije & Ernst, Granular Matter 1, 57 (1998):
// a2 of the HCS and of the white-noise-driven gas) and are checked independently by a Monte Carlo
// quadrature in tests/sdk/mixture_kinetic_theory_test.cpp. Header-only, no allocation.
#pragma once
#include <cmath>
#include <limits>

namespace gdsmc {

// The energy (second) and fourth collisional moments that species i receives from collisions with
// species j, per unit n_j sigma_ij^2 v_ij, v_ij = sqrt(2T_i/m_i + 2T_j/m_j), as linear forms in
// the Sonine amplitudes A_i = c_i/2, A_j = c_j/2:
//   zeta_ij = n_j sigma_ij^2 v_ij [z0 + zi A_i + zj A_j]                   (partial cooling rate)
//   -(2/15) a_i^2 int dv1 dv2 |v1|^4 ... = n_j sigma_ij^2 v_ij [w0 + wi A_i + wj A_j]  (a_i = m_i/2T_i)
// in the variables w = a_i/(a_i + a_j) = (m_i/T_i)/(m_i/T_i + m_j/T_j) and
// l = (1 + alpha_ij) mu_ji, mu_ji = m_j/(m_i + m_j) (scripts/mixture_sonine_moments.py).
struct MixturePairMoments {
  double z0, zi, zj;  // zeta_ij / (n_j sigma_ij^2 v_ij): Maxwellian part, coefficients of A_i, A_j
  double w0, wi, wj;  // the fourth-moment rate, likewise
};

inline MixturePairMoments mixture_pair_moments(double w, double l) {
  const double sp = std::sqrt(M_PI), v = 1.0 - w, l2 = l * l, l3 = l2 * l, w2 = w * w, w3 = w2 * w;
  MixturePairMoments p;
  // Maxwellian zeta_ij = (8 sqrt(pi)/3) n_j sigma_ij^2 mu_ji (1+alpha_ij) v_ij
  //   [1 - mu_ji (1+alpha_ij)(1 + m_i T_j/(m_j T_i))/2]   (GD99 Maxwellian cooling rate; Dahl et al. 2002)
  p.z0 = 4.0 * sp / 3.0 * l * (2.0 - l / v);
  p.zi = sp / 6.0 * l * v * (6.0 + 2.0 * w - 3.0 * l);
  p.zj = -sp / 6.0 * l * w2 * (3.0 * l + 2.0 * v) / v;
  p.w0 = 4.0 * sp / 15.0 * l * (2.0 - l / v) * (2.0 * l2 - 4.0 * l * v + v * (6.0 - w)) / v;
  p.wi = -sp / 30.0 * l *
         (30.0 * l3 + 24.0 * l2 * w - 120.0 * l2 - 9.0 * l * w2 - 69.0 * l * w + 210.0 * l + 6.0 * w3 + 16.0 * w2 +
          78.0 * w - 180.0);
  p.wj = -sp / 30.0 * l * w2 *
         (30.0 * l3 + 24.0 * l2 * w - 24.0 * l2 - 9.0 * l * w2 + 3.0 * l * w + 6.0 * l + 6.0 * w3 - 8.0 * w2 - 2.0 * w +
          4.0) /
         (v * v);
  return p;
}

// A binary mixture: masses (units of any common mass), diameters, number fractions (x_0 + x_1 = 1;
// x_0 = 0 is the tracer limit of species 0 in a gas of species 1) and restitution alpha[i][j]
// (symmetric: alpha[0][1] = alpha[1][0] = alpha_12).
struct BinaryMixture {
  double mass[2] = {1, 1};
  double diameter[2] = {1, 1};
  double fraction[2] = {0.5, 0.5};
  double alpha[2][2] = {{1, 1}, {1, 1}};
};

// Which homogeneous state: the HCS (zeta_0 = zeta_1, GD99) or the white-noise steady state
// (dT_i/dt = m_i xi0^2 - zeta_i T_i = 0: zeta_0 T_0/m_0 = zeta_1 T_1/m_1, the condition of
// Barrat & Trizac 2002 and Dahl et al. 2002 for a thermostat of equal acceleration variance).
enum class MixtureState { cooling, white_noise };
// Maxwellian (c_i = 0) or first Sonine (c_i from the linearised fourth-moment equations).
enum class MixtureApproximation { maxwellian, first_sonine };

// The theory's answer. zeta_star[i] = zeta_i / nu with GD99's nu = n sigma_12^2 v0,
// v0 = sqrt(2T (m_0 + m_1)/(m_0 m_1)), T the mixture temperature; in the white-noise state the
// steady T is set by xi0 (not computed here), and zeta_star is at that T.
struct MixtureTheory {
  double gamma = std::numeric_limits<double>::quiet_NaN();  // T_0 / T_1
  double t_over_t[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  double zeta_star[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  double c[2] = {0, 0};
  bool converged = false;
};

namespace detail {

// The pair (i, j) at temperatures T_i/T = tau_i, T_j/T = tau_j: the prefactor
// x_j (sigma_ij/sigma_12)^2 v_ij / v0 and the moments.
struct MixturePair {
  double weight;
  MixturePairMoments m;
};
inline MixturePair mixture_pair(const BinaryMixture& mix, int i, int j, const double tau[2]) {
  const double mi = mix.mass[i], mj = mix.mass[j];
  const double sij = 0.5 * (mix.diameter[i] + mix.diameter[j]), s12 = 0.5 * (mix.diameter[0] + mix.diameter[1]);
  const double ai = mi / tau[i], aj = mj / tau[j];  // proportional to a_i = m_i / (2 T_i)
  const double v_over_v0 =
      std::sqrt((tau[i] / mi + tau[j] / mj) * mix.mass[0] * mix.mass[1] / (mix.mass[0] + mix.mass[1]));
  const double l = (1.0 + mix.alpha[i][j]) * mj / (mi + mj);
  return {mix.fraction[j] * (sij / s12) * (sij / s12) * v_over_v0, mixture_pair_moments(ai / (ai + aj), l)};
}

inline void mixture_taus(const BinaryMixture& mix, double gamma, double tau[2]) {
  const double d = mix.fraction[0] * gamma + mix.fraction[1];  // T_1 / T
  tau[0] = gamma / d;
  tau[1] = 1.0 / d;
}

}  // namespace detail

// zeta_i* at temperature ratio gamma and cumulants c (GD99's zeta_i* = zeta_i / nu, first Sonine;
// c = {0, 0} gives the Maxwellian approximation): sum over j of the pair moments above.
inline void mixture_cooling_rates(const BinaryMixture& mix, double gamma, const double c[2], double zeta_star[2]) {
  double tau[2];
  detail::mixture_taus(mix, gamma, tau);
  for (int i = 0; i < 2; ++i) {
    zeta_star[i] = 0;
    for (int j = 0; j < 2; ++j) {
      const detail::MixturePair p = detail::mixture_pair(mix, i, j, tau);
      zeta_star[i] += p.weight * (p.m.z0 + p.m.zi * 0.5 * c[i] + p.m.zj * 0.5 * c[j]);
    }
  }
}

// The cumulants c_i at temperature ratio gamma: the fourth-moment balance of each species,
//   HCS:         d<V^4>_i/dt|coll = -2 zeta_i <V^4>_i, i.e. W_i = zeta_i (1 + A_i),
//   white noise: d<V^4>_i/dt|coll = -20 (xi0^2/2) <V^2>_i with xi0^2 = zeta_i T_i/m_i, i.e. W_i = zeta_i,
// (W_i the fourth-moment rate of mixture_pair_moments summed over j), linearised in A_0, A_1 as
// GD99 do (their one-species limit is van Noije & Ernst's a2 for both states), solved by Cramer's
// rule. NaN when the 2x2 system is singular.
inline void mixture_cumulants(const BinaryMixture& mix, double gamma, MixtureState state, double c[2]) {
  double tau[2];
  detail::mixture_taus(mix, gamma, tau);
  double M[2][2] = {{0, 0}, {0, 0}}, rhs[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    double z0 = 0;
    for (int j = 0; j < 2; ++j) {
      const detail::MixturePair p = detail::mixture_pair(mix, i, j, tau);
      // W_i - zeta_i [- zeta_i^M A_i in the HCS] = 0, linear in (A_0, A_1); the partner's
      // amplitude is A_j (A_i itself in the like pair j = i)
      M[i][i] += p.weight * (p.m.wi - p.m.zi);
      M[i][j] += p.weight * (p.m.wj - p.m.zj);
      rhs[i] -= p.weight * (p.m.w0 - p.m.z0);
      z0 += p.weight * p.m.z0;
    }
    if (state == MixtureState::cooling) M[i][i] -= z0;
  }
  const double det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
  if (!(std::fabs(det) > 0)) {
    c[0] = c[1] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  c[0] = 2.0 * (rhs[0] * M[1][1] - M[0][1] * rhs[1]) / det;
  c[1] = 2.0 * (M[0][0] * rhs[1] - rhs[0] * M[1][0]) / det;
}

// The temperature ratio's condition F(gamma) = 0, divided by the same expression with every
// zeta_i* replaced by its collision-frequency scale nu_i* = sum_j x_j (sigma_ij/sigma_12)^2 v_ij/v0
// (positive, so F is finite where both zeta_i vanish, e.g. elastic at gamma = 1):
//   HCS (GD99: zeta_0 = zeta_1):                  (zeta_0* - zeta_1*) / (nu_0* + nu_1*)
//   white noise (zeta_0 T_0/m_0 = zeta_1 T_1/m_1): (zeta_0* gamma/m_0 - zeta_1*/m_1) / (nu_0* gamma/m_0 + nu_1*/m_1)
inline double mixture_condition(const BinaryMixture& mix, double gamma, MixtureState state,
                                MixtureApproximation approx, double c[2], double zeta_star[2]) {
  c[0] = c[1] = 0;
  if (approx == MixtureApproximation::first_sonine) mixture_cumulants(mix, gamma, state, c);
  mixture_cooling_rates(mix, gamma, c, zeta_star);
  double tau[2], nu[2] = {0, 0};
  detail::mixture_taus(mix, gamma, tau);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) nu[i] += detail::mixture_pair(mix, i, j, tau).weight;
  double f[2] = {1, 1};  // the factors T_i/(T_1 m_i) of the white-noise condition
  if (state == MixtureState::white_noise) {
    f[0] = gamma / mix.mass[0];
    f[1] = 1.0 / mix.mass[1];
  }
  return (f[0] * zeta_star[0] - f[1] * zeta_star[1]) / (f[0] * nu[0] + f[1] * nu[1]);
}

// Solves for gamma = T_0/T_1 and fills the rest. The root is bracketed by stepping outwards in
// ln gamma (factor 1.05) from `start` (1, or the Maxwellian root for first Sonine) on both sides
// until F changes sign, then bisected to round-off; a sign change through a pole of c_i (the
// Sonine system singular) is recognised by |F| not vanishing there and skipped.
inline MixtureTheory mixture_theory(const BinaryMixture& mix, MixtureState state, MixtureApproximation approx,
                                    double start = 0) {
  MixtureTheory out;
  if (!(start > 0)) {
    start = 1.0;
    if (approx == MixtureApproximation::first_sonine) {
      const MixtureTheory maxwell = mixture_theory(mix, state, MixtureApproximation::maxwellian);
      if (maxwell.converged) start = maxwell.gamma;
    }
  }
  double c[2], z[2];
  auto F = [&](double u) { return mixture_condition(mix, std::exp(u), state, approx, c, z); };
  const double u0 = std::log(start), step = std::log(1.05);
  double lo_prev = u0, f_lo_prev = F(u0), hi_prev = u0, f_hi_prev = f_lo_prev;
  if (f_lo_prev == 0) {
    out.gamma = start;
  } else {
    for (int k = 1; k <= 800 && !out.converged; ++k) {  // out to gamma = start * 1.05^+-800 ~ 1e+-17
      for (int side = 0; side < 2 && !out.converged; ++side) {
        double& prev = side ? hi_prev : lo_prev;
        double& f_prev = side ? f_hi_prev : f_lo_prev;
        const double u = u0 + (side ? 1.0 : -1.0) * k * step, f = F(u);
        if (std::isfinite(f) && std::isfinite(f_prev) && f * f_prev <= 0) {
          double a = std::min(u, prev), b = std::max(u, prev), fa = side ? f_prev : f;
          for (int it = 0; it < 200 && b - a > 1e-15 * (1.0 + std::fabs(a)); ++it) {
            const double mid = 0.5 * (a + b), fm = F(mid);
            if ((fm <= 0) == (fa <= 0)) {
              a = mid;
              fa = fm;
            } else {
              b = mid;
            }
          }
          const double root = 0.5 * (a + b);
          if (std::fabs(F(root)) < 1e-9) {
            out.gamma = std::exp(root);
            out.converged = true;
          }
        }
        prev = u;
        f_prev = f;
      }
    }
    if (!out.converged) return out;
  }
  out.converged = true;
  mixture_condition(mix, out.gamma, state, approx, c, z);
  double tau[2];
  detail::mixture_taus(mix, out.gamma, tau);
  for (int i = 0; i < 2; ++i) {
    out.t_over_t[i] = tau[i];
    out.zeta_star[i] = z[i];
    out.c[i] = c[i];
  }
  return out;
}

// The tracer limit x_0 -> 0 (species 0 an impurity in a gas of species 1): zeta_0 from 0-1
// collisions only, zeta_1 and c_1 those of the pure gas 1 -- mixture_theory at x_0 = 0, where
// T = T_1 and t_over_t[0] = gamma.
inline MixtureTheory mixture_tracer_theory(BinaryMixture mix, MixtureState state, MixtureApproximation approx) {
  mix.fraction[0] = 0;
  mix.fraction[1] = 1;
  return mixture_theory(mix, state, approx);
}

}  // namespace gdsmc
