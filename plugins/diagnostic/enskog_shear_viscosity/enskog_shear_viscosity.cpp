// The Navier-Stokes shear viscosity of the modified uniform shear flow (paper 002): kinetic and
// collisional pressure tensors, eta(t) = -P_xy/a, Kn(t), the cumulant c(t), the first-Sonine
// theory of Eqs. 16-18 and the long-time plateau.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

using gdsmc::enskog_hcs_cumulant;
using gdsmc::enskog_kinetic_viscosity;
using gdsmc::enskog_viscosity;

// The grids of the first-Sonine curves of 002 Figs. 3-4: phi at the run's alpha, alpha at its phi.
constexpr double kPhiGridFirst = 1e-4, kPhiGridLast = 0.52, kAlphaGridFirst = 0.58, kAlphaGridLast = 1.0;
constexpr std::size_t kPhiGridPoints = 300, kAlphaGridPoints = 200;

// n points from first to last, evenly spaced (numpy's linspace).
std::vector<double> linspace(double first, double last, std::size_t n) {
  std::vector<double> x(n);
  const double step = (last - first) / static_cast<double>(n - 1);
  for (std::size_t k = 0; k < n; ++k) x[k] = first + static_cast<double>(k) * step;
  x[n - 1] = last;
  return x;
}

// y = b0 + b1 x by least squares from streamed sums (no storage): the intercept is the
// Navier-Stokes value at Kn^2 -> 0, its error from the residual scatter.
class PlateauFit {
 public:
  void add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    const Eigen::Vector2d row(1.0, x);
    normal_ += row * row.transpose();
    rhs_ += row * y;
    yy_ += y * y;
    ++count_;
  }
  std::size_t count() const { return count_; }
  // {intercept, its standard error, slope, its standard error}; NaN with fewer than 3 points.
  Eigen::Vector4d result() const {
    const double nan = std::nan("");
    if (count_ < 3 || std::fabs(normal_.determinant()) < 1e-300) return {nan, nan, nan, nan};
    const Eigen::Matrix2d inverse = normal_.inverse();
    const Eigen::Vector2d beta = normal_.ldlt().solve(rhs_);
    const double rss = std::max(0.0, yy_ - 2.0 * beta.dot(rhs_) + beta.dot(normal_ * beta));
    const double s2 = rss / static_cast<double>(count_ - 2);
    return {beta(0), std::sqrt(s2 * inverse(0, 0)), beta(1), std::sqrt(s2 * inverse(1, 1))};
  }
  // Checkpoints: the streamed sums {normal (column-major), rhs, yy} and the count, under `prefix`.
  void save(gdsmc::StateWriter& out, const std::string& prefix) const {
    const double sums[7] = {normal_(0, 0), normal_(1, 0), normal_(0, 1), normal_(1, 1), rhs_(0), rhs_(1), yy_};
    out.write(prefix + ".sums", sums, 7);
    out.write(prefix + ".count", static_cast<std::uint64_t>(count_));
  }
  void load(gdsmc::StateReader& in, const std::string& prefix) {
    double sums[7];
    in.read(prefix + ".sums", sums, 7);
    normal_ << sums[0], sums[2], sums[1], sums[3];
    rhs_ << sums[4], sums[5];
    yy_ = sums[6];
    std::uint64_t count = 0;
    in.read(prefix + ".count", count);
    count_ = static_cast<std::size_t>(count);
  }

 private:
  Eigen::Matrix2d normal_ = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs_ = Eigen::Vector2d::Zero();
  double yy_ = 0;
  std::size_t count_ = 0;
};

