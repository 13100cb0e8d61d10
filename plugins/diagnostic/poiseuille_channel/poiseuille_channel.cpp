// The acceleration-driven Poiseuille channel of paper 004: steady profiles after the total energy
// has settled (Appendix), and every derived quantity of Secs. IV-VI with jackknife errors.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/bins.hpp>
#include <gdsmc/physics/series.hpp>
#include <gdsmc/physics/steady.hpp>

namespace {

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
constexpr std::size_t kFirstWallFit = u_s_wall;

struct Column {
  const char* name;
  const char* unit;
  const char* doc;
};

constexpr Column kScalars[kScalar] = {
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
constexpr Column kProfiles[kProfile] = {
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

constexpr double kDelta1 = -0.04;  // 004 Eq. 37 (Sela & Goldhirsch)
constexpr double kDelta2 = 0.214;  // 004 Eq. 37
constexpr std::size_t kMaxBatches = 64;

class PoiseuilleChannel final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "poiseuille_channel";
  static constexpr const char* version = "1.8.0";
  static constexpr const char* summary =
      "Granular Poiseuille flow (004): steady profiles once E(t) settles, slip, bimodality, N1, N2, chi, Q, balances";
  static constexpr const char* documentation =
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
      "A run that never becomes steady writes NaN and says so in the summary.\n"
      "Parameters: steady_window (time, bare tau0; required), steady_tolerance (default 0.005),\n"
      "steady_sigmas (default 2), "
      "min_time (bare tau0, default 0), wall_temperature (bare T0, default 1), centre_fit (default\n"
      "0.25), wall_fit_bins (default 3), wall_fit_reach (length, bare lambda0; default 0: off).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("steady_window", "window of the energy test of the steady state (bare: tau0)")
                .above(0.0)
                .unit(gdsmc::Dimension::time),
            gdsmc::ParamSpec::real("steady_tolerance", "largest relative change of the window mean of E(t) when steady")
                .above(0.0)
                .default_value(0.005),
            gdsmc::ParamSpec::real("steady_sigmas",
                                   "a change of the window mean within this many standard errors (noise) also counts as settled; 0: tolerance only")
                .at_least(0.0)
                .default_value(2.0),
            gdsmc::ParamSpec::real("min_time", "never steady before this time (bare: tau0)")
                .at_least(0.0)
                .unit(gdsmc::Dimension::time)
                .default_value(0.0),
            gdsmc::ParamSpec::real("wall_temperature", "T_w of the units and of the temperature slip (bare: T0)")
                .above(0.0)
                .unit(gdsmc::Dimension::temperature)
                .default_value(1.0),
            gdsmc::ParamSpec::real("centre_fit", "half-width of the curvature fit at the centre line, in W").range(0.05, 0.5).default_value(0.25),
            gdsmc::ParamSpec::integer("wall_fit_bins", "bins next to each wall in the gradient fit (at most bins/2 - 1 are used)")
                .range(2, 50)
                .default_value(3),
            gdsmc::ParamSpec::real("wall_fit_reach",
                                   "distance from each wall of the quadratic fit that gives the wall values u_s_wall ... (bare: lambda0; 0: off)")
                .at_least(0.0)
                .unit(gdsmc::Dimension::length)
                .default_value(0.0)};
  }
  explicit PoiseuilleChannel(const gdsmc::Params& p)
      : window_(p.real("steady_window")),
        tolerance_(p.real("steady_tolerance")),
        sigmas_(p.real("steady_sigmas")),
        min_time_(p.real("min_time")),
        t_wall_(p.real("wall_temperature")),
        centre_fit_(p.real("centre_fit")),
        wall_bins_(static_cast<std::size_t>(p.integer("wall_fit_bins"))),
        wall_reach_(p.real("wall_fit_reach")) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& quantities, gdsmc::OutputSink& out) override {
    // What it measures is a steady state: `gdsmc plot` draws the steady means of its series.
    out.attribute("stationary", "all");
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("poiseuille_channel: needs a slab system (system.domain: slab) between two walls");
    sys_ = sys;
    // Written as the run begins, so that `gdsmc validate` shows them (the samples then read a).
    const double* a = quantities.find("body_acceleration");
    accel_ = a ? *a : 0.0;
    out.scalar("a_hat", a_hat(), "1", "dimensionless acceleration a_hat = a W / (2 T_w/m) (004 Eq. 17)");
    bins_ = sys.bins;
    // The wall fits use at most the wall-side half of the bins (less the central one).
    wall_fit_ = std::min(wall_bins_, bins_ / 2 > 0 ? bins_ / 2 - 1 : 0);
    // The fixed-reach fit: the bins whose centres lie within wall_fit_reach of the wall.
    reach_bins_ = 0;
    if (wall_reach_ > 0) {
      const double bin = sys_.bin_width();
      while (reach_bins_ + 1 < bins_ / 2 && (static_cast<double>(reach_bins_) + 0.5) * bin <= wall_reach_) ++reach_bins_;
      if (reach_bins_ < 3) {
        char why[512];
        std::snprintf(why, sizeof why,
                      "poiseuille_channel: wall_fit_reach = %.4g lambda0 holds %zu bin centre(s) next to each wall "
                      "(bins %.4g lambda0 wide, %zu bins); the quadratic wall fit needs 3: give wall_fit_reach >= %.4g "
                      "lambda0, more bins (system.bins), or 0 to switch it off",
                      wall_reach_ / sys_.mean_free_path0, reach_bins_, bin / sys_.mean_free_path0, bins_,
                      2.5 * bin / sys_.mean_free_path0);
        throw std::runtime_error(why);
      }
    }
    batches_.resize(kMaxBatches);
    for (auto& b : batches_) b.begin(bins_, false);
    total_.begin(bins_, false);
    work_.begin(bins_, false);
    extras_.assign(kMaxBatches * kExtra, 0.0);
    filled_ = 0;
    batch_records_ = 1;
    records_in_batch_ = 0;
    steady_ = false;
    steady_from_ = std::nan("");
    steady_test_.configure(window_, tolerance_, sigmas_);
    steady_test_.start(0.0);
    record_e_ = record_vx_ = 0;
    record_samples_ = 0;
    have_last_ = false;
    id_e_ = out.series("E", "T_w", "kinetic energy per particle E(t) = (m/2) sum v^2 / N (004 Eq. A1), mean over the record");
    id_steady_ = out.series("steady", "1", "1 once E(t) has settled (the averaging window), else 0");
    id_q_ = out.series("Q_record", "1", "flow rate of Eq. 40 over the record's samples");
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double e = ctx.moments->kinetic_energy / static_cast<double>(p.count);
    double sum_vx = 0;
    for (std::size_t i = 0; i < p.count; ++i) sum_vx += p.vx[i];
    record_e_ += e;
    record_vx_ += sum_vx;
    ++record_samples_;
    accel_ = ctx.body_acceleration.x;
    if (!steady_) {
      // The energy test of the Appendix (gdsmc::SteadyTest): consecutive window means of E(t).
      if (!steady_test_.add(ctx.time, e) || ctx.time < min_time_) return;
      steady_ = true;
      steady_from_ = ctx.time;
      filled_ = 1;  // open the first batch; this sample is its first
      have_last_ = false;
    }
    // Accumulate into the open batch (the last filled_ slot).
    batches_[filled_ - 1].add_sample(sys_, p);
    double* x = &extras_[(filled_ - 1) * kExtra];
    x[eSumVx] += sum_vx;
    const Ledger now = ledger(ctx);
    if (have_last_) {
      x[eTime] += ctx.time - last_.time;
      x[eWallMomentum] += now.wall_momentum - last_.wall_momentum;
      x[eWallEnergy] += now.wall_energy - last_.wall_energy;
      x[eCollisions] += now.collisions - last_.collisions;
      x[eForcings] += now.forcings - last_.forcings;
    }
    last_ = now;
    have_last_ = true;
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double ns = static_cast<double>(record_samples_);
    out.append(id_e_, record_samples_ ? record_e_ / ns / t_wall_ : std::nan(""));
    out.append(id_steady_, steady_ ? 1.0 : 0.0);
    out.append(id_q_, record_samples_ ? record_vx_ / (ns * static_cast<double>(sys_.particles)) / (u_ref() * a_hat())
                                      : std::nan(""));
    record_e_ = record_vx_ = 0;
    record_samples_ = 0;
    if (!steady_ || filled_ == 0) return;
    // Close the record in the open batch; open the next batch when this one has its length.
    if (++records_in_batch_ < batch_records_) return;
    records_in_batch_ = 0;
    if (filled_ == kMaxBatches) {  // merge neighbours: 8 batches of twice the length
      for (std::size_t k = 0; k < kMaxBatches / 2; ++k) {
        batches_[k].copy_from(batches_[2 * k]);
        batches_[k].append(batches_[2 * k + 1]);
        double* dst = &extras_[k * kExtra];
        const double* a = &extras_[2 * k * kExtra];
        const double* c = &extras_[(2 * k + 1) * kExtra];
        for (std::size_t j = 0; j < kExtra; ++j) dst[j] = a[j] + c[j];
      }
      for (std::size_t k = kMaxBatches / 2; k < kMaxBatches; ++k) batches_[k].clear();
      std::fill(extras_.begin() + static_cast<std::ptrdiff_t>(kMaxBatches / 2 * kExtra), extras_.end(), 0.0);
      filled_ = kMaxBatches / 2;
      batch_records_ *= 2;
    }
    ++filled_;  // the next batch opens (empty)
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.scalar("Kn", sys_.mean_free_path0 / sys_.box[1], "1", "Knudsen number lambda0 / W (004 Eq. 18)");
    out.scalar("steady_from", steady_ ? steady_from_ / sys_.time_unit0 : std::nan(""), "tau0",
               "time at which E(t) was found steady and averaging began");
    // The batches that hold samples (the open one may be empty).
    std::size_t used = 0;
    for (std::size_t k = 0; k < filled_; ++k)
      if (batches_[k].samples() > 0) ++used;
    out.scalar("batches", static_cast<double>(used), "1", "batches of the steady window in the jackknife");
    // The whole window: the batches appended in order (the order rule of gdsmc/physics/bins.hpp).
    total_.clear();
    std::vector<double> total(kExtra, 0.0);
    for (std::size_t k = 0; k < used; ++k) {
      total_.append(batches_[k]);
      for (std::size_t j = 0; j < kExtra; ++j) total[j] += extras_[k * kExtra + j];
    }
    out.scalar("averaged_time", total[eTime] / sys_.time_unit0, "tau0", "length of the steady window");

    Result whole = evaluate(total_, total.data());
    Result err;
    err.scalars.assign(kScalar, std::nan(""));
    err.profiles.assign(kProfile * bins_, std::nan(""));
    if (used >= 2) {
      std::vector<Result> jack;
      std::vector<double> work(kExtra);
      for (std::size_t k = 0; k < used; ++k) {
        work_.copy_from(total_);
        work_.subtract(batches_[k]);
        for (std::size_t j = 0; j < kExtra; ++j) work[j] = total[j] - extras_[k * kExtra + j];
        jack.push_back(evaluate(work_, work.data(), whole.peak_half_width));
      }
      jackknife(jack, whole.scalars, err.scalars, [](const Result& r) -> const std::vector<double>& { return r.scalars; });
      jackknife(jack, whole.profiles, err.profiles, [](const Result& r) -> const std::vector<double>& { return r.profiles; });
    }
    // The peak's width is fixed by the whole window (the jackknife fits over the same bins): its error
    // is the resolution of its two edges, a bin width / sqrt(6).
    if (std::isfinite(whole.scalars[centre_peak_width]))
      err.scalars[centre_peak_width] = 1.0 / (static_cast<double>(bins_) * std::sqrt(6.0));
    // A NaN error says why (issue 29: no NaN error without its reason and the remedy).
    const auto error_doc = [&](const std::string& what, double value, double error) {
      std::string doc = "jackknife error over the batches of " + what + " (times the square root of the delete-one values' integrated autocorrelation time)";
      if (std::isfinite(error)) return doc;
      if (used < 2)
        return doc + "; NaN: the steady window holds " + std::to_string(used) +
               " batch(es) (E(t) never settled, or the run stopped right after it did): run longer (run.stop) or "
               "lower min_time; with run.realizations >= 2 the host's _stderr is the realizations' scatter";
      if (!std::isfinite(value)) return doc + "; NaN: the value itself is undefined in this run (see its description)";
      return doc + "; NaN: the value is undefined in some batch's complement (a gradient or fit without enough "
                   "finite bins there): run longer so that every batch fills every bin";
    };
    if (reach_bins_ >= 3) {
      out.scalar("wall_fit_reach", static_cast<double>(reach_bins_) / static_cast<double>(bins_), "W",
                 "distance from the wall spanned by the bins of the quadratic wall fit (their outer edge)");
      out.scalar("wall_fit_bins_used", static_cast<double>(reach_bins_), "1", "bins next to each wall in the quadratic wall fit");
    }
    for (std::size_t s = 0; s < kScalar; ++s) {
      if (s >= kFirstWallFit && reach_bins_ < 3) continue;  // wall_fit_reach off
      out.scalar(kScalars[s].name, whole.scalars[s], kScalars[s].unit, kScalars[s].doc);
      out.scalar(std::string(kScalars[s].name) + "_error", err.scalars[s], kScalars[s].unit,
                 s == centre_peak_width && std::isfinite(err.scalars[s])
                     ? "the resolution of the peak's two edges, a bin width / sqrt(6) (the width is fixed by the whole window)"
                     : error_doc(kScalars[s].name, whole.scalars[s], err.scalars[s]));
    }
    double chi2 = 0;
    std::size_t terms = 0;
    for (std::size_t b = 0; b < bins_; ++b) {
      const double res = whole.profiles[pPxyResidual * bins_ + b], e = err.profiles[pPxyResidual * bins_ + b];
      if (std::isfinite(res) && e > 0) {
        chi2 += res * res / (e * e);
        ++terms;
      }
    }
    out.scalar("momentum_balance_chi2", terms ? chi2 / static_cast<double>(terms) : std::nan(""), "1",
               "mean over bins of (P_xy_residual / its jackknife error)^2: about 1 when Eq. 33 holds");
    std::vector<double> y(bins_);
    for (std::size_t b = 0; b < bins_; ++b) y[b] = sys_.bin_centre(b) / sys_.box[1];
    out.array("y", y, {bins_}, "W", "bin centres y / W of the steady profiles");
    for (std::size_t k = 0; k < kProfile; ++k) {
      std::vector<double> v(whole.profiles.begin() + static_cast<std::ptrdiff_t>(k * bins_),
                            whole.profiles.begin() + static_cast<std::ptrdiff_t>((k + 1) * bins_));
      std::vector<double> e(err.profiles.begin() + static_cast<std::ptrdiff_t>(k * bins_),
                            err.profiles.begin() + static_cast<std::ptrdiff_t>((k + 1) * bins_));
      out.array(std::string("steady_") + kProfiles[k].name, v, {bins_}, kProfiles[k].unit,
                std::string("steady ") + kProfiles[k].doc);
      const bool any_nan = std::any_of(e.begin(), e.end(), [](double x) { return !std::isfinite(x); });
      const bool value_nan = std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); });
      out.array(std::string("steady_") + kProfiles[k].name + "_error", e, {bins_}, kProfiles[k].unit,
                any_nan ? error_doc("steady_" + std::string(kProfiles[k].name) + " (some bins)",
                                    value_nan ? std::nan("") : 0.0, std::nan(""))
                        : std::string("jackknife error of steady_") + kProfiles[k].name);
    }
    char line[512];
    if (!steady_) {
      out.summary("poiseuille_channel: E(t) never settled within the steady tolerance: no steady averages (NaN); "
                  "run longer or loosen steady_tolerance");
      return;
    }
    std::snprintf(line, sizeof line,
                  "poiseuille_channel: steady from t = %.4g tau0 over %.4g tau0: Q = %.5g +- %.2g, rho(0) = %.4g, "
                  "u_s = %.4g, Delta T = %.4g +- %.2g, N1(0) = %.3g, N2(0) = %.3g; momentum balance max %.2g, "
                  "wall/body force %.5g, energy closure %.2g",
                  steady_from_ / sys_.time_unit0, total[eTime] / sys_.time_unit0, whole.scalars[Q],
                  err.scalars[Q], whole.scalars[rho_centre], whole.scalars[u_s], whole.scalars[delta_T],
                  err.scalars[delta_T], whole.scalars[N1_centre], whole.scalars[N2_centre],
                  whole.scalars[momentum_balance_max], whole.scalars[wall_momentum_ratio],
                  whole.scalars[energy_balance_closure]);
    out.summary(line);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    for (std::size_t k = 0; k < kMaxBatches; ++k) batches_[k].save(out, "batch" + std::to_string(k));
    out.write("batch_extras", extras_);
    const std::uint64_t counts[3] = {filled_, batch_records_, records_in_batch_};
    out.write("batch_counts", counts, 3);
    out.write("steady", steady_);
    out.write("steady_from", steady_from_);
    steady_test_.save(out, "steady_test");
    out.write("record_samples", static_cast<std::uint64_t>(record_samples_));
    out.write("record_e", record_e_);
    out.write("record_vx", record_vx_);
    out.write("accel", accel_);  // set by the first sample; a_hat() needs it
    out.write("have_last", have_last_);
    const double last[5] = {last_.time, last_.wall_momentum, last_.wall_energy, last_.collisions, last_.forcings};
    out.write("last", last, 5);
  }
  void load_state(gdsmc::StateReader& in) override {
    for (std::size_t k = 0; k < kMaxBatches; ++k) batches_[k].load(in, "batch" + std::to_string(k));  // as begin() sized them
    in.read("batch_extras", extras_.data(), extras_.size());
    std::uint64_t counts[3];
    in.read("batch_counts", counts, 3);
    if (counts[0] > kMaxBatches || counts[1] == 0 || counts[2] >= counts[1])
      throw gdsmc::StateError("checkpoint entry 'batch_counts': not a batch state of poiseuille_channel");
    filled_ = static_cast<std::size_t>(counts[0]);
    batch_records_ = static_cast<std::size_t>(counts[1]);
    records_in_batch_ = static_cast<std::size_t>(counts[2]);
    in.read("steady", steady_);
    in.read("steady_from", steady_from_);
    steady_test_.load(in, "steady_test");
    std::uint64_t record_samples = 0;
    in.read("record_samples", record_samples);
    record_samples_ = static_cast<std::size_t>(record_samples);
    in.read("record_e", record_e_);
    in.read("record_vx", record_vx_);
    in.read("accel", accel_);
    in.read("have_last", have_last_);
    double last[5];
    in.read("last", last, 5);
    last_ = {last[0], last[1], last[2], last[3], last[4]};
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads only the kinetic energy of the host's sampled moments (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_energy>(id);
  }
 private:
  struct Ledger {
    double time = 0, wall_momentum = 0, wall_energy = 0, collisions = 0, forcings = 0;
  };
  struct Result {
    std::vector<double> scalars;   // kScalar
    std::vector<double> profiles;  // kProfile x bins
    double peak_half_width = 0;    // the centre peak's half width at half maximum [W] (0: no peak)
  };

  double u_ref() const { return std::sqrt(2.0 * t_wall_ / sys_.mass); }
  double a_hat() const { return accel_ * sys_.box[1] / (u_ref() * u_ref()); }  // 004 Eq. 17

  static Ledger ledger(const gdsmc::StepContext& ctx) {
    Ledger l;
    l.time = ctx.time;
    for (std::size_t w = 0; w < ctx.boundary_count; ++w) {
      l.wall_momentum += ctx.boundaries[w].momentum[0];
      l.wall_energy += ctx.boundaries[w].energy;
    }
    for (std::size_t k = 0; k < ctx.energy_ledger_size; ++k) {  // no std::string: called every sample
      const char* stage = ctx.energy_ledger[k].stage;
      if (std::strcmp(stage, "collisions") == 0) l.collisions += ctx.energy_ledger[k].energy;
      else if (std::strcmp(stage, "y_min") != 0 && std::strcmp(stage, "y_max") != 0) l.forcings += ctx.energy_ledger[k].energy;
    }
    return l;
  }

  // Symmetrise an even profile: bin b and its mirror bins-1-b get their mean.
  void symmetrise(double* v) const {
    for (std::size_t b = 0; b < bins_ / 2; ++b) {
      const double m = 0.5 * (v[b] + v[bins_ - 1 - b]);
      v[b] = v[bins_ - 1 - b] = m;
    }
  }

  // Least-squares f = c0 + c2 y^2 + c4 y^4 over |y| <= half_width (y in W): returns {f(0), f''(0)}.
  std::pair<double, double> centre_fit(const double* f, double half_width) const {
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
  double centre_peak_half_width(const double* rho, bool concave) const {
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
  double bins_from_centre(std::size_t b) const {
    return static_cast<double>(b) - 0.5 * static_cast<double>(bins_ - 1);
  }

  // c0 of the least-squares c0 + c2 y^2 over the bins within max(2, bins/15) bin widths of y = 0.
  double local_centre(const double* f) const {
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
  Eigen::VectorXd wall_polynomial(const double* f, std::size_t n, int degree, bool upper, X x_of) const {
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
  double wall_gradient(const double* f) const {
    if (wall_fit_ < 2) return std::nan("");  // fewer than 6 bins
    const auto y = [&](std::size_t b, std::size_t) { return sys_.bin_centre(b) / sys_.box[1]; };
    return 0.5 * (wall_polynomial(f, wall_fit_, 1, false, y)(1) - wall_polynomial(f, wall_fit_, 1, true, y)(1));
  }

  // {f, df/ds} at the wall (s the distance into the gas, in W) from the least-squares
  // f = c0 + c1 s + c2 s^2 over the reach_bins_ bins next to each wall, the two walls averaged.
  std::pair<double, double> wall_extrapolation(const double* f) const {
    const double h = 1.0 / static_cast<double>(bins_);
    const auto s = [&](std::size_t, std::size_t r) { return (static_cast<double>(r) + 0.5) * h; };
    const Eigen::VectorXd lo = wall_polynomial(f, reach_bins_, 2, false, s), hi = wall_polynomial(f, reach_bins_, 2, true, s);
    return {0.5 * (lo(0) + hi(0)), 0.5 * (lo(1) + hi(1))};
  }

  // Every profile and scalar from one set of sums (the whole window, or the window less a batch).
  // peak_half_width: the centre peak's half width at half maximum in W (0: none), or < 0 to find it.
  Result evaluate(const gdsmc::BinSums& s, const double* x, double peak_half_width = -1) const {
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
    // T_max: a least-squares parabola over the bins within +-max(2, bins/15) of the largest one
    // (one bin alone carries the noise of ~1/bins of the particles); its vertex if it lies in
    // that window, else the largest bin.
    const double* T = P(pT);
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
  // BatchMeans' error).
  template <class Get>
  static void jackknife(const std::vector<Result>& jack, const std::vector<double>& whole, std::vector<double>& err, Get get) {
    const double B = static_cast<double>(jack.size());
    std::vector<double> v(jack.size());
    for (std::size_t j = 0; j < whole.size(); ++j) {
      double mean = 0;
      for (std::size_t k = 0; k < jack.size(); ++k) mean += (v[k] = get(jack[k])[j]);
      mean /= B;
      double ss = 0;
      for (const double x : v) ss += (x - mean) * (x - mean);
      const double tau = std::isfinite(ss) ? gdsmc::integrated_autocorrelation_time(v.data(), v.size()) : 1.0;
      err[j] = std::sqrt((B - 1.0) / B * ss * tau);
    }
  }

  double window_, tolerance_, sigmas_, min_time_, t_wall_, centre_fit_;
  std::size_t wall_bins_, wall_fit_ = 0;
  double wall_reach_;           // wall_fit_reach (reduced length; 0: off)
  std::size_t reach_bins_ = 0;  // bins of the quadratic wall fit
  gdsmc::SystemInfo sys_;
  std::size_t bins_ = 0, filled_ = 0, batch_records_ = 1, records_in_batch_ = 0;
  std::vector<gdsmc::BinSums> batches_;  // kMaxBatches per-bin sums
  std::vector<double> extras_;           // kMaxBatches x kExtra whole-system sums
  gdsmc::BinSums total_, work_;          // finish(): the whole window, the window less one batch
  bool steady_ = false, have_last_ = false;
  double steady_from_ = 0;
  gdsmc::SteadyTest steady_test_;
  std::size_t record_samples_ = 0;
  double record_e_ = 0, record_vx_ = 0, accel_ = 0;
  Ledger last_;
  std::size_t id_e_ = 0, id_steady_ = 0, id_q_ = 0;
};

}  // namespace

GDSMC_PLUGIN(PoiseuilleChannel)

// What `gdsmc conformance` runs it in when no --context is given.
// A channel: a slab of 12 layers (its wall-gradient fits) between diffuse walls, driven along x.
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 12}\n"
    "forcings: [{plugin: body_acceleration, acceleration: 0.5}]\n"
    "boundaries: {y: diffuse_wall}")
