// poiseuille_channel: the fits of paper 004 to one set of steady sums (profile_fits.cpp).
#pragma once
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/bins.hpp>

#include "columns.hpp"

namespace poiseuille {

// u_R = sqrt(2 T_w / m), the velocity unit of 004 Eq. 19.
inline double reference_speed(double t_wall, double mass) { return std::sqrt(2.0 * t_wall / mass); }
// a_hat = a W / u_R^2 (004 Eq. 17).
inline double a_hat(double accel, double width, double u_ref) { return accel * width / (u_ref * u_ref); }

class ProfileFits {
 public:
  // accel: the body acceleration a; centre_fit: the half width [W] of the curvature fit; wall_fit:
  // bins of the straight wall-gradient fit (< 2: off); reach_bins: bins of the quadratic wall fit
  // (< 3: off).
  ProfileFits(const gdsmc::SystemInfo& sys, double t_wall, double accel, double centre_fit, std::size_t wall_fit,
              std::size_t reach_bins);
  // Every profile and scalar from one set of sums (the whole window, or the window less a batch) and
  // its whole-system sums x (kExtra). peak_half_width: the centre peak's half width at half maximum
  // in W (0: none), or < 0 to find it.
  Result evaluate(const gdsmc::BinSums& s, const double* x, double peak_half_width = -1) const;

 private:
  double u_ref() const { return reference_speed(t_wall_, sys_.mass); }
  double a_hat() const { return poiseuille::a_hat(accel_, sys_.box[1], u_ref()); }
  void symmetrise(double* v) const;
  std::pair<double, double> centre_fit(const double* f, double half_width) const;
  double centre_peak_half_width(const double* rho, bool concave) const;
  double bins_from_centre(std::size_t b) const;
  double local_centre(const double* f) const;
  template <class X>
  Eigen::VectorXd wall_polynomial(const double* f, std::size_t n, int degree, bool upper, X x_of) const;
  double wall_gradient(const double* f) const;
  std::pair<double, double> wall_extrapolation(const double* f) const;
  std::pair<double, double> temperature_maximum(const double* T) const;

  const gdsmc::SystemInfo& sys_;
  std::size_t bins_;
  double t_wall_, accel_, centre_fit_;
  std::size_t wall_fit_, reach_bins_;
};

}  // namespace poiseuille
