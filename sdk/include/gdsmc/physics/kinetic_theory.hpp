// gdsmc SDK: the local-equilibrium formulas of paper 000, the elastic conductivity of paper 001 and
// the first-Sonine Enskog viscosity of paper 002 that plugins use, in one place (reduced units, m = 1
// unless given).
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

// kappa0(T) = (75/64) sqrt(T/(pi m)) / sigma^2: the first-Sonine thermal conductivity of elastic
// hard spheres (001 Eq. 2.47).
inline double elastic_conductivity0(double temperature, double mass = 1.0, double sigma = 1.0) {
  return 75.0 / 64.0 * std::sqrt(temperature / (M_PI * mass)) / (sigma * sigma);
}

// kappa / kappa0: the converged Chapman-Enskog (Sonine) conductivity of elastic hard spheres over its
// first Sonine value (001 Sec. IV, its Ref. 37).
inline constexpr double chapman_enskog_conductivity_factor = 1.025218;

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

// Carnahan-Starling contact value chi(phi) = (1 - phi/2) / (1 - phi)^3 (002, after Eq. 18).
inline double carnahan_starling_contact_value(double phi) {
  return (1.0 - 0.5 * phi) / ((1.0 - phi) * (1.0 - phi) * (1.0 - phi));
}

// c0(alpha): the HCS fourth cumulant estimate of 002 Eq. 18 (c = 2 a2).
inline double enskog_hcs_cumulant(double alpha) {
  return 32.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha) / (81.0 - 17.0 * alpha + 30.0 * alpha * alpha * (1.0 - alpha));
}

// eta^k / eta0 of the Enskog gas in the first Sonine approximation (002 Eq. 16), chi the contact value.
inline double enskog_kinetic_viscosity(double alpha, double phi, double chi) {
  const double c0 = enskog_hcs_cumulant(alpha);
  return (1.0 - 0.4 * phi * chi * (1.0 + alpha) * (1.0 - 3.0 * alpha)) /
         (chi * (1.0 + alpha) * (16.0 * (13.0 - alpha) - 3.0 * (4.0 - 3.0 * alpha) * c0) / 384.0);
}

// eta / eta0, kinetic and collisional parts, in the first Sonine approximation (002 Eq. 17).
inline double enskog_viscosity(double alpha, double phi, double chi) {
  const double c0 = enskog_hcs_cumulant(alpha);
  return enskog_kinetic_viscosity(alpha, phi, chi) * (1.0 + 0.8 * phi * chi * (1.0 + alpha)) +
         384.0 / (25.0 * M_PI) * phi * phi * chi * (1.0 + alpha) * (1.0 - c0 / 32.0);
}

// The packing fraction at which the first-Sonine eta^k(alpha, phi)/eta^k(1, phi) (kinetic) or
// eta(alpha, phi)/eta(1, phi) crosses 1, with the Carnahan-Starling chi (002 Sec. 3: phi0^k, phi0):
// bisection on (1e-4, 0.5); NaN if the ratio does not change sign there (alpha = 1 included).
inline double enskog_viscosity_crossing(double alpha, bool kinetic) {
  auto f = [alpha, kinetic](double phi) {
    const double chi = carnahan_starling_contact_value(phi);
    return kinetic ? enskog_kinetic_viscosity(alpha, phi, chi) / enskog_kinetic_viscosity(1.0, phi, chi) - 1.0
                   : enskog_viscosity(alpha, phi, chi) / enskog_viscosity(1.0, phi, chi) - 1.0;
  };
  double lo = 1e-4, hi = 0.5;
  if (!(f(lo) * f(hi) < 0)) return std::nan("");
  for (int k = 0; k < 80; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (f(lo) * f(mid) <= 0) hi = mid;
    else lo = mid;
  }
  return 0.5 * (lo + hi);
}

// P(x) = erf(x) - 2x exp(-x^2)/sqrt(pi): the fraction of a Maxwellian with speed below
// x sqrt(2T/m) (000, after Eq. 4.19).
inline double maxwell_speed_fraction_below(double x) {
  if (std::isinf(x)) return x > 0 ? 1.0 : 0.0;
  return std::erf(x) - 2.0 * x * std::exp(-x * x) / std::sqrt(M_PI);
}

}  // namespace gdsmc
