// poiseuille_channel: the fits of paper 004 to one set of steady sums (the whole window, or the
// window less one batch for the jackknife): the profiles in the paper's units and every scalar of
// columns.hpp, centre-line values, curvatures and chi (Eqs. 36-39), slip (Eqs. 23-29), T_max and
// Delta T (Eq. 22), Q (Eq. 40) and the balances (Eq. 33).
#include "profile_fits.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

namespace poiseuille {

ProfileFits::ProfileFits(const gdsmc::SystemInfo& sys, double t_wall, double accel, double centre_fit, std::size_t wall_fit,
                         std::size_t reach_bins)
    : sys_(sys), bins_(sys.bins), t_wall_(t_wall), accel_(accel), centre_fit_(centre_fit), wall_fit_(wall_fit),
      reach_bins_(reach_bins) {}

void ProfileFits::symmetrise(double* v) const {
  for (std::size_t b = 0; b < bins_ / 2; ++b) {
    const double m = 0.5 * (v[b] + v[bins_ - 1 - b]);
    v[b] = v[bins_ - 1 - b] = m;
  }
}

// Least-squares f = c0 + c2 y^2 + c4 y^4 over |y| <= half_width (y in W): returns {f(0), f''(0)}.
std::pair<double, double> ProfileFits::centre_fit(const double* f, double half_width) const {
  std::vector<std::size_t> rows;
  for (std::size_t b = 0; b < bins_; ++b)
    if (std::fabs(bins_from_centre(b)) / static_cast<double>(bins_) <= half_width && std::isfinite(f[b]))
      rows.push_back(b);
  if (rows.size() < 3) {  // too few bins: the mean of the two central bins, no curvature
    return {0.5 * (f[(bins_ - 1) / 2] + f[bins_ / 2]), std::nan("")};
  }
  Eigen::MatrixXd A(rows.size(), 3);
  Eigen::VectorXd rhs(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double y = bins_from_centre(rows[r]) / static_cast<double>(bins_), y2 = y * y;
    A(static_cast<Eigen::Index>(r), 0) = 1.0;
    A(static_cast<Eigen::Index>(r), 1) = y2;
    A(static_cast<Eigen::Index>(r), 2) = y2 * y2;
    rhs(static_cast<Eigen::Index>(r)) = f[rows[r]];
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(rhs);
  return {c(0), 2.0 * c(1)};
}

// Half width at half maximum [W] of the density peak at the centre line of a symmetrised profile
// that is concave there (rho''(0) < 0 by the wide even fit): the bins from the centre outwards
// while rho stays above half its centre value; 0 where it is not concave or never falls to half.
double ProfileFits::centre_peak_half_width(const double* rho, bool concave) const {
  const std::size_t c = bins_ / 2;  // the centre bin (odd bins) or the first right of the centre
  const double top = 0.5 * (rho[(bins_ - 1) / 2] + rho[c]);
  if (!concave || !(top > 0)) return 0;
  std::size_t k = c;
  while (k + 1 < bins_ && rho[k + 1] > 0.5 * top) ++k;
  if (k + 1 >= bins_) return 0;  // never half as dense: no peak
  return (static_cast<double>(k) + 1.0 - 0.5 * static_cast<double>(bins_)) / static_cast<double>(bins_);
}

// y / (bin width) of bin b's centre, exact (b - (bins - 1)/2), so that a window |y| <= h takes a
// bin and its mirror image together. bin_centre(b) / bin_width() rounds: with 180 bins across
// 1860 sigma it gave -12.499999999999996 and 12.500000000000007, and the centre window of 1.2.0
// held 25 bins instead of 26 (rho(0) 0.9 % high in a clustered channel).
double ProfileFits::bins_from_centre(std::size_t b) const {
  return static_cast<double>(b) - 0.5 * static_cast<double>(bins_ - 1);
}

// c0 of the least-squares c0 + c2 y^2 over the bins within max(2, bins/15) bin widths of y = 0.
double ProfileFits::local_centre(const double* f) const {
  const double half = static_cast<double>(std::max<std::size_t>(2, bins_ / 15)) + 0.5;  // in bins
  double s0 = 0, s2 = 0, s4 = 0, f0 = 0, f2 = 0;
  for (std::size_t b = 0; b < bins_; ++b) {
    const double d = bins_from_centre(b);  // y in bins
    if (std::fabs(d) > half || !std::isfinite(f[b])) continue;
    const double d2 = d * d;
    s0 += 1; s2 += d2; s4 += d2 * d2; f0 += f[b]; f2 += f[b] * d2;
  }
  const Eigen::Matrix2d normal{{s0, s2}, {s2, s4}};
  return Eigen::Vector2d(normal.ldlt().solve(Eigen::Vector2d(f0, f2)))(0);
}

// Least-squares c_0 + c_1 x + ... + c_degree x^degree through the n bins next to one wall (from
// y_min, or from y_max when upper), x = x_of(b, r) for bin b, the r-th from that wall.
template <class X>
Eigen::VectorXd ProfileFits::wall_polynomial(const double* f, std::size_t n, int degree, bool upper, X x_of) const {
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), degree + 1);
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n));
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t b = upper ? bins_ - 1 - r : r;
    const double x = x_of(b, r);
    double power = 1.0;
    for (int j = 0; j <= degree; ++j, power *= x) A(static_cast<Eigen::Index>(r), j) = power;
    rhs(static_cast<Eigen::Index>(r)) = f[b];
  }
  return A.colPivHouseholderQr().solve(rhs);
}

