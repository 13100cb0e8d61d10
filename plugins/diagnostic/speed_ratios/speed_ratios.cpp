// Population ratios R_l of speed shells relative to local equilibrium (000 Eqs. 3.15, 4.19).
#include <cmath>
#include <cstdio>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {


class SpeedRatios final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "speed_ratios";
  static constexpr const char* version = "1.3.0";
  static constexpr const char* summary = "R_0..R_3: speed-shell populations over local equilibrium (Eqs. 3.15, 4.19)";
  static constexpr const char* documentation =
      "R_l = [fraction of particles with W_l < V < W_{l+1}] / [P(C_{l+1}) - P(C_l)] (paper 000, Eq. 4.19),\n"
      "with V the speed relative to the local flow (the mean of all particles in a homogeneous system, of\n"
      "the particle's layer in a slab, u_I as of the host's last moment update), W_l = C_l sqrt(2T/m) at the current T (T-bar of Eq. 4.8 in a\n"
      "slab; the host's moments of the sample, ctx.moments), C_0..C_4 = 0, 1, 2, 3, infinity (text after\n"
      "Eq. 3.15) and P(x) = erf(x) - 2x exp(-x^2)/sqrt(pi) the local-equilibrium (Maxwellian) fraction\n"
      "of reduced speeds below x. R_l = 1 for a Maxwellian. Series [1]: R0, R1, R2, R3 and the raw\n"
      "fractions fraction0, fraction1, fraction2, fraction3 (local-equilibrium values 0.4276, 0.5264, 0.0456, 0.00044). Paper values at\n"
      "alpha = 0.5, a tau0 = 4 (steady): R0 ~ 1.18, R1 ~ 0.81, R2 ~ 1.39, R3 ~ 15. After the run:\n"
      "scalars R<l>_mean and R<l>_standard_error over the samples in the run's steady averaging window\n"
      "(run.average_after; ctx.in_average_window, no parameter of its own).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit SpeedRatios(const gdsmc::Params&) {
    const double C[5] = {0, 1, 2, 3, INFINITY};
    for (int l = 0; l < 4; ++l) reference_[l] = gdsmc::maxwell_speed_fraction_below(C[l + 1]) - gdsmc::maxwell_speed_fraction_below(C[l]);
  }

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    std::vector<gdsmc::WindowAverage::Column> cols;
    static const char* const doc_R[4] = {"R_0 (Eq. 4.19)", "R_1 (Eq. 4.19)", "R_2 (Eq. 4.19)", "R_3 (Eq. 4.19)"};
    static const char* const doc_f[4] = {"fraction of particles with 0 < V/sqrt(2T/m) < 1",
                                         "fraction of particles with 1 < V/sqrt(2T/m) < 2",
                                         "fraction of particles with 2 < V/sqrt(2T/m) < 3",
                                         "fraction of particles with V/sqrt(2T/m) > 3"};
    static const char* const name_R[4] = {"R0", "R1", "R2", "R3"};
    static const char* const name_f[4] = {"fraction0", "fraction1", "fraction2", "fraction3"};
    for (int l = 0; l < 4; ++l) cols.push_back({name_R[l], "1", doc_R[l]});
    for (int l = 0; l < 4; ++l) cols.push_back({name_f[l], "1", doc_f[l]});
    window_.declare(out, cols);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%.8f %.8f %.8f %.8f", reference_[0], reference_[1], reference_[2], reference_[3]);
    out.attribute("local_equilibrium_fractions", buf);
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const bool slab = ctx.system->geometry == gdsmc::Geometry::slab;
    const double v0sq = 2.0 * m.temperature;  // (sqrt(2T/m))^2, m = 1
    std::size_t counts[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < p.count; ++i) {
      const double* u = slab ? ctx.cells[p.cell[i]].mean_velocity : m.mean;  // the local flow
      const double cx = p.vx[i] - u[0], cy = p.vy[i] - u[1], cz = p.vz[i] - u[2];
      const double c2 = (cx * cx + cy * cy + cz * cz) / v0sq;
      const int l = c2 < 1.0 ? 0 : c2 < 4.0 ? 1 : c2 < 9.0 ? 2 : 3;
      ++counts[l];
    }
    std::vector<double> v(8);
    const double inv = p.count ? 1.0 / static_cast<double>(p.count) : 0.0;
    const bool steady = ctx.in_average_window;
    for (int l = 0; l < 4; ++l) {
      v[4 + l] = static_cast<double>(counts[l]) * inv;
      v[l] = v[4 + l] / reference_[l];
      if (steady) avg_[l].add(v[l]);
    }
    window_.add(v);
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    std::string line = "speed_ratios: in the averaging window:";
    for (int l = 0; l < 4; ++l) {
      const std::string n = "R" + std::to_string(l);
      out.scalar(n + "_mean", avg_[l].mean(), "1", n + " averaged over the averaging window");
      out.scalar(n + "_standard_error", avg_[l].standard_error(), "1", "batch-means standard error of " + n + "_mean");
      char buf[80];
      std::snprintf(buf, sizeof buf, " %s = %.3f +- %.3f", n.c_str(), avg_[l].mean(), avg_[l].standard_error());
      line += buf;
    }
    out.summary(line + " (paper, alpha = 0.5: 1.18, 0.81, 1.39, 15)");
  }
  void save_state(gdsmc::StateWriter& out) const override {
    window_.save(out);
    for (int l = 0; l < 4; ++l) avg_[l].save(out, "avg.R" + std::to_string(l));
  }
  void load_state(gdsmc::StateReader& in) override {
    window_.load(in);
    for (int l = 0; l < 4; ++l) avg_[l].load(in, "avg.R" + std::to_string(l));
  }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  const void* extension(const char* id) const override { return gdsmc::offer_bracketed_sampling(id); }
 private:
  double reference_[4];
  gdsmc::WindowAverage window_;
  gdsmc::BatchMeans avg_[4];
};

}  // namespace

GDSMC_PLUGIN(SpeedRatios)
