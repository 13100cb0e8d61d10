// The distribution of the reduced speed c = |V| / sqrt(2T/m), written through the SDK output sink
// as a series, a histogram with its bin edges, an array and scalars. The diagnostic never sees
// HDF5: the host writes whatever it hands to the sink into its group of the output file.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class SpeedDistribution final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "speed_distribution";
  static constexpr const char* version = "1.2.1";
  static constexpr const char* summary = "Histogram of the reduced speed c = |V|/sqrt(2T/m) against the Maxwellian";
  static constexpr const char* documentation =
      "At every sample, the reduced speeds c = |v - u| / sqrt(2T/m) of all particles are binned on\n"
      "[0, c_max) in `bins` bins. T is that sample's temperature (ctx.moments, computed once by the\n"
      "host; T-bar of 000 Eq. 4.8 in a slab) and u the local flow: the mean of all particles in a\n"
      "homogeneous system, the particle's layer mean u_I in a slab (ctx.cells, as of the host's last\n"
      "moment update). Output (group of this diagnostic):\n"
      "  series  mean_speed [1]        <c> of each sample, averaged over the record window\n"
      "                                (Maxwellian: 2/sqrt(pi) = 1.128)\n"
      "  series  tail_fraction [1]     fraction of particles with c > c_tail\n"
      "  histogram speed_pdf           probability density of c over all samples, edges in [1]\n"
      "  array   maxwellian_pdf [1]    4/sqrt(pi) c^2 exp(-c^2) at the bin centres, marked as theory of\n"
      "                                speed_pdf (OutputSink::theory)\n"
      "  scalar  samples [1]           number of samples accumulated in the histogram\n"
      "  scalar  overflow_fraction [1] fraction of speeds at or beyond c_max (not in the histogram)";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("bins", "number of histogram bins").range(1, 100000).default_value(40),
            gdsmc::ParamSpec::real("c_max", "upper edge of the histogram (reduced speed)").above(0.0).default_value(4.0),
            gdsmc::ParamSpec::real("c_tail", "speed beyond which the tail fraction is counted").above(0.0).default_value(2.0)};
  }
  explicit SpeedDistribution(const gdsmc::Params& p)
      : bins_(static_cast<std::size_t>(p.integer("bins"))), c_max_(p.real("c_max")), c_tail_(p.real("c_tail")) {
    if (c_tail_ >= c_max_) throw gdsmc::ParameterError("c_tail", "c_tail must be below c_max");
  }

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    counts_.assign(bins_, 0.0);
    window_.declare(out, {{"mean_speed", "1", "mean reduced speed <c>"},
                          {"tail_fraction", "1", "fraction of particles with c > c_tail"}});
    out.attribute("c_definition", "c = |v - u| / sqrt(2 T / m), T and u of the sample");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    const bool slab = ctx.system->geometry == gdsmc::Geometry::slab;
    const double inv_scale = 1.0 / std::sqrt(2.0 * m.temperature);
    const double width = c_max_ / static_cast<double>(bins_);
    double sum = 0, tail = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      const double* u = slab ? ctx.cells[p.cell[i]].mean_velocity : m.mean;  // the local flow
      const double dx = p.vx[i] - u[0], dy = p.vy[i] - u[1], dz = p.vz[i] - u[2];
      const double c = std::sqrt(dx * dx + dy * dy + dz * dz) * inv_scale;
      sum += c;
      tail += c > c_tail_;
      const auto b = static_cast<std::size_t>(c / width);
      if (b < bins_) counts_[b] += 1;
      else overflow_ += 1;
    }
    total_ += static_cast<double>(p.count);
    ++samples_;
    const double n = static_cast<double>(p.count);
    window_.add({sum / n, tail / n});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double width = c_max_ / static_cast<double>(bins_);
    std::vector<double> edges(bins_ + 1), pdf(bins_), maxwell(bins_);
    for (std::size_t b = 0; b <= bins_; ++b) edges[b] = width * static_cast<double>(b);
    for (std::size_t b = 0; b < bins_; ++b) {
      pdf[b] = total_ > 0 ? counts_[b] / (total_ * width) : 0.0;
      const double c = width * (static_cast<double>(b) + 0.5);
      maxwell[b] = 4.0 / std::sqrt(M_PI) * c * c * std::exp(-c * c);
    }
    out.histogram("speed_pdf", edges, pdf, "1", "1", "probability density of the reduced speed c over all samples");
    out.array("maxwellian_pdf", maxwell, {bins_}, "1", "Maxwellian density 4/sqrt(pi) c^2 exp(-c^2) at the bin centres");
    out.theory("maxwellian_pdf", "speed_pdf", "Maxwell's speed distribution");  // SDK 6.3: gdsmc plot pairs them
    out.scalar("samples", static_cast<double>(samples_), "1", "samples accumulated in speed_pdf");
    out.scalar("overflow_fraction", total_ > 0 ? overflow_ / total_ : 0.0, "1", "fraction of speeds >= c_max");
    char buf[160];
    std::snprintf(buf, sizeof buf, "speed_distribution: %zu samples in %zu bins on [0, %g)", samples_, bins_, c_max_);
    out.summary(buf);
  }
  // Checkpoints: everything sample() accumulates, in a fixed order; load_state reads it back into
  // an object that begin() has set up again (counts_ sized to bins_, the series declared).
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("counts", counts_);
    out.write("overflow", overflow_);
    out.write("total", total_);
    out.write("samples", static_cast<std::uint64_t>(samples_));
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("counts", counts_.data(), counts_.size());  // exactly `bins` values, else a StateError
    in.read("overflow", overflow_);
    in.read("total", total_);
    std::uint64_t samples = 0;
    in.read("samples", samples);
    samples_ = static_cast<std::size_t>(samples);
    window_.load(in);
  }

 private:
  std::size_t bins_;
  double c_max_, c_tail_;
  std::vector<double> counts_;
  double overflow_ = 0, total_ = 0;
  std::size_t samples_ = 0;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(SpeedDistribution)
