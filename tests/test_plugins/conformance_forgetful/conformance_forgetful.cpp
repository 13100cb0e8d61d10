// Test plugin: a temperature diagnostic that keeps a running mean over the whole run but does not
// save it in a checkpoint (no save_state / load_state). Conformance check `checkpoint` must fail.
#include <gdsmc/gdsmc.hpp>

namespace {

class Forgetful final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "conformance_forgetful";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Test: running mean of T that a checkpoint loses";
  static constexpr const char* documentation = "Records the mean of T/T0 over every sample since the start of the run.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Forgetful(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    t0_ = sys.initial_temperature;
    id_ = out.series("running_mean_temperature", "T0", "mean of T/T0 since the start");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    sum_ += ctx.moments->local.temperature / t0_;
    ++samples_;
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.append(id_, sum_ / static_cast<double>(samples_));
  }

 private:
  double t0_ = 1, sum_ = 0;
  std::uint64_t samples_ = 0;  // forgotten by a checkpoint: the bug this plugin exists for
  std::size_t id_ = 0;
};

}  // namespace

GDSMC_PLUGIN(Forgetful)