// Slope d f / d(y/W) into the gas, the two walls averaged: straight lines through the
// wall_fit_bins bins next to each wall.
double ProfileFits::wall_gradient(const double* f) const {
  if (wall_fit_ < 2) return std::nan("");  // fewer than 6 bins
  const auto y = [&](std::size_t b, std::size_t) { return sys_.bin_centre(b) / sys_.box[1]; };
  return 0.5 * (wall_polynomial(f, wall_fit_, 1, false, y)(1) - wall_polynomial(f, wall_fit_, 1, true, y)(1));
}

// {f, df/ds} at the wall (s the distance into the gas, in W) from the least-squares
// f = c0 + c1 s + c2 s^2 over the reach_bins_ bins next to each wall, the two walls averaged.
std::pair<double, double> ProfileFits::wall_extrapolation(const double* f) const {
  const double h = 1.0 / static_cast<double>(bins_);
  const auto s = [&](std::size_t, std::size_t r) { return (static_cast<double>(r) + 0.5) * h; };
  const Eigen::VectorXd lo = wall_polynomial(f, reach_bins_, 2, false, s), hi = wall_polynomial(f, reach_bins_, 2, true, s);
  return {0.5 * (lo(0) + hi(0)), 0.5 * (lo(1) + hi(1))};
}

