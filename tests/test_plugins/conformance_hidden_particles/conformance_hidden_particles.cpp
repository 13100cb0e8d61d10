// Test plugin: a diagnostic that declares its sample reads no particle (MomentsRead::particles = 0,
// what spares a decomposed run the gather to rank 0) but sums the particles' v_x. Conformance check
// `diagnostic.moments_read` must fail: on the empty span a decomposed run hands it, its mean flow is
// NaN.
#include <gdsmc/gdsmc.hpp>

namespace {

class HiddenParticles final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "conformance_hidden_particles";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Test: reads the particles though it declares it reads none";
  static constexpr const char* documentation = "Records the mean v_x of the particles of each sample; declares no particle.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit HiddenParticles(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    flow_ = out.series("mean_vx", "sqrt(T0/m)", "mean v_x of the particles");
  }
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan& p) override {
    double s = 0;
    for (std::size_t i = 0; i < p.count; ++i) s += p.vx[i];  // the bug: declared as reading no particle
    mean_ = s / static_cast<double>(p.count);
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { out.append(flow_, mean_); }
  const void* extension(const char* id) const override {
    return gdsmc::offer_moments_read<0, gdsmc::reads_no_particles>(id);
  }

 private:
  double mean_ = 0;
  std::size_t flow_ = 0;
};

}  // namespace

GDSMC_PLUGIN(HiddenParticles)
