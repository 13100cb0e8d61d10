// Hydrodynamic profiles of a slab along y: density, flow, temperature, pressure tensor, heat flux,
// normal stress differences and local Knudsen number per sampling bin, window-averaged; optionally
// Fourier's law fitted to the steady profiles, beside the Chapman-Enskog conductivity (001 Eq. 2.47).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/bins.hpp>
#include <gdsmc/physics/kinetic_theory.hpp>
#include <gdsmc/physics/line_fit.hpp>

namespace {

// The profiles written at each record, in this order.
enum Prof : std::size_t { n_, ux, uy, uz, T_, Pxx, Pyy, Pzz, Pxy, Pxz, Pyz, qx, qy, N1, N2, Kn, kProf };

struct ProfileColumn {
  const char* name;
  const char* unit;
  const char* doc;
};

constexpr ProfileColumn kColumns[kProf] = {
    {"n", "n0", "number density n(y) = <1>_y (004 Eqs. 13-14); n0 = N / volume, the mean density"},
    {"u_x", "sqrt(2T0/m)", "flow velocity u_x(y) = <v_x>_y / n (004 Eq. 15)"},
    {"u_y", "sqrt(2T0/m)", "flow velocity u_y(y) (004 Eq. 15)"},
    {"u_z", "sqrt(2T0/m)", "flow velocity u_z(y) (004 Eq. 15)"},
    {"T", "T0", "granular temperature T(y) = m <|v - u|^2>_y / (3 n) (004 Eq. 16, 000 Eq. 4.6)"},
    {"P_xx", "n0 T0", "pressure tensor P_xx(y) = <m V_x V_x>_y, V = v - u (004 Eq. 31, 000 Eq. 4.7)"},
    {"P_yy", "n0 T0", "pressure tensor P_yy(y) (004 Eq. 31)"},
    {"P_zz", "n0 T0", "pressure tensor P_zz(y) (004 Eq. 31)"},
    {"P_xy", "n0 T0", "pressure tensor P_xy(y), the shear stress (004 Eq. 31)"},
    {"P_xz", "n0 T0", "pressure tensor P_xz(y) (004 Eq. 31)"},
    {"P_yz", "n0 T0", "pressure tensor P_yz(y) (004 Eq. 31)"},
    {"q_x", "n0 T0 sqrt(2T0/m)", "heat flux q_x(y) = <(m/2) |V|^2 V_x>_y"},
    {"q_y", "n0 T0 sqrt(2T0/m)", "heat flux q_y(y) = <(m/2) |V|^2 V_y>_y"},
    {"N1", "1", "first normal stress difference (P_xx - P_yy) / p, p = tr P / 3 (004 Eq. 34)"},
    {"N2", "1", "second normal stress difference (P_yy - P_zz) / p (004 Eq. 35)"},
    {"Kn", "1", "local Knudsen number lambda(y) / Ly, lambda(y) = 1 / (sqrt(2) pi n(y) sigma^2) (004 Eq. 21)"},
};

class Profiles final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "profiles";
  static constexpr const char* version = "1.5.0";
  static constexpr const char* summary =
      "Profiles along y per sampling bin: n, u, T, P_ij, q_x, q_y, N1, N2, Kn (window averages)";
  static constexpr const char* documentation =
      "Slab systems only. The sampling bins are system.bins layers of equal width dy along y, of\n"
      "volume V_bin = dy Lx Lz. Each record is the window average since the previous record in the\n"
      "sense of paper 004 Eq. (13): over the N_t samples of the window,\n"
      "  <psi>_y = (1 / (N_t V_bin)) sum_t sum_{i in bin} psi(v_i(t)),\n"
      "accumulated as the sums of 1, v_a, v_a v_b and |v|^2 v_a per bin (the host's sums of each\n"
      "sample, SampledMoments::bin_sums, added into the toolkit's gdsmc::BinSums, gdsmc/physics/bins.hpp;\n"
      "no particle is read, so a decomposed run gathers none for it). At the record, with N_b the count summed over the window and u taken from the same window:\n"
      "  n(y) = N_b / (N_t V_bin)                                   (004 Eq. 14, per unit mass)\n"
      "  u(y) = sum v / N_b                                          (004 Eq. 15)\n"
      "  P_ab(y) = (m / (N_t V_bin)) sum (v_a - u_a)(v_b - u_b)      (004 Eq. 31, 000 Eq. 4.7)\n"
      "  T(y) = tr P / (3 n)                                         (004 Eq. 16, 000 Eq. 4.6)\n"
      "  q_a(y) = (m / (2 N_t V_bin)) sum |v - u|^2 (v_a - u_a)      (a = x, y)\n"
      "  N1 = (P_xx - P_yy) / p,  N2 = (P_yy - P_zz) / p,  p = tr P / 3   (004 Eqs. 34-35)\n"
      "  Kn(y) = lambda(y) / Ly,  lambda(y) = 1 / (sqrt(2) pi n(y) sigma^2)   (004 Eq. 21, W = Ly)\n"
      "The peculiar sums are expanded around the window mean, e.g. sum V_a V_b = sum v_a v_b -\n"
      "N_b u_a u_b. Profiles (record x bin): n [n0 = N / volume], u_x, u_y, u_z [sqrt(2T0/m)],\n"
      "T [T0], P_xx, P_yy, P_zz, P_xy, P_xz, P_yz [n0 T0], q_x, q_y [n0 T0 sqrt(2T0/m)], N1, N2, Kn [1].\n"
      "A bin that no particle visited in the window has n = 0 and NaN for every other profile; a\n"
      "window without samples gives NaN everywhere. The host writes the bin centres beside the profiles (bin_centre [lambda0]).\n"
      "fourier_law: true (plane Fourier flow of dilute elastic hard spheres between walls at different\n"
      "temperatures; refused unless the collision rule publishes 'restitution' = 1 and no packing fraction)\n"
      "also accumulates the sums of every sample with ctx.in_average_window and, after the run, fits\n"
      "Fourier's law q_y = -kappa dT/dy in the central windows of the slab: for each window of the n\n"
      "central bins (n = 3 or 4, 5 or 6, ... up to all, as the bin count is odd or even), from T and q_y\n"
      "of those pooled sums (in T0 and n0 T0 sqrt(2T0/m), y in lambda0),\n"
      "  kappa = -<q_y> / b,  T_c = a,   T = a + b y the least-squares line (gdsmc/physics/line_fit.hpp),\n"
      "<q_y> the mean of the window's bins. Its error, treating the bins as independent (a lower bound:\n"
      "neighbouring bins are correlated), is kappa sqrt((e_q/<q_y>)^2 + var b / b^2), e_q = sd(q_y)/sqrt(n)\n"
      "and var b from the scatter of T about the line. The theory beside it is the converged\n"
      "Chapman-Enskog conductivity at the centre temperature, kappa_CE = 1.025218 kappa0(T_c) with\n"
      "kappa0(T) = (75/64) sqrt(T/(pi m))/sigma^2 (001 Eq. 2.47; 1.025218 the converged Sonine factor of\n"
      "001 Ref. 37). Arrays over the windows: fourier_window [lambda0] (n dy), fourier_centre_temperature\n"
      "[T0] (T_c), fourier_conductivity and fourier_conductivity_error [kappa0(T0)], theory_fourier_conductivity\n"
      "[kappa0(T0)] (kappa_CE, role theory), fourier_conductivity_over_chapman_enskog and its _error [1]\n"
      "(kappa/kappa_CE, the error of kappa over kappa_CE), each declaring fourier_window its axis; NaN\n"
      "where a bin of the window is empty.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::boolean("fourier_law",
                                      "fit Fourier's law to the steady T and q_y profiles of central windows and write "
                                      "kappa beside the elastic Chapman-Enskog conductivity (001 Eq. 2.47)")
                .default_value(false)};
  }
  explicit Profiles(const gdsmc::Params& p) : fourier_law_(p.boolean("fourier_law")) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("profiles: needs a slab system (system.domain: slab)");
    if (fourier_law_) check_fourier_flow(sys, board);
    bins_ = sys.bins;
    mass_ = sys.mass;
    bin_volume_ = sys.bin_width() * sys.cross_section();
    n0_ = sys.number_density;
    t0_ = sys.initial_temperature;
    v0_ = std::sqrt(2.0 * sys.initial_temperature / sys.mass);
    sigma_ = sys.sigma;
    width_ = sys.box[1];
    centres_.resize(bins_);
    for (std::size_t b = 0; b < bins_; ++b) centres_[b] = sys.bin_centre(b) / sys.mean_free_path0;
    acc_.begin(bins_, true);  // third moments: the heat flux
    if (fourier_law_) steady_.begin(bins_, true), straddle_.begin(bins_, true);
    values_.assign(bins_ * kProf, 0.0);
    for (std::size_t k = 0; k < kProf; ++k) ids_[k] = out.profile(kColumns[k].name, kColumns[k].unit, kColumns[k].doc);
  }

  // With fourier_law the steady sums take every record window wholly in ctx.in_average_window at its
  // record (appended), and the samples of the one window that straddles its start from a second sum.
  // The host's sums of the state in every bin (SampledMoments::bin_sums) are one sample.
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    if (fourier_law_ && ctx.in_average_window && !window_in_average_) {
      if (acc_.samples() == 0) window_in_average_ = true;
      else straddle_.append_sample(*ctx.moments);
    }
    acc_.append_sample(*ctx.moments);
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    for (std::size_t b = 0; b < bins_; ++b) compute_bin(acc_.moments(b, bin_volume_, mass_), b);
    for (std::size_t k = 0; k < kProf; ++k) out.append_profile(ids_[k], &values_[k * bins_]);
    if (fourier_law_) {
      steady_.append(window_in_average_ ? acc_ : straddle_);
      straddle_.clear();
      window_in_average_ = false;
    }
    acc_.clear();
  }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    if (fourier_law_) write_fourier_law(out);
  }

  void save_state(gdsmc::StateWriter& out) const override {
    acc_.save(out, "acc");
    if (!fourier_law_) return;
    steady_.save(out, "steady");
    straddle_.save(out, "straddle");
    out.write("window_in_average", static_cast<std::uint64_t>(window_in_average_));
  }
  void load_state(gdsmc::StateReader& in) override {
    acc_.load(in, "acc");
    if (!fourier_law_) return;
    steady_.load(in, "steady");
    straddle_.load(in, "straddle");
    std::uint64_t flag = 0;
    in.read("window_in_average", flag);
    window_in_average_ = flag != 0;
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the host's bin sums with their third moments, and no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_bin_heat, gdsmc::reads_no_particles>(id);
  }
 private:
  // The record-time formulas of the documentation, from one bin's moments over the window.
  void compute_bin(const gdsmc::BinMoments& m, std::size_t b) {
    double v[kProf];
    const double nan = std::nan("");
    if (!(m.count > 0)) {
      for (double& x : v) x = nan;
      v[n_] = m.density;  // 0 for a bin no particle visited, NaN for a window without samples
    } else {
      const double n = m.density;
      const double* P = m.pressure;  // xx, yy, zz, xy, xz, yz
      const double p = m.pressure_scalar;
      const double lambda = 1.0 / (std::sqrt(2.0) * M_PI * n * sigma_ * sigma_);
      const double nT0 = n0_ * t0_;
      v[n_] = n / n0_;
      v[ux] = m.mean[0] / v0_;
      v[uy] = m.mean[1] / v0_;
      v[uz] = m.mean[2] / v0_;
      v[T_] = m.temperature / t0_;
      for (std::size_t k = 0; k < 6; ++k) v[Pxx + k] = P[k] / nT0;
      v[qx] = m.heat_flux[0] / (nT0 * v0_);
      v[qy] = m.heat_flux[1] / (nT0 * v0_);
      v[N1] = (P[0] - P[1]) / p;
      v[N2] = (P[1] - P[2]) / p;
      v[Kn] = lambda / width_;
    }
    for (std::size_t k = 0; k < kProf; ++k) values_[k * bins_ + b] = v[k];
  }

  static void check_fourier_flow(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board) {
    if (sys.bins < 3)
      throw gdsmc::ParameterError("fourier_law", "profiles: fourier_law fits lines through at least 3 bins; system.bins is " +
                                                     std::to_string(sys.bins));
    const double* alpha = board.find("restitution");
    const double* phi = board.find("packing_fraction");
    if (!alpha || *alpha != 1.0 || (phi && *phi > 0))
      throw gdsmc::ParameterError("fourier_law", "profiles: fourier_law compares with the Chapman-Enskog conductivity of "
                                                 "dilute elastic hard spheres: it needs a collision rule that publishes "
                                                 "'restitution' = 1 and no packing fraction");
  }

  // Fourier's law in every central window of the steady sums (the documentation's formulas).
  void write_fourier_law(gdsmc::OutputSink& out) const {
    std::vector<double> T(bins_), q(bins_), window, centre, kappa, error, theory, ratio, ratio_error;
    for (std::size_t b = 0; b < bins_; ++b) {
      const gdsmc::BinMoments m = steady_.moments(b, bin_volume_, mass_);
      const bool empty = !(m.count > 0);
      T[b] = empty ? std::nan("") : m.temperature / t0_;
      q[b] = empty ? std::nan("") : m.heat_flux[1] / (n0_ * t0_ * v0_);
    }
    // kappa in sqrt(T0/m)/(pi sigma^2) (q in n0 T0 sqrt(2T0/m), y in lambda0); kappa0(T0) in the same unit.
    const double kappa0 = gdsmc::elastic_conductivity0(1.0) * M_PI;
    for (std::size_t n = bins_ % 2 ? 3 : 4; n <= bins_; n += 2) {
      const std::size_t first = (bins_ - n) / 2;
      const gdsmc::LineFit line = gdsmc::fit_line(&centres_[first], &T[first], n);
      double qm = 0, qv = 0;
      for (std::size_t b = first; b < first + n; ++b) qm += q[b] / static_cast<double>(n);
      for (std::size_t b = first; b < first + n; ++b) qv += (q[b] - qm) * (q[b] - qm) / static_cast<double>(n - 1);
      const double k = -qm / line.slope;
      const double e = std::fabs(k) * std::sqrt(qv / static_cast<double>(n) / (qm * qm) + line.slope_variance / (line.slope * line.slope));
      const double ce = gdsmc::chapman_enskog_conductivity_factor * std::sqrt(line.intercept);  // kappa_CE / kappa0(T0)
      window.push_back(static_cast<double>(n) * (centres_[1] - centres_[0]));
      centre.push_back(line.intercept);
      kappa.push_back(k / kappa0);
      error.push_back(e / kappa0);
      theory.push_back(ce);
      ratio.push_back(k / kappa0 / ce);
      ratio_error.push_back(e / kappa0 / ce);
    }
    const std::vector<std::size_t> shape{window.size()};
    const char* k0 = "(75/64) sqrt(T0/(pi m))/sigma^2";
    out.array("fourier_window", window, shape, "lambda0", "width of the central window of each fit (n bins)");
    out.array("fourier_centre_temperature", centre, shape, "T0", "T_c: the fitted line's T at the centre y = 0");
    out.array("fourier_conductivity", kappa, shape, k0, "kappa = -<q_y>/(dT/dy) in the window (Fourier's law)");
    out.array("fourier_conductivity_error", error, shape, k0,
              "error of fourier_conductivity, the window's bins taken as independent (a lower bound)");
    out.array("theory_fourier_conductivity", theory, shape, k0,
              "kappa_CE = 1.025218 kappa0(T_c), kappa0(T) = (75/64) sqrt(T/(pi m))/sigma^2 (001 Eq. 2.47, Ref. 37)");
    out.array("fourier_conductivity_over_chapman_enskog", ratio, shape, "1", "kappa / kappa_CE");
    out.array("fourier_conductivity_over_chapman_enskog_error", ratio_error, shape, "1",
              "fourier_conductivity_error / kappa_CE");
    out.theory("theory_fourier_conductivity", "fourier_conductivity", "001 Eq. 2.47, Ref. 37");
    for (const char* a : {"fourier_centre_temperature", "fourier_conductivity", "fourier_conductivity_error",
                          "theory_fourier_conductivity", "fourier_conductivity_over_chapman_enskog",
                          "fourier_conductivity_over_chapman_enskog_error"})
      out.axis(a, "fourier_window");
  }

  std::size_t bins_ = 1;
  double mass_ = 1, bin_volume_ = 1, n0_ = 1, t0_ = 1, v0_ = 1, sigma_ = 1, width_ = 1;
  bool fourier_law_ = false;
  std::vector<double> centres_;  // bin centres [lambda0]
  gdsmc::BinSums acc_;         // the window's per-bin sums
  // fourier_law: the sums of the steady window, and those of the record window that straddles its start.
  gdsmc::BinSums steady_, straddle_;
  bool window_in_average_ = false;  // every sample since the last record lies in the steady window
  std::vector<double> values_;  // kProf x bins: the record being written
  std::size_t ids_[kProf] = {};
};

}  // namespace

GDSMC_PLUGIN(Profiles)

// What `gdsmc conformance` runs it in when no --context is given.
// A slab between diffuse walls.
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
    "boundaries: {y: diffuse_wall}")
