// System averages of a slab (paper 000 Eqs. 4.8-4.9, Fig. 4) and the flow, density and
// temperature of the central and top layers (Fig. 3).
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class SlabAverages final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "slab_averages";
  static constexpr const char* version = "1.3.0";
  static constexpr const char* summary =
      "T_bar/T0, reduced mean pressure tensor, and u_x, n, T of the central and top layers (000 Figs. 3-4)";
  static constexpr const char* documentation =
      "Slab systems only; L = Ly, M = system.cells layers of width dy = L / M, n = n_bar.\n"
      "From the shared moments of each sample (000 Sec. IV.A, peculiar velocities relative to the\n"
      "flow of each particle's layer):\n"
      "  T_bar = (1/N) sum_I N_I T_I                      (Eq. 4.8)   series T_bar [T0]\n"
      "  P_bar = (1/M) sum_I P_I = n_bar m <V V>          (Eq. 4.9)\n"
      "  series minus_Pxy_over_nT = -P_xy / (n_bar T_bar), Pxx_minus_Pyy_over_nT = (P_xx - P_yy) /\n"
      "  (n_bar T_bar), Pyy_minus_Pzz_over_nT = (P_yy - P_zz) / (n_bar T_bar) [1] (Fig. 4).\n"
      "Two groups of layers for Fig. 3, computed at each sample from the host's fresh moments of each\n"
      "layer (SampledMoments::cells: N_I, u_I, T_I; no particle is read), layers I = 0..M-1 along y: 'centre', the layers inside |y| <= 2 dy (the four\n"
      "central layers when M is even), and 'top', the three top layers, L/2 - 3 dy <= y <= L/2.\n"
      "For each group G with N_G particles in its M_G layers:\n"
      "  u_x = (1 / N_G) sum_{I in G} N_I u_x,I  (the mean v_x of its particles)  [sqrt(2T0/m)]\n"
      "  n = N_G / (M_G A dy)  (A dy the layer volume, Eq. 4.4)           [n0]\n"
      "  T = (1 / N_G) sum_{I in G} N_I T_I  with T_I of Eq. (4.6), i.e. each layer's temperature\n"
      "      about its own mean velocity u_I (Eq. 4.5), weighted by its count   [T0]\n"
      "Series centre_u_x, centre_n, centre_T, top_u_x, top_n, top_T. Each record is the mean of\n"
      "the samples since the previous record (a group without particles in a sample gives NaN for\n"
      "its u_x and T in that window). Needs at least 3 layers; with M < 8 the groups overlap.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit SlabAverages(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("slab_averages: needs a slab system (system.domain: slab)");
    layers_ = sys.cells;
    if (layers_ < 3)
      throw std::runtime_error("slab_averages: needs at least 3 layers (system.cells), got " + std::to_string(layers_));
    if (sys.layer_edges)
      throw std::runtime_error("slab_averages: needs layers of equal width (the groups of 000 Sec. IV.A are counted "
                               "in layer widths); this run sizes its layers otherwise");
    half_ = 0.5 * sys.box[1];
    dy_ = sys.layer_width(0);
    layer_volume_ = dy_ * sys.cross_section();
    n0_ = sys.number_density;
    t0_ = sys.initial_temperature;
    v0_ = std::sqrt(2.0 * sys.initial_temperature / sys.mass);
    // Groups (a layer may belong to both when M < 8): centre = the layers whose extent lies
    // within [-2 dy, 2 dy] (to round-off); top = layers M-3..M-1.
    in_group_[kCentre].assign(layers_, 0);
    in_group_[kTop].assign(layers_, 0);
    const double tol = 1e-9 * dy_;
    for (std::size_t I = 0; I < layers_; ++I) {
      const double lo = -half_ + static_cast<double>(I) * dy_, hi = lo + dy_;
      in_group_[kCentre][I] = lo >= -2.0 * dy_ - tol && hi <= 2.0 * dy_ + tol;
      in_group_[kTop][I] = I + 3 >= layers_;
    }
    for (int g : {kCentre, kTop}) {
      group_layers_[g] = 0;
      for (std::size_t I = 0; I < layers_; ++I) group_layers_[g] += in_group_[g][I];
    }
    values_.assign(10, 0.0);
    window_.declare(out, {{"T_bar", "T0", "mean temperature T_bar = (1/N) sum_I N_I T_I (000 Eq. 4.8)"},
                          {"minus_Pxy_over_nT", "1", "-P_bar_xy / (n_bar T_bar), P_bar of 000 Eq. (4.9)"},
                          {"Pxx_minus_Pyy_over_nT", "1", "(P_bar_xx - P_bar_yy) / (n_bar T_bar) (000 Eq. 4.9)"},
                          {"Pyy_minus_Pzz_over_nT", "1", "(P_bar_yy - P_bar_zz) / (n_bar T_bar) (000 Eq. 4.9)"},
                          {"centre_u_x", "sqrt(2T0/m)", "flow velocity u_x of the layers inside |y| <= 2 dy (000 Fig. 3)"},
                          {"centre_n", "n0", "number density of the layers inside |y| <= 2 dy (000 Eq. 4.4, Fig. 3)"},
                          {"centre_T", "T0", "count-weighted mean of the layer temperatures T_I (000 Eq. 4.6) inside |y| <= 2 dy"},
                          {"top_u_x", "sqrt(2T0/m)", "flow velocity u_x of the three top layers (000 Fig. 3)"},
                          {"top_n", "n0", "number density of the three top layers (000 Eq. 4.4, Fig. 3)"},
                          {"top_T", "T0", "count-weighted mean of the layer temperatures T_I (000 Eq. 4.6) of the three top layers"}});
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const double T = m.temperature;
    values_[0] = T / t0_;
    values_[1] = -m.second[0][1] / T;  // P_bar / (n_bar T_bar) = m <V V> / T_bar
    values_[2] = (m.second[0][0] - m.second[1][1]) / T;
    values_[3] = (m.second[1][1] - m.second[2][2]) / T;

    for (int g : {kCentre, kTop}) {
      double N = 0, sx = 0, nt = 0;  // sum_I N_I, sum_I N_I u_x,I, sum_I N_I T_I
      for (std::size_t I = 0; I < layers_; ++I) {
        const gdsmc::CellMoments& c = ctx.moments->cells[I];
        if (!in_group_[g][I] || c.count == 0) continue;
        const double n = static_cast<double>(c.count);
        N += n;
        sx += n * c.mean_velocity[0];
        nt += n * c.temperature;  // T_I of Eq. 4.6 (0 for a lone particle, which has no peculiar motion)
      }
      double* v = &values_[4 + 3 * static_cast<std::size_t>(g)];
      v[0] = N > 0 ? sx / N / v0_ : std::nan("");
      v[1] = N / (static_cast<double>(group_layers_[g]) * layer_volume_) / n0_;
      v[2] = N > 0 ? nt / N / t0_ : std::nan("");
    }
    window_.add(values_);
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  // values_ is scratch of one sample.
  void save_state(gdsmc::StateWriter& out) const override { window_.save(out); }
  void load_state(gdsmc::StateReader& in) override { window_.load(in); }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Reads the host's peculiar moments and cells, no particle (MomentsRead).
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_peculiar | gdsmc::moments_cells, gdsmc::reads_no_particles>(id);
  }
 private:
  enum Group : int { kCentre = 0, kTop = 1 };

  std::size_t layers_ = 1;
  double half_ = 0, dy_ = 1, layer_volume_ = 1, n0_ = 1, t0_ = 1, v0_ = 1;
  std::vector<unsigned char> in_group_[2];  // per group, per layer: 1 if the layer belongs to it
  std::size_t group_layers_[2] = {0, 0};
  std::vector<double> values_;   // one sample's values, in the order of the columns
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(SlabAverages)

// What `gdsmc conformance` runs it in when no --context is given.
// A slab between diffuse walls.
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
    "boundaries: {y: diffuse_wall}")
