// Steady marginal distributions g_x^(+-)(C_x), g_y^(+-)(C_y) and F(C) (000 Eqs. 3.16-3.20, 5.3).
#include <cmath>
#include <cstdio>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {


class VelocityMarginals final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "velocity_marginals";
  static constexpr const char* version = "1.3.1";
  static constexpr const char* summary = "Steady marginals g_x^(+-)(C_x), g_y^(+-)(C_y), F(C) as histograms (Eqs. 3.18-3.20)";
  static constexpr const char* documentation =
      "Reduced velocities C = V / sqrt(2T/m) at the current T (paper 000, Eqs. 3.16, 5.2), with f* normalized\n"
      "to 1; V relative to the local flow (the mean of all particles in a homogeneous system, of the\n"
      "particle's layer in a slab, u_I as of the host's last moment update, where T is T-bar of\n"
      "Eq. 4.8). Histograms accumulated over every sample\n"
      "in the run's steady averaging window (run.average_after; ctx.in_average_window, no parameter of\n"
      "its own) and written at the end:\n"
      "  g_x_plus / g_x_minus (C_x)  = int dC_z int dC_y Theta(+-C_y) f*(C)     (Eq. 3.18)\n"
      "  g_y_plus / g_y_minus (C_y)  = int dC_z int dC_x Theta(+-C_x) f*(C)     (Eq. 3.19)\n"
      "  F (C)                      = C^2 int dC_hat f*(C)                      (Eq. 3.20)\n"
      "estimated as counts / (samples N bin width), so g_x_plus + g_x_minus and F integrate to 1 over\n"
      "the whole line (particles beyond c_max are counted in the scalar fraction_outside). The edges\n"
      "are symmetric about 0, so the symmetrized forms of Eq. (5.3),\n"
      "  g_x_plus_symmetrized(C_x) = [g_x^(+)(C_x) + g_x^(-)(-C_x)] / 2, likewise g_y_plus_symmetrized,\n"
      "use mirrored bins exactly. The local-equilibrium references (bin averages of\n"
      "g^(+-) = exp(-C^2)/(2 sqrt(pi)) and F0 = 4 C^2 exp(-C^2)/sqrt(pi)) are written beside them as\n"
      "g_local_equilibrium and F_local_equilibrium. The symmetry (3.21) g_x^(+)(C_x) = g_x^(-)(-C_x) is\n"
      "a check of the run: the scalar symmetry_defect is max |g_x^(+)(C_x) - g_x^(-)(-C_x)| over bins.\n"
      "No time series.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("c_max", "histogram range: |C_x|, |C_y| < c_max and C < c_max").above(0.0).default_value(5.0),
            gdsmc::ParamSpec::integer("bins", "bins of each histogram (even, so that C = 0 is an edge)").range(2.0, 1e6).default_value(100)};
  }
  explicit VelocityMarginals(const gdsmc::Params& p)
      : c_max_(p.real("c_max")), bins_(static_cast<std::size_t>(p.integer("bins"))) {
    if (bins_ % 2 != 0) throw gdsmc::ParameterError("bins", "bins must be even so that C = 0 is a bin edge (Eq. 5.3 mirrors bins)");
    gxp_.assign(bins_, 0);
    gxm_.assign(bins_, 0);
    gyp_.assign(bins_, 0);
    gym_.assign(bins_, 0);
    F_.assign(bins_, 0);
  }

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink&) override {}
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (!ctx.in_average_window || p.count == 0) return;
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const bool slab = ctx.system->geometry == gdsmc::Geometry::slab;
    if (!(m.temperature > 0)) return;
    const double scale = 1.0 / std::sqrt(2.0 * m.temperature);
    const double w = gdsmc::bracket_weight(ctx);  // 1/2 for each side of a bracketed step: the counts stay one per particle a step
    const double nb = static_cast<double>(bins_);
    const double sym_width = 2.0 * c_max_ / nb, width = c_max_ / nb;
    auto sym_bin = [&](double c) -> long {
      const double b = std::floor((c + c_max_) / sym_width);
      return (b >= 0 && b < nb) ? static_cast<long>(b) : -1;
    };
    for (std::size_t i = 0; i < p.count; ++i) {
      const double* u = slab ? ctx.cells[p.cell[i]].mean_velocity : m.mean;  // the local flow
      const double cx = (p.vx[i] - u[0]) * scale, cy = (p.vy[i] - u[1]) * scale, cz = (p.vz[i] - u[2]) * scale;
      const long bx = sym_bin(cx), by = sym_bin(cy);
      if (bx >= 0) (cy > 0 ? gxp_ : gxm_)[bx] += w;  // C_y = 0 exactly has measure zero
      else outside_x_ += w;
      if (by >= 0) (cx > 0 ? gyp_ : gym_)[by] += w;
      else outside_y_ += w;
      const double c = std::sqrt(cx * cx + cy * cy + cz * cz);
      const double bc = std::floor(c / width);
      if (bc < nb) F_[static_cast<std::size_t>(bc)] += w;
      else outside_c_ += w;
    }
    total_ += w * static_cast<double>(p.count);
    ++samples_;
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink&) override {}
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double nb = static_cast<double>(bins_);
    const double sym_width = 2.0 * c_max_ / nb, width = c_max_ / nb;
    std::vector<double> sym_edges(bins_ + 1), edges(bins_ + 1);
    for (std::size_t b = 0; b <= bins_; ++b) {
      sym_edges[b] = -c_max_ + sym_width * static_cast<double>(b);
      edges[b] = width * static_cast<double>(b);
    }
    sym_edges[bins_ / 2] = 0.0;
    const double norm_sym = total_ > 0 ? 1.0 / (total_ * sym_width) : 0.0, norm = total_ > 0 ? 1.0 / (total_ * width) : 0.0;
    auto scaled = [](std::vector<double> v, double s) {
      for (double& x : v) x *= s;
      return v;
    };
    const auto gxp = scaled(gxp_, norm_sym), gxm = scaled(gxm_, norm_sym), gyp = scaled(gyp_, norm_sym), gym = scaled(gym_, norm_sym);
    std::vector<double> gxs(bins_), gys(bins_), gle(bins_), Fle(bins_);
    double defect = 0;
    for (std::size_t b = 0; b < bins_; ++b) {
      const std::size_t mb = bins_ - 1 - b;  // the bin of -C
      gxs[b] = 0.5 * (gxp[b] + gxm[mb]);
      gys[b] = 0.5 * (gyp[b] + gym[mb]);
      defect = std::max(defect, std::fabs(gxp[b] - gxm[mb]));
      gle[b] = 0.25 * (std::erf(sym_edges[b + 1]) - std::erf(sym_edges[b])) / sym_width;
      Fle[b] = (gdsmc::maxwell_speed_fraction_below(edges[b + 1]) - gdsmc::maxwell_speed_fraction_below(edges[b])) / width;
    }
    const char* doc_c = "reduced velocity C = V/sqrt(2T/m)";
    out.histogram("g_x_plus", sym_edges, gxp, "1", "1", "g_x^(+)(C_x): particles with C_y > 0 (Eq. 3.18)");
    out.histogram("g_x_minus", sym_edges, gxm, "1", "1", "g_x^(-)(C_x): particles with C_y < 0 (Eq. 3.18)");
    out.histogram("g_y_plus", sym_edges, gyp, "1", "1", "g_y^(+)(C_y): particles with C_x > 0 (Eq. 3.19)");
    out.histogram("g_y_minus", sym_edges, gym, "1", "1", "g_y^(-)(C_y): particles with C_x < 0 (Eq. 3.19)");
    out.histogram("g_x_plus_symmetrized", sym_edges, gxs, "1", "1", "[g_x^(+)(C_x) + g_x^(-)(-C_x)]/2 (Eq. 5.3)");
    out.histogram("g_y_plus_symmetrized", sym_edges, gys, "1", "1", "[g_y^(+)(C_y) + g_y^(-)(-C_y)]/2 (Eq. 5.3)");
    out.histogram("g_local_equilibrium", sym_edges, gle, "1", "1", "bin average of exp(-C^2)/(2 sqrt(pi)), g^(+-) of a Maxwellian");
    out.histogram("F", edges, scaled(F_, norm), "1", "1", "F(C) = C^2 int dC_hat f*(C) (Eq. 3.20)");
    out.histogram("F_local_equilibrium", edges, Fle, "1", "1", "bin average of 4 C^2 exp(-C^2)/sqrt(pi)");
    out.theory("g_local_equilibrium", "g_x_plus, g_x_minus, g_y_plus, g_y_minus, g_x_plus_symmetrized, g_y_plus_symmetrized",
               "000 Eqs. 3.18-3.19 of a Maxwellian");
    out.theory("F_local_equilibrium", "F", "000 Eq. 3.20 of a Maxwellian");
    out.attribute("edges", doc_c);
    out.scalar("samples", static_cast<double>(samples_), "1", "samples accumulated (in the averaging window)");
    const double tot = total_ > 0 ? total_ : 1.0;
    out.scalar("fraction_outside", (outside_x_ + outside_y_ + outside_c_) / (3.0 * tot), "1",
               "mean fraction of particle samples beyond c_max (of the three kinds of histogram)");
    out.scalar("symmetry_defect", defect, "1", "max over bins of |g_x^(+)(C_x) - g_x^(-)(-C_x)| (0 by Eq. 3.21, up to noise)");
    char buf[200];
    std::snprintf(buf, sizeof buf, "velocity_marginals: %zu samples in the averaging window; symmetry defect (3.21) %.3g",
                  samples_, defect);
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("g_x_plus", gxp_);
    out.write("g_x_minus", gxm_);
    out.write("g_y_plus", gyp_);
    out.write("g_y_minus", gym_);
    out.write("F", F_);
    out.write("outside_x", outside_x_);
    out.write("outside_y", outside_y_);
    out.write("outside_c", outside_c_);
    out.write("total", total_);
    out.write("samples", static_cast<std::uint64_t>(samples_));
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("g_x_plus", gxp_.data(), bins_);
    in.read("g_x_minus", gxm_.data(), bins_);
    in.read("g_y_plus", gyp_.data(), bins_);
    in.read("g_y_minus", gym_.data(), bins_);
    in.read("F", F_.data(), bins_);
    in.read("outside_x", outside_x_);
    in.read("outside_y", outside_y_);
    in.read("outside_c", outside_c_);
    in.read("total", total_);
    std::uint64_t samples = 0;
    in.read("samples", samples);
    samples_ = static_cast<std::size_t>(samples);
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  const void* extension(const char* id) const override { return gdsmc::offer_bracketed_sampling(id); }
 private:
  double c_max_;
  std::size_t bins_;
  std::vector<double> gxp_, gxm_, gyp_, gym_, F_;
  double outside_x_ = 0, outside_y_ = 0, outside_c_ = 0, total_ = 0;
  std::size_t samples_ = 0;
};

}  // namespace

GDSMC_PLUGIN(VelocityMarginals)