class EnskogShearViscosity final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "enskog_shear_viscosity";
  static constexpr const char* version = "1.4.2";
  static constexpr const char* summary =
      "Modified USF (002): kinetic + collisional P_ij, eta(t) = -P_xy/a, Kn(t), c(t)/c0, first-Sonine eta and the NS plateau";
  static constexpr const char* documentation =
      "The measurements of paper 002 (Enskog gas in the modified simple shear flow). Needs the\n"
      "published 'shear_rate' a (uniform_shear); 'packing_fraction' phi and 'contact_value' chi come\n"
      "from enskog_hard_spheres (without them: phi = (pi/6) n sigma^3 and chi = 1, the Boltzmann gas,\n"
      "e.g. inelastic_hard_spheres). Per record (every record_every steps):\n"
      "  kinetic P^k_ij = n m <V_i V_j> (Eq. 5), the mean over the samples since the last record;\n"
      "  collisional P^c_ij = (increase of the rule's tally collisional_transfer_ij) / (volume x time\n"
      "    since the last record) (Eq. 5; 0 without the tally), divided by n T with T the mean of the\n"
      "    samples; both xy and yx are written (the tensor is symmetric);\n"
      "  eta^k = -P^k_xy / a, eta^c = -P^c_xy / a, eta = eta^k + eta^c, in units of\n"
      "    eta0(T) = (5 / 16 sigma^2) sqrt(m T / pi) (002, after Eq. 17), and relative to the elastic\n"
      "    first-Sonine values eta^k(1, phi), eta(1, phi) of Eqs. (16)-(17) at the same T (Figs. 2-4);\n"
      "  Kn = a sigma / (12 phi chi sqrt(T/m)) as 002 writes it (lambda / l with lambda =\n"
      "    1/(sqrt 2 pi n sigma^2 chi), l = sqrt(2T/m)/a), and Kn^2;\n"
      "  c = 2 a2, a2 = <V^4>/(15 (T/m)^2) - 1: the fourth cumulant in the convention of 002 and its\n"
      "    Ref. 2 (f = f_M [1 + (c/4)(V*^4 - 5 V*^2 + 15/4)], V* = V/sqrt(2T/m), i.e. c = 2 a2; Eq. 18\n"
      "    is van Noije and Ernst's a2 times 2), and c/c0 with c0(alpha) of Eq. (18);\n"
      "  zeta: the cooling rate of Eq. (6), (increase of the tally dissipated_energy) / ((3/2) N T dt)\n"
      "    (or minus the collisional energy change without the tally), in 1/tau0.\n"
      "Scalars: the first-Sonine eta^k/eta0 and eta/eta0 at (alpha, phi) and at (1, phi), their ratios\n"
      "(the theory lines of Figs. 3-4), c0 of Eq. (18). The Navier-Stokes plateau: over the records in\n"
      "the run's averaging window (run.average_after, chosen after the transient), each of\n"
      "eta_k_over_elastic_sonine and eta_over_elastic_sonine (and eta_k, eta in eta0 units) is fitted\n"
      "as y = y_NS + b Kn^2 (the hydrodynamic stage is linear in Kn^2, Burnett order; least squares\n"
      "with Eigen) and averaged: <name>_ns (the intercept), <name>_ns_error (from the residual\n"
      "scatter, treating records as independent: space them by more than the correlation time),\n"
      "<name>_slope, and <name>_mean / _standard_error (batch means) over the same records. With\n"
      "several realizations the host's realization scatter of these scalars is the honest error.\n"
      "Datasets (name [unit]): series temperature [T0], Kn, Kn_squared, Pk_xx_over_nT, Pk_yy_over_nT,\n"
      "Pk_zz_over_nT, Pk_xy_over_nT, Pc_xx_over_nT, Pc_yy_over_nT, Pc_zz_over_nT, Pc_xy_over_nT,\n"
      "Pc_yx_over_nT, P_xy_over_nT [1], eta_k, eta_c, eta [eta0(T)], eta_k_over_elastic_sonine,\n"
      "eta_over_elastic_sonine, c, c_over_c0 [1], zeta [1/tau0]; scalars packing_fraction,\n"
      "contact_value, c0, eta_k_sonine, eta_sonine, eta_k_sonine_elastic, eta_sonine_elastic,\n"
      "eta_k_sonine_ratio, eta_sonine_ratio, eta_k_sonine_crossing_phi, eta_sonine_crossing_phi (phi0^k and\n"
      "phi0 of Sec. 3 at this alpha), eta_chapman_enskog_over_sonine (1.016034) [1] and the arrays\n"
      "sonine_phi_grid (300 phi in [1e-4, 0.52]) with eta_k_sonine_ratio_vs_phi, eta_sonine_ratio_vs_phi\n"
      "(at this alpha, Carnahan-Starling chi), sonine_alpha_grid (200 alpha in [0.58, 1]) with\n"
      "eta_k_sonine_ratio_vs_alpha, eta_sonine_ratio_vs_alpha (at this phi and chi): the curves of Figs. 3-4\n"
      "(written as the run begins; every theory dataset tagged role = theory with its equation), and for <name> = eta_k,\n"
      "eta [eta0(T)], eta_k_over_elastic_sonine, eta_over_elastic_sonine [1]: <name>_ns,\n"
      "<name>_ns_error, <name>_slope, <name>_slope_error, <name>_mean, <name>_standard_error.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit EnskogShearViscosity(const gdsmc::Params&) {}

  enum Column {
    kTemperature, kKn, kKn2, kPkXX, kPkYY, kPkZZ, kPkXY, kPcXX, kPcYY, kPcZZ, kPcXY, kPcYX, kPXY,
    kEtaK, kEtaC, kEta, kEtaKRatio, kEtaRatio, kC, kCRatio, kZeta, kColumns
  };

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    // No series is steady: in the modified shear flow T grows, so Kn = a sigma / (12 phi chi sqrt(T))
    // falls and the reduced stresses follow it towards their Navier-Stokes values (002 Sec. 3), which
    // finish() takes by the fit against Kn^2. `gdsmc plot` draws no steady-mean line.
    out.attribute("stationary", "");
    const double* a = board.find("shear_rate");
    if (!a || *a == 0)
      throw gdsmc::ParameterError("plugin", "enskog_shear_viscosity needs a non-zero 'shear_rate' (the uniform_shear forcing)");
    a_ = *a;
    const double* alpha = board.find("restitution");
    alpha_ = alpha ? *alpha : 1.0;
    const double* phi = board.find("packing_fraction");
    const double* chi = board.find("contact_value");
    phi_ = phi ? *phi : M_PI / 6.0 * sys.number_density * sys.sigma * sys.sigma * sys.sigma;
    chi_ = chi ? *chi : 1.0;
    sigma_ = sys.sigma;
    n_ = sys.number_density;
    volume_ = sys.volume;
    particles_ = static_cast<double>(sys.particles);
    t0_ = sys.initial_temperature;
    tau0_ = sys.time_unit0;
    c0_ = enskog_hcs_cumulant(alpha_);
    elastic_k_ = enskog_kinetic_viscosity(1.0, phi_, chi_);
    elastic_ = enskog_viscosity(1.0, phi_, chi_);
    const std::vector<std::array<const char*, 3>> cols = {
        {"temperature", "T0", "T/T0"},
        {"Kn", "1", "Kn = a sigma / (12 phi chi sqrt(T/m)) (002, Sec. 3)"},
        {"Kn_squared", "1", "Kn^2"},
        {"Pk_xx_over_nT", "1", "kinetic P^k_xx / nT (Eq. 5)"},
        {"Pk_yy_over_nT", "1", "kinetic P^k_yy / nT"},
        {"Pk_zz_over_nT", "1", "kinetic P^k_zz / nT"},
        {"Pk_xy_over_nT", "1", "kinetic P^k_xy / nT"},
        {"Pc_xx_over_nT", "1", "collisional transfer P^c_xx / nT (Eq. 5)"},
        {"Pc_yy_over_nT", "1", "collisional transfer P^c_yy / nT"},
        {"Pc_zz_over_nT", "1", "collisional transfer P^c_zz / nT"},
        {"Pc_xy_over_nT", "1", "collisional transfer P^c_xy / nT"},
        {"Pc_yx_over_nT", "1", "collisional transfer P^c_yx / nT (= P^c_xy: symmetric)"},
        {"P_xy_over_nT", "1", "total shear stress (P^k_xy + P^c_xy) / nT"},
        {"eta_k", "eta0(T)", "kinetic shear viscosity -P^k_xy / a over eta0(T) = (5/16 sigma^2) sqrt(mT/pi)"},
        {"eta_c", "eta0(T)", "collisional shear viscosity -P^c_xy / a over eta0(T)"},
        {"eta", "eta0(T)", "shear viscosity eta^k + eta^c over eta0(T)"},
        {"eta_k_over_elastic_sonine", "1", "eta^k / eta^k(1, phi) of Eq. 16 (Fig. 2)"},
        {"eta_over_elastic_sonine", "1", "eta / eta(1, phi) of Eq. 17"},
        {"c", "1", "fourth cumulant c = 2 a2 (002 / Garzo-Dufty convention)"},
        {"c_over_c0", "1", "c / c0(alpha), c0 of Eq. 18 (NaN where c0 = 0)"},
        {"zeta", "1/tau0", "cooling rate zeta of Eq. 6, measured from the dissipated energy"}};
    for (const auto& c : cols) {
      names_.push_back(c[0]);
      ids_.push_back(out.series(c[0], c[1], c[2]));
    }
    auto put = [&](const char* n, double v, const char* doc) { out.scalar(n, v, "1", doc); };
    put("packing_fraction", phi_, "phi = (pi/6) n sigma^3");
    put("contact_value", chi_, "chi(phi)");
    put("c0", c0_, "HCS fourth cumulant c0(alpha), Eq. 18");
    put("eta_k_sonine", enskog_kinetic_viscosity(alpha_, phi_, chi_), "first-Sonine eta^k(alpha, phi)/eta0, Eq. 16");
    put("eta_sonine", enskog_viscosity(alpha_, phi_, chi_), "first-Sonine eta(alpha, phi)/eta0, Eq. 17");
    put("eta_k_sonine_elastic", elastic_k_, "first-Sonine eta^k(1, phi)/eta0");
    put("eta_sonine_elastic", elastic_, "first-Sonine eta(1, phi)/eta0");
    put("eta_k_sonine_ratio", enskog_kinetic_viscosity(alpha_, phi_, chi_) / elastic_k_,
        "first-Sonine eta^k(alpha, phi)/eta^k(1, phi): the theory line of Figs. 3-4 (left)");
    put("eta_sonine_ratio", enskog_viscosity(alpha_, phi_, chi_) / elastic_,
        "first-Sonine eta(alpha, phi)/eta(1, phi): the theory line of Figs. 3-4 (right)");
    put("eta_k_sonine_crossing_phi", gdsmc::enskog_viscosity_crossing(alpha_, true),
        "phi0^k: where the first-Sonine eta^k(alpha, phi)/eta^k(1, phi) crosses 1 at this alpha (Sec. 3; NaN if nowhere in (1e-4, 0.5))");
    put("eta_sonine_crossing_phi", gdsmc::enskog_viscosity_crossing(alpha_, false),
        "phi0: where the first-Sonine eta(alpha, phi)/eta(1, phi) crosses 1 at this alpha (Sec. 3; NaN if nowhere in (1e-4, 0.5))");
    put("eta_chapman_enskog_over_sonine", gdsmc::chapman_enskog_viscosity_factor,
        "converged Chapman-Enskog eta of elastic hard spheres over its first Sonine value (Chapman & Cowling Sec. 10.21)");
    write_sonine_curves(out);
  }

  // The first-Sonine ratios of Figs. 3-4 as curves: against phi at this alpha (Carnahan-Starling
  // chi at each phi), and against alpha at this phi and chi.
  void write_sonine_curves(gdsmc::OutputSink& out) const {
    const std::vector<double> phis = linspace(kPhiGridFirst, kPhiGridLast, kPhiGridPoints);
    const std::vector<double> alphas = linspace(kAlphaGridFirst, kAlphaGridLast, kAlphaGridPoints);
    std::vector<double> k_phi(phis.size()), t_phi(phis.size()), k_alpha(alphas.size()), t_alpha(alphas.size());
    for (std::size_t j = 0; j < phis.size(); ++j) {
      const double chi = gdsmc::carnahan_starling_contact_value(phis[j]);
      k_phi[j] = enskog_kinetic_viscosity(alpha_, phis[j], chi) / enskog_kinetic_viscosity(1.0, phis[j], chi);
      t_phi[j] = enskog_viscosity(alpha_, phis[j], chi) / enskog_viscosity(1.0, phis[j], chi);
    }
    for (std::size_t j = 0; j < alphas.size(); ++j) {
      k_alpha[j] = enskog_kinetic_viscosity(alphas[j], phi_, chi_) / elastic_k_;
      t_alpha[j] = enskog_viscosity(alphas[j], phi_, chi_) / elastic_;
    }
    out.array("sonine_phi_grid", phis, {phis.size()}, "1", "packing fractions phi of the curves *_vs_phi");
    out.array("eta_k_sonine_ratio_vs_phi", k_phi, {phis.size()}, "1",
              "first-Sonine eta^k(alpha, phi)/eta^k(1, phi) at this alpha on sonine_phi_grid, Carnahan-Starling chi (Fig. 3 left)");
    out.array("eta_sonine_ratio_vs_phi", t_phi, {phis.size()}, "1",
              "first-Sonine eta(alpha, phi)/eta(1, phi) at this alpha on sonine_phi_grid, Carnahan-Starling chi (Fig. 3 right)");
    out.array("sonine_alpha_grid", alphas, {alphas.size()}, "1", "restitution coefficients alpha of the curves *_vs_alpha");
    out.array("eta_k_sonine_ratio_vs_alpha", k_alpha, {alphas.size()}, "1",
              "first-Sonine eta^k(alpha, phi)/eta^k(1, phi) at this phi and chi on sonine_alpha_grid (Fig. 4 left)");
    out.array("eta_sonine_ratio_vs_alpha", t_alpha, {alphas.size()}, "1",
              "first-Sonine eta(alpha, phi)/eta(1, phi) at this phi and chi on sonine_alpha_grid (Fig. 4 right)");
    for (const char* curve : {"eta_k_sonine_ratio_vs_phi", "eta_sonine_ratio_vs_phi"}) out.axis(curve, "sonine_phi_grid");
    for (const char* curve : {"eta_k_sonine_ratio_vs_alpha", "eta_sonine_ratio_vs_alpha"}) out.axis(curve, "sonine_alpha_grid");
  }

  // The theory of begin() marked as theory (OutputSink::theory), once the measured values exist.
  static void tag_theory(gdsmc::OutputSink& out) {
    out.theory("contact_value", "", "002, after Eq. 18 (Carnahan-Starling, unless the rule was given chi)");
    out.theory("c0", "c", "002 Eq. 18");
    out.theory("eta_k_sonine", "eta_k, eta_k_ns, eta_k_mean", "002 Eqs. 16, 18");
    out.theory("eta_sonine", "eta, eta_ns, eta_mean", "002 Eqs. 16-18");
    out.theory("eta_k_sonine_elastic", "", "002 Eq. 16 at alpha = 1");
    out.theory("eta_sonine_elastic", "", "002 Eqs. 16-17 at alpha = 1");
    out.theory("eta_k_sonine_ratio", "eta_k_over_elastic_sonine, eta_k_over_elastic_sonine_ns, eta_k_over_elastic_sonine_mean",
               "002 Eqs. 16, 18");
    out.theory("eta_sonine_ratio", "eta_over_elastic_sonine, eta_over_elastic_sonine_ns, eta_over_elastic_sonine_mean",
               "002 Eqs. 16-18");
    out.theory("eta_k_sonine_crossing_phi", "", "002 Sec. 3, Eqs. 16, 18");
    out.theory("eta_sonine_crossing_phi", "", "002 Sec. 3, Eqs. 16-18");
    out.theory("eta_chapman_enskog_over_sonine", "", "Chapman & Cowling Sec. 10.21");
    for (const char* curve : {"eta_k_sonine_ratio_vs_phi", "eta_k_sonine_ratio_vs_alpha"}) out.theory(curve, "", "002 Eqs. 16, 18");
    for (const char* curve : {"eta_sonine_ratio_vs_phi", "eta_sonine_ratio_vs_alpha"}) out.theory(curve, "", "002 Eqs. 16-18");
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const double T = m.temperature;
    sums_[kTemperature] += T;
    for (int a = 0; a < 3; ++a) sums_[kPkXX + a] += m.second[a][a] / T;
    sums_[kPkXY] += m.second[0][1] / T;
    sums_[kEtaK] += -n_ * m.second[0][1] / (a_ * eta0(T));
    sums_[kKn] += kn(T);
    sums_[kKn2] += kn(T) * kn(T);
    sums_[kC] += 2.0 * m.a2();  // c = 2 a2 (002's convention, see the documentation)
    ++samples_;
  }

  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    double v[kColumns];
    const double ns = samples_ ? static_cast<double>(samples_) : std::nan("");
    for (int k = 0; k < kColumns; ++k) v[k] = sums_[k] / ns;
    const double T = v[kTemperature];
    // Collisional transfer and dissipation over the interval since the last record.
    const double dt = ctx.time - last_time_;
    double transfer[9];
    for (int k = 0; k < 9; ++k) {
      static const char* const tally_names[9] = {"collisional_transfer_xx", "collisional_transfer_xy", "collisional_transfer_xz",
                                                 "collisional_transfer_yx", "collisional_transfer_yy", "collisional_transfer_yz",
                                                 "collisional_transfer_zx", "collisional_transfer_zy", "collisional_transfer_zz"};
      const double* t = ctx.collision_tally(tally_names[k]);
      const double now = t ? *t : 0.0;
      transfer[k] = dt > 0 ? (now - last_transfer_[k]) / (volume_ * dt) : std::nan("");  // P^c_ij
      last_transfer_[k] = now;
    }
    const double* d = ctx.collision_tally("dissipated_energy");
    const double dissipated = d ? *d : -ctx.collision_energy_change;
    const double zeta = dt > 0 ? (dissipated - last_dissipated_) / (1.5 * particles_ * T * dt) : std::nan("");
    last_dissipated_ = dissipated;
    last_time_ = ctx.time;
    const double nT = n_ * T;
    v[kTemperature] = T / t0_;
    v[kPcXX] = transfer[0] / nT;
    v[kPcYY] = transfer[4] / nT;
    v[kPcZZ] = transfer[8] / nT;
    v[kPcXY] = transfer[1] / nT;
    v[kPcYX] = transfer[3] / nT;
    v[kPXY] = v[kPkXY] + v[kPcXY];
    v[kEtaC] = -transfer[1] / (a_ * eta0(T));
    v[kEta] = v[kEtaK] + v[kEtaC];
    v[kEtaKRatio] = v[kEtaK] / elastic_k_;
    v[kEtaRatio] = v[kEta] / elastic_;
    v[kCRatio] = c0_ != 0 ? v[kC] / c0_ : std::nan("");
    v[kZeta] = zeta * tau0_;
    for (int k = 0; k < kColumns; ++k) out.append(ids_[k], v[k]);
    if (ctx.in_average_window && std::isfinite(v[kEta]))
      for (int k = 0; k < kFitted; ++k) {
        fits_[k].add(v[kKn2], v[kFittedColumns[k]]);
        means_[k].add(v[kFittedColumns[k]]);
      }
    for (double& s : sums_) s = 0;
    samples_ = 0;
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    std::string line = "enskog_shear_viscosity: phi = " + number(phi_) + ", chi = " + number(chi_) + ", alpha = " + number(alpha_);
    for (int k = 0; k < kFitted; ++k) {
      const std::string n = names_[kFittedColumns[k]];
      const Eigen::Vector4d r = fits_[k].result();
      const char* unit = k < 2 ? "1" : "eta0(T)";
      out.scalar(n + "_ns", r(0), unit, "Navier-Stokes value: intercept at Kn^2 = 0 of the fit over the averaging window");
      out.scalar(n + "_ns_error", r(1), unit, "standard error of the intercept (residual scatter)");
      out.scalar(n + "_slope", r(2), unit, "slope d/d(Kn^2) of the fit");
      out.scalar(n + "_slope_error", r(3), unit, "standard error of the slope");
      out.scalar(n + "_mean", means_[k].mean(), unit, "mean over the records in the averaging window");
      out.scalar(n + "_standard_error", means_[k].standard_error(), unit, "batch-means standard error of the mean");
      if (k < 2) line += ", " + n + "(Kn->0) = " + number(r(0)) + " +- " + number(r(1));
    }
    tag_theory(out);
    line += " (first Sonine: " + number(enskog_kinetic_viscosity(alpha_, phi_, chi_) / elastic_k_) + ", " +
            number(enskog_viscosity(alpha_, phi_, chi_) / elastic_) + "; " + std::to_string(fits_[0].count()) + " records)";
    out.summary(line);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("sums", sums_, kColumns);
    out.write("samples", static_cast<std::uint64_t>(samples_));
    out.write("last_time", last_time_);
    out.write("last_dissipated", last_dissipated_);
    out.write("last_transfer", last_transfer_, 9);
    for (int k = 0; k < kFitted; ++k) {
      fits_[k].save(out, "fit" + std::to_string(k));
      means_[k].save(out, "mean" + std::to_string(k));
    }
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("sums", sums_, kColumns);
    std::uint64_t samples = 0;
    in.read("samples", samples);
    samples_ = static_cast<std::size_t>(samples);
    in.read("last_time", last_time_);
    in.read("last_dissipated", last_dissipated_);
    in.read("last_transfer", last_transfer_, 9);
    for (int k = 0; k < kFitted; ++k) {
      fits_[k].load(in, "fit" + std::to_string(k));
      means_[k].load(in, "mean" + std::to_string(k));
    }
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the host's moments and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);
  }
 private:
  static constexpr int kFitted = 4;
  static constexpr int kFittedColumns[kFitted] = {kEtaKRatio, kEtaRatio, kEtaK, kEta};
  static std::string number(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", x);
    return b;
  }
  double eta0(double T) const { return 5.0 / (16.0 * sigma_ * sigma_) * std::sqrt(T / M_PI); }  // m = 1
  double kn(double T) const { return a_ * sigma_ / (12.0 * phi_ * chi_ * std::sqrt(T)); }

  double a_ = 0, alpha_ = 1, phi_ = 0, chi_ = 1, sigma_ = 1, n_ = 0, volume_ = 1, particles_ = 1, t0_ = 1, tau0_ = 1;
  double c0_ = 0, elastic_k_ = 1, elastic_ = 1;
  std::vector<std::string> names_;
  std::vector<std::size_t> ids_;
  double sums_[kColumns] = {};
  std::size_t samples_ = 0;
  double last_time_ = 0, last_dissipated_ = 0;
  double last_transfer_[9] = {};
  PlateauFit fits_[kFitted];
  gdsmc::BatchMeans means_[kFitted];
};

}  // namespace

GDSMC_PLUGIN(EnskogShearViscosity)

// What `gdsmc conformance` runs it in when no --context is given.
// A dense, uniformly sheared Enskog gas (the forcing publishes the shear rate).
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 0.4, sigma: 1, temperature: 1.0, domain: homogeneous}\n"
    "collision: {plugin: enskog_hard_spheres, alpha: 0.8}\n"
    "forcings: [{plugin: uniform_shear, shear_rate: 0.2}]")
