// poiseuille_channel: what it writes. The whole-system sums beside the per-bin ones, the scalars
// and steady profiles in the order the fits of profile_fits.cpp fill them (name, unit, doc), the
// Burnett coefficients of paper 004 and the plugin's documentation text.
#pragma once
#include <cstddef>
#include <vector>

#include <gdsmc/gdsmc.hpp>

namespace poiseuille {

// Per-bin sums over the samples of a batch: gdsmc::BinSums (1, v_a, v_a v_b; N_t), as `profiles`.
// Whole-system sums of a batch, beside them.
enum Extra : std::size_t {
  eTime,         // elapsed time (reduced units)
  eSumVx,        // sum over samples of sum_i v_x,i
  eWallMomentum, // x momentum given to the gas by both walls
  eWallEnergy,   // energy given to the gas by both walls
  eCollisions,   // energy added by the collisions (negative: dissipated)
  eForcings,     // energy added by the forcings (the body acceleration's work)
  kExtra
};

// Scalars derived from a set of sums, in this order.
enum Scalar : std::size_t {
  rho_centre, rho_fw, Kn_centre, Kn_fw, T_centre, T_max, y_T_max, delta_T, u_centre, u_s, du_dy_fw, zeta,
  T_s, dT_dy_fw, zeta_T, drho_dy_fw, p_centre, N1_centre, N2_centre, T2_centre, rho2_centre, chi, Q,
  momentum_balance_max, wall_momentum_ratio, power_acceleration, power_collisions, power_walls,
  energy_balance_closure, power_from_flow_ratio, centre_peak_width, rho2_peak, T2_peak, N1_burnett, N2_burnett,
  // Written only with wall_fit_reach > 0: the wall values of the fixed-reach quadratic fit.
  u_s_wall, du_dy_wall, zeta_wall, T_s_wall, dT_dy_wall, zeta_T_wall, kScalar
};
inline constexpr std::size_t kFirstWallFit = u_s_wall;

struct Column {
  const char* name;
  const char* unit;
  const char* doc;
};

inline constexpr Column kScalars[kScalar] = {
    {"rho_centre", "rho_av", "centre-line density rho(0): local even fit at the centre (004 Fig. 4a)"},
    {"rho_fw", "rho_av", "near-wall density rho_fw = [rho(-W/2) + rho(W/2)]/2, the wall-adjacent bins (004 Eq. 20)"},
    {"Kn_centre", "1", "local Knudsen number at the centre Kn_0 = Kn / rho(0) (004 Eq. 21, Fig. 21)"},
    {"Kn_fw", "1", "near-wall Knudsen number Kn_fw = Kn / rho_fw (004 Eq. 24)"},
    {"T_centre", "T_w", "centre-line temperature T(0): local even fit at the centre"},
    {"T_max", "T_w", "maximum of the temperature profile (vertex of the parabola fitted around the largest bin)"},
    {"y_T_max", "W", "distance |y| of the temperature maximum from the centre line"},
    {"delta_T", "1", "excess temperature Delta T = (T_max - T(0)) / T(0) (004 Eq. 22)"},
    {"u_centre", "sqrt(2T_w/m)", "centre-line velocity u_x(0): local even fit at the centre"},
    {"u_s", "sqrt(2T_w/m)", "slip velocity u_s = [u_x(-W/2) + u_x(W/2)]/2, the wall-adjacent bins (004 Eq. 23)"},
    {"du_dy_fw", "sqrt(2T_w/m)/W", "near-wall velocity gradient u'_w = (du/dy)_fw into the gas (004 Fig. 11b)"},
    {"zeta", "W", "velocity slip length zeta = u_s / u'_w (004 Eq. 25)"},
    {"T_s", "T_w", "temperature slip T_s = T_fw - T_w (004 Eq. 27)"},
    {"dT_dy_fw", "T_w/W", "near-wall temperature gradient T'_w = (dT/dy)_fw into the gas (004 Fig. 12c)"},
    {"zeta_T", "W", "temperature slip length zeta_T = T_s / T'_w (004 Eq. 29)"},
    {"drho_dy_fw", "rho_av/W", "near-wall density gradient rho'_w = (drho/dy)_fw into the gas (the Dufour term of 004 Eq. 30)"},
    {"p_centre", "rho_av u_R^2/2", "centre-line pressure p(0) = tr P / 3 (004 Eq. 31; P_R = n_av T_w)"},
    {"N1_centre", "1", "first normal stress difference at the centre N1(0) = (P_xx - P_yy)/p (004 Eq. 34)"},
    {"N2_centre", "1", "second normal stress difference at the centre N2(0) = (P_yy - P_zz)/p (004 Eq. 35)"},
    {"T2_centre", "1", "curvature T''(0) of T/T(0) against y/W (004 Eq. 36)"},
    {"rho2_centre", "1", "curvature rho''(0)/rho(0) against y/W (004 Eq. 36)"},
    {"chi", "1", "Burnett combination chi = delta1 T''(0) + delta2 rho''(0)/rho(0) (004 Eq. 39)"},
    {"Q", "1", "flow rate Q = int rho u_x dy / (rho_av u_R W a_hat) (004 Eq. 40)"},
    {"momentum_balance_max", "1",
     "max over bins of |P_xy(y) - a int_{-W/2}^{y} rho dy' + a rho_av W/2| / (a rho_av W/2) (004 Eq. 33)"},
    {"wall_momentum_ratio", "1",
     "x momentum the walls gave the gas per unit time over N m a (steady state: -1, the force balance)"},
    {"power_acceleration", "T_w/tau0", "energy per particle and unit time added by the forcings (body acceleration)"},
    {"power_collisions", "T_w/tau0", "energy per particle and unit time added by the collisions (minus the dissipation)"},
    {"power_walls", "T_w/tau0", "energy per particle and unit time given to the gas by both walls"},
    {"energy_balance_closure", "1",
     "(power_acceleration + power_collisions + power_walls) / power_acceleration: dE/dt over the work, 0 when steady"},
    {"power_from_flow_ratio", "1",
     "m a sum_i <v_x,i> (the work rate from the sampled flow) over power_acceleration (1 up to O(a dt))"},
    {"centre_peak_width", "W",
     "full width at half maximum of the density peak at the centre line, to a bin (its error: a bin / sqrt(6)); NaN where "
     "rho is not concave there or never falls to half"},
    {"rho2_peak", "1",
     "curvature rho''(0)/rho(0) against y/W over the peak's own centre, |y| <= max(centre_peak_width/4, 3.5 bins)"},
    {"T2_peak", "1", "curvature T''(0)/T(0) against y/W over the same window as rho2_peak"},
    {"N1_burnett", "1",
     "Burnett N1(0) = Kn_0^2 (delta1 T''(0) + delta2 rho''(0)/rho(0)) with the peak's curvatures and Kn_0 = Kn/rho(0) there (004 Eq. 36)"},
    {"N2_burnett", "1", "Burnett N2(0) = -N1(0) (004 Eq. 38)"},
    {"u_s_wall", "sqrt(2T_w/m)",
     "slip velocity at the wall: u_x(+-W/2) of the quadratic fit over the bins within wall_fit_reach of each wall (004 Eq. 23)"},
    {"du_dy_wall", "sqrt(2T_w/m)/W", "velocity gradient into the gas at the wall, the same fit's slope there (004 Fig. 11b)"},
    {"zeta_wall", "W", "velocity slip length u_s_wall / du_dy_wall (004 Eq. 25)"},
    {"T_s_wall", "T_w", "temperature slip at the wall T(+-W/2) - T_w from the same fit of T (004 Eq. 27)"},
    {"dT_dy_wall", "T_w/W", "temperature gradient into the gas at the wall, the fit's slope there (004 Fig. 12c)"},
    {"zeta_T_wall", "W", "temperature slip length T_s_wall / dT_dy_wall (004 Eq. 29)"},
};

// Profiles written as steady arrays (with errors), in this order.
enum ProfileIndex : std::size_t { pRho, pUx, pT, pP, pPxx, pPyy, pPzz, pPxy, pPxyBalance, pPxyResidual, pN1, pN2, pKn, kProfile };
inline constexpr Column kProfiles[kProfile] = {
    {"rho", "rho_av", "density rho(y) (004 Eq. 14)"},
    {"u_x", "sqrt(2T_w/m)", "streamwise velocity u_x(y) (004 Eq. 15)"},
    {"T", "T_w", "temperature T(y) (004 Eq. 16)"},
    {"p", "rho_av u_R^2/2", "pressure p(y) = tr P / 3 (004 Eq. 31)"},
    {"P_xx", "rho_av u_R^2/2", "P_xx(y) (004 Eq. 31)"},
    {"P_yy", "rho_av u_R^2/2", "P_yy(y) (004 Eq. 31)"},
    {"P_zz", "rho_av u_R^2/2", "P_zz(y) (004 Eq. 31)"},
    {"P_xy", "rho_av u_R^2/2", "shear stress P_xy(y) (004 Eq. 31)"},
    {"P_xy_balance", "rho_av u_R^2/2", "a int_{-W/2}^{y} rho dy' - a rho_av W/2, what Eq. 33 says P_xy(y) is"},
    {"P_xy_residual", "rho_av u_R^2/2", "P_xy - P_xy_balance: the momentum balance of Eq. 33, zero within errors"},
    {"N1", "1", "first normal stress difference N1(y) (004 Eq. 34)"},
    {"N2", "1", "second normal stress difference N2(y) (004 Eq. 35)"},
    {"Kn", "1", "local Knudsen number Kn(y) (004 Eq. 21)"},
};

inline constexpr double kDelta1 = -0.04;  // 004 Eq. 37 (Sela & Goldhirsch)
inline constexpr double kDelta2 = 0.214;  // 004 Eq. 37

inline constexpr const char* kDocumentation =
      "Slab systems between two walls, driven along x by body_acceleration (paper 004). Units as in\n"
      "the paper (Eq. 19): rho in rho_av = m N / volume, T in T_w, u in u_R = sqrt(2 T_w/m), y in\n"
      "W = Ly, stresses in P_R = rho_av u_R^2 / 2 = n_av T_w. T_w is the parameter wall_temperature\n"
      "(default: the system temperature T0); a_hat = a W / u_R^2 (Eq. 17, a the body_acceleration\n"
      "published) and Kn = lambda0 / W (Eq. 18) are written as scalars.\n"
      "Steady state (Appendix): the kinetic energy per particle E(t) is averaged over consecutive\n"
      "windows of steady_window (time); the state is steady from the end of the first window that\n"
      "ends after min_time and whose mean differs from the previous window's by at most\n"
      "steady_tolerance (relative) or by at most steady_sigmas standard errors of the difference (each\n"
      "window mean's error from the means of its 8 equal pieces: a change noise alone explains; the\n"
      "toolkit's gdsmc::SteadyTest). From then on every sample is accumulated (004 Eq. 13) per sampling\n"
      "bin: the sums of 1, v_a and v_a v_b (gdsmc::BinSums), in batches of consecutive records; when\n"
      "64 batches are full, neighbours are merged (32 batches of twice the length), so the batches\n"
      "always cover the whole steady window in 32-64 pieces.\n"
      "Datasets of the group (name [unit]; every scalar and steady array also has <name>_error, the\n"
      "delete-one jackknife error over the batches times the square root of the integrated\n"
      "autocorrelation time of the delete-one values (gdsmc::integrated_autocorrelation_time: batches\n"
      "shorter than the correlation time are not independent); low when the window spans fewer than\n"
      "about 5 correlation times; with run.realizations the host's <name>_stderr is the safer one):\n"
      "  series per record: E [T_w] (kinetic energy per particle, Eq. A1), steady [1] (0/1),\n"
      "  Q_record [1] (Eq. 40 over the record);\n"
      "  a_hat [1] (Eq. 17; written as the run begins, so `gdsmc validate` shows it), Kn [1] (lambda0/W,\n"
      "  Eq. 18), steady_from [tau0], averaged_time [tau0], batches [1], momentum_balance_chi2 [1];\n"
      "  y [W] (bin centres y/W) and the steady profiles over it, from the sums of the whole window,\n"
      "  the even ones (all but P_xy) symmetrised, bin b with its mirror image: steady_rho [rho_av],\n"
      "  steady_u_x [sqrt(2T_w/m)], steady_T [T_w], steady_p, steady_P_xx, steady_P_yy, steady_P_zz,\n"
      "  steady_P_xy, steady_P_xy_balance (a int rho dy, Eq. 33), steady_P_xy_residual [rho_av u_R^2/2],\n"
      "  steady_N1, steady_N2, steady_Kn [1];\n"
      "  centre-line values, c0 of the least-squares c0 + c2 y^2 over the bins within max(2, bins/15)\n"
      "  bin widths of the centre: rho_centre [rho_av] (rho(0)), T_centre [T_w] (T(0)), u_centre\n"
      "  [sqrt(2T_w/m)] (u_x(0)), p_centre [rho_av u_R^2/2] (p(0)), N1_centre, N2_centre [1] (N1(0),\n"
      "  N2(0), Eqs. 34-35), Kn_centre [1] (Kn_0 = Kn/rho(0), Eq. 21);\n"
      "  curvatures T2_centre [1] (T''(0)/T(0)) and rho2_centre [1] (rho''(0)/rho(0)): least-squares\n"
      "  f = c0 + c2 y^2 + c4 y^4 (Eigen) over the bins with |y| <= centre_fit W, f''(0)/f(0) = 2 c2/c0\n"
      "  (unreliable where the centre is a cusp, as for e_n <= 0.6 at Kn = 0.05); chi [1] = delta1\n"
      "  T''(0) + delta2 rho''(0)/rho(0), delta1 = -0.04, delta2 = 0.214 (Eqs. 37, 39);\n"
      "  where the centre is a density peak (a clustered channel), the same on the peak's own scale:\n"
      "  centre_peak_width [W] (its full width at half maximum), rho2_peak, T2_peak [1] (the even fit\n"
      "  over |y| <= max(centre_peak_width/4, 3.5 bins), fixed by the whole window for the jackknife),\n"
      "  N1_burnett [1] = Kn_0^2 (delta1 T2_peak + delta2 rho2_peak), Kn_0 = Kn/rho(0) of that fit\n"
      "  (Eq. 36), N2_burnett = -N1_burnett (Eq. 38); NaN where rho is not concave at the centre\n"
      "  (rho2_centre >= 0) or never falls to half its centre value;\n"
      "  near-wall values from the wall-adjacent bins, as the paper (so they depend on the bin width,\n"
      "  004 Sec. III.D.1): rho_fw [rho_av] (Eq. 20), Kn_fw [1] (Eq. 24), u_s [sqrt(2T_w/m)] (slip,\n"
      "  Eq. 23), T_s [T_w] (T_fw - T_w, Eq. 27); gradients into the gas by a straight-line fit over the\n"
      "  wall_fit_bins bins next to each wall (at most bins/2 - 1; NaN with fewer than 6 bins), the two\n"
      "  walls averaged: du_dy_fw [sqrt(2T_w/m)/W] (u'_w), dT_dy_fw [T_w/W] (T'_w), drho_dy_fw [rho_av/W]\n"
      "  (rho'_w, the Dufour term of Eq. 30); slip lengths\n"
      "  zeta [W] = u_s/u'_w (Eq. 25) and zeta_T [W] = T_s/T'_w (Eq. 29);\n"
      "  with wall_fit_reach > 0, the same at the wall itself, independent of the bin width: a\n"
      "  least-squares f = c0 + c1 s + c2 s^2 (s the distance from the wall, in W) over the bins whose\n"
      "  centres lie within wall_fit_reach of each wall (at least 3, at most bins/2 - 1), c0 and c1 the\n"
      "  two walls averaged: u_s_wall [sqrt(2T_w/m)], du_dy_wall [sqrt(2T_w/m)/W], zeta_wall [W],\n"
      "  T_s_wall [T_w], dT_dy_wall [T_w/W], zeta_T_wall [W], and wall_fit_reach [W], wall_fit_bins_used\n"
      "  [1]; the adjacent bins' values move with the bin width by about the gradient times half a bin,\n"
      "  these by the fit's noise (the values still depend on the reach inside a Knudsen layer);\n"
      "  T_max [T_w]: the vertex of the least-squares parabola through the bins within max(2,\n"
      "  bins/15) of the largest bin of T (the largest bin if the vertex falls outside), y_T_max [W]\n"
      "  its |y|, delta_T [1] = (T_max - T(0))/T(0) (Eq. 22);\n"
      "  Q [1] (Eq. 40) = <v_x> over all particles and samples / (u_R a_hat) (= int rho u dy / (rho_av\n"
      "  u_R W a_hat) exactly: the integral is the mean streamwise velocity of all particles);\n"
      "  checks that must hold in every steady run: momentum_balance_max [1] (Eq. 33: the shear stress\n"
      "  against a times the integrated density, relative to the wall stress a rho_av W/2),\n"
      "  wall_momentum_ratio [1] (the walls take out what the acceleration puts in: -1),\n"
      "  power_acceleration, power_collisions, power_walls [T_w/tau0 per particle] and\n"
      "  energy_balance_closure [1] (work of the acceleration + collisions + walls = dE/dt: ~ 0),\n"
      "  power_from_flow_ratio [1] (the work computed from the sampled flow over the host's ledger: 1).\n"
      "Trends of the records (record_trends.hpp), written in every run so that no report fits them:\n"
      "  E_drift [1] (the least-squares slope of the E records from steady_from on, times the time\n"
      "  between the first and last of them, over their mean: ~0 when steady; NaN without 4 records\n"
      "  there), E_relative_rms [1] (their rms about the mean, n - 1, over the mean), Q_growth_rate\n"
      "  [1/tau0] (the least-squares dQ/d(t/tau0) of Q_record over the last three quarters of the\n"
      "  records, steady or not: Kn exactly between specular walls, where nothing balances the\n"
      "  acceleration and no steady state exists (Eq. 40); ~0 in a steady run).\n"
      "A run that never becomes steady writes NaN and says so in the summary.\n"
      "Parameters: steady_window (time, bare tau0; required), steady_tolerance (default 0.005),\n"
      "steady_sigmas (default 2), "
      "min_time (bare tau0, default 0), wall_temperature (bare T0, default 1), centre_fit (default\n"
      "0.25), wall_fit_bins (default 3), wall_fit_reach (length, bare lambda0; default 0: off).";

// The scalars and profiles of one set of sums, in the order of kScalars and kProfiles.
struct Result {
  std::vector<double> scalars;   // kScalar
  std::vector<double> profiles;  // kProfile x bins
  double peak_half_width = 0;    // the centre peak's half width at half maximum [W] (0: no peak)
};

// Write the scalars (with wall_fit_reach's only when reach_bins >= 3), momentum_balance_chi2, y and
// the steady profiles, each with its _error; `used`: the batches of the jackknife.
void write_columns(gdsmc::OutputSink& out, const gdsmc::SystemInfo& sys, const Result& whole, const Result& err,
                   std::size_t used, std::size_t reach_bins);

}  // namespace poiseuille