// T_max: a least-squares parabola over the bins within +-max(2, bins/15) of the largest one
// (one bin alone carries the noise of ~1/bins of the particles); its vertex if it lies in
// that window, else the largest bin. Returns {T_max [T_w], y of the maximum [W]}.
std::pair<double, double> ProfileFits::temperature_maximum(const double* T) const {
  const double width = sys_.box[1], h = 1.0 / static_cast<double>(bins_);
  std::size_t m = 0;
  for (std::size_t b = 1; b < bins_; ++b)
    if (T[b] > T[m]) m = b;
  double tmax = T[m], ymax = sys_.bin_centre(m) / width;
  const std::size_t half = std::max<std::size_t>(2, bins_ / 15);
  const std::size_t lo = m > half ? m - half : 0, hi = std::min(bins_ - 1, m + half);
  if (hi - lo >= 2) {
    Eigen::MatrixXd A(static_cast<Eigen::Index>(hi - lo + 1), 3);
    Eigen::VectorXd rhs(static_cast<Eigen::Index>(hi - lo + 1));
    for (std::size_t b = lo; b <= hi; ++b) {
      const double d = static_cast<double>(b) - static_cast<double>(m);  // in bins
      const auto r = static_cast<Eigen::Index>(b - lo);
      A(r, 0) = 1.0;
      A(r, 1) = d;
      A(r, 2) = d * d;
      rhs(r) = T[b];
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(rhs);
    if (c(2) < 0) {
      const double shift = -c(1) / (2.0 * c(2));
      if (shift >= static_cast<double>(lo) - static_cast<double>(m) && shift <= static_cast<double>(hi) - static_cast<double>(m)) {
        tmax = c(0) - c(1) * c(1) / (4.0 * c(2));
        ymax += shift * h;
      }
    }
  }
  return {tmax, ymax};
}

// Every profile and scalar from one set of sums (the whole window, or the window less a batch).
// peak_half_width: the centre peak's half width at half maximum in W (0: none), or < 0 to find it.
Result ProfileFits::evaluate(const gdsmc::BinSums& s, const double* x, double peak_half_width) const {
  Result r;
  r.scalars.assign(kScalar, std::nan(""));
  r.profiles.assign(kProfile * bins_, std::nan(""));
  const double samples = s.samples();
  if (samples <= 0) return r;
  const double n_av = sys_.number_density, tw = t_wall_, ur = u_ref(), width = sys_.box[1];
  const double bin_volume = sys_.bin_width() * sys_.cross_section();
  const double p_ref = n_av * tw;  // P_R = rho_av u_R^2 / 2 (m = 1)
  double* prof = r.profiles.data();
  auto P = [&](std::size_t k) { return prof + k * bins_; };
  for (std::size_t b = 0; b < bins_; ++b) {
    const gdsmc::BinMoments m = s.moments(b, bin_volume, sys_.mass);  // 004 Eqs. 13-16, 31
    if (m.count <= 0) continue;
    const double n = m.density;
    const double pxx = m.pressure[0], pyy = m.pressure[1], pzz = m.pressure[2], pxy = m.pressure[3];
    const double p = m.pressure_scalar;
    P(pRho)[b] = n / n_av;
    P(pUx)[b] = m.mean[0] / ur;
    P(pT)[b] = m.temperature / tw;
    P(pP)[b] = p / p_ref;
    P(pPxx)[b] = pxx / p_ref;
    P(pPyy)[b] = pyy / p_ref;
    P(pPzz)[b] = pzz / p_ref;
    P(pPxy)[b] = pxy / p_ref;
    P(pN1)[b] = (pxx - pyy) / p;
    P(pN2)[b] = (pyy - pzz) / p;
  }
  for (std::size_t k : {pRho, pUx, pT, pP, pPxx, pPyy, pPzz, pN1, pN2}) symmetrise(P(k));
  // Eq. 33: P_xy(y) = a int_{-W/2}^{y} rho dy' - a rho_av W/2 (in P_R units, y in W, rho in rho_av).
  const double a_red = accel_ * width / p_ref * n_av * sys_.mass;  // a rho_av W / P_R
  double cumulative = 0;
  const double h = 1.0 / static_cast<double>(bins_);
  for (std::size_t b = 0; b < bins_; ++b) {
    const double rho = std::isfinite(P(pRho)[b]) ? P(pRho)[b] : 0.0;
    P(pPxyBalance)[b] = a_red * (cumulative + 0.5 * h * rho - 0.5);
    cumulative += h * rho;
    P(pPxyResidual)[b] = P(pPxy)[b] - P(pPxyBalance)[b];
    P(pKn)[b] = sys_.mean_free_path0 / width / P(pRho)[b];
  }
  double* v = r.scalars.data();
  const double kn = sys_.mean_free_path0 / width;
  // Centre-line values: c0 of c0 + c2 y^2 over the central 2 max(2, bins/15) bins, local enough to
  // follow the sharp density peak of strongly inelastic gases at small Kn (a fit over |y| <= W/4
  // flattens it by half), smooth enough not to carry one bin's noise; curvatures: the wide even
  // fit, normalised by its own f(0).
  const auto [rho0_fit, rho2] = centre_fit(P(pRho), centre_fit_);
  const auto [T0_fit, T2] = centre_fit(P(pT), centre_fit_);
  const double rho0 = local_centre(P(pRho)), T0 = local_centre(P(pT));
  v[rho_centre] = rho0;
  v[rho2_centre] = rho2 / rho0_fit;
  v[T_centre] = T0;
  v[T2_centre] = T2 / T0_fit;
  v[u_centre] = local_centre(P(pUx));
  v[p_centre] = local_centre(P(pP));
  v[N1_centre] = local_centre(P(pN1));
  v[N2_centre] = local_centre(P(pN2));
  v[chi] = kDelta1 * v[T2_centre] + kDelta2 * v[rho2_centre];
  // The centre on the density peak's own scale (a clustered channel's sheet is far narrower than
  // centre_fit): the window is fixed by the whole window's peak, so the jackknife fits alike.
  const double peak = peak_half_width >= 0 ? peak_half_width : centre_peak_half_width(P(pRho), v[rho2_centre] < 0);
  r.peak_half_width = peak;
  if (peak > 0) {
    v[centre_peak_width] = 2.0 * peak;
    const double window = std::max(0.5 * peak, 3.5 / static_cast<double>(bins_));  // FWHM/4 each side
    const auto [rho0_peak, rho2p] = centre_fit(P(pRho), window);
    const auto [T0_peak, T2p] = centre_fit(P(pT), window);
    v[rho2_peak] = rho2p / rho0_peak;
    v[T2_peak] = T2p / T0_peak;
    const double kn0 = kn / rho0_peak;
    v[N1_burnett] = kn0 * kn0 * (kDelta1 * v[T2_peak] + kDelta2 * v[rho2_peak]);  // 004 Eq. 36
    v[N2_burnett] = -v[N1_burnett];                                                 // 004 Eq. 38
  }
  v[rho_fw] = P(pRho)[0];  // symmetrised: the mean of both wall-adjacent bins
  v[Kn_centre] = kn / rho0;
  v[Kn_fw] = kn / v[rho_fw];
  const double* T = P(pT);
  const auto [tmax, ymax] = temperature_maximum(T);
  v[T_max] = tmax;
  v[y_T_max] = std::fabs(ymax);
  v[delta_T] = (tmax - T0) / T0;
  v[u_s] = P(pUx)[0];
  v[du_dy_fw] = wall_gradient(P(pUx));
  v[zeta] = v[u_s] / v[du_dy_fw];
  v[T_s] = T[0] - 1.0;
  v[dT_dy_fw] = wall_gradient(T);
  v[zeta_T] = v[T_s] / v[dT_dy_fw];
  v[drho_dy_fw] = wall_gradient(P(pRho));
  if (reach_bins_ >= 3) {
    const auto [u_w, du_w] = wall_extrapolation(P(pUx));
    const auto [T_w, dT_w] = wall_extrapolation(T);
    v[u_s_wall] = u_w;
    v[du_dy_wall] = du_w;
    v[zeta_wall] = u_w / du_w;
    v[T_s_wall] = T_w - 1.0;
    v[dT_dy_wall] = dT_w;
    v[zeta_T_wall] = (T_w - 1.0) / dT_w;
  }
  const double nsum = samples * static_cast<double>(sys_.particles);
  v[Q] = x[eSumVx] / nsum / (ur * a_hat());
  double worst = 0;
  for (std::size_t b = 0; b < bins_; ++b)
    if (std::isfinite(P(pPxy)[b])) worst = std::max(worst, std::fabs(P(pPxy)[b] - P(pPxyBalance)[b]));
  v[momentum_balance_max] = worst / (0.5 * std::fabs(a_red));
  const double time = x[eTime];
  const double N = static_cast<double>(sys_.particles);
  v[wall_momentum_ratio] = x[eWallMomentum] / (time * N * sys_.mass * accel_);
  const double rate = sys_.time_unit0 / (N * tw * time);  // to T_w per particle per tau0
  v[power_acceleration] = x[eForcings] * rate;
  v[power_collisions] = x[eCollisions] * rate;
  v[power_walls] = x[eWallEnergy] * rate;
  v[energy_balance_closure] = (x[eForcings] + x[eCollisions] + x[eWallEnergy]) / x[eForcings];
  v[power_from_flow_ratio] = sys_.mass * accel_ * x[eSumVx] / samples * time / x[eForcings];
  return r;
}

// The delete-one jackknife variance, times the integrated autocorrelation time of the delete-one
// values in batch order (consecutive batches of a short window are correlated; for a mean this is

}  // namespace poiseuille
