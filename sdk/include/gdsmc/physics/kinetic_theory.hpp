// gdsmc SDK: the local-equilibrium formulas of paper 000 that several plugins use, in one place
// (reduced units, m = 1 unless given).
#pragma once
#include <cmath>

namespace gdsmc {

// tau(T) = lambda0 / sqrt(2T/m): the characteristic time at temperature T (000 Eq. 2.12 with the
// mean free path lambda0 of the mean density, Eq. 4.1).
inline double characteristic_time(double lambda0, double temperature, double mass = 1.0) {
  return lambda0 / std::sqrt(2.0 * temperature / mass);
}

// zeta0 tau = 2 (1 - alpha^2) / (3 sqrt(pi)): the local-equilibrium cooling rate (000 Eq. 2.16).
inline double cooling_rate0_times_tau(double alpha) { return 2.0 * (1.0 - alpha * alpha) / (3.0 * std::sqrt(M_PI)); }

// tau_eta / tau = c 5 sqrt(pi) / 8 with c = 1.016 for hard spheres (000 Eq. 2.18; the BGK model
// may take c = 1).
inline double viscosity_time_over_tau(double c = 1.016) { return c * 5.0 * std::sqrt(M_PI) / 8.0; }

// [eta]_inf / [eta]_1: the converged Chapman-Enskog shear viscosity of elastic hard spheres over its
// first Sonine value (Chapman & Cowling Sec. 10.21).
inline constexpr double chapman_enskog_viscosity_factor = 1.016034;

// eta(a*) / eta(0) of an elastic gas in uniform shear held at fixed T by a Gaussian thermostat,
// from Grad's (= BGK's) equations for P_ij with the relaxation rate nu = p/eta(0), a* = a/nu:
// P_yy = p/(1 + g), P_xy = -a* p/(1 + g)^2, where g (1 + g)^2 = 2 a*^2/3 is the thermostat's rate
// over nu; so 1/(1 + g)^2 = 1 - 4 a*^2/3 + O(a*^4).
inline double thermostatted_shear_viscosity_ratio(double a_star) {
  const double c = 2.0 * a_star * a_star / 3.0;
  double g = c;
  for (int k = 0; k < 100; ++k) {  // Newton on g (1 + g)^2 - c, monotone from g = c
    const double step = (g * (1.0 + g) * (1.0 + g) - c) / ((1.0 + g) * (1.0 + 3.0 * g));
    g -= step;
    if (std::fabs(step) <= 1e-16 * (1.0 + g)) break;
  }
  return 1.0 / ((1.0 + g) * (1.0 + g));
}

// P(x) = erf(x) - 2x exp(-x^2)/sqrt(pi): the fraction of a Maxwellian with speed below
// x sqrt(2T/m) (000, after Eq. 4.19).
inline double maxwell_speed_fraction_below(double x) {
  if (std::isinf(x)) return x > 0 ? 1.0 : 0.0;
  return std::erf(x) - 2.0 * x * std::exp(-x * x) / std::sqrt(M_PI);
}

}  // namespace gdsmc
