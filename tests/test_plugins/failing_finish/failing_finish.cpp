#include <stdexcept>

#include <gdsmc/gdsmc.hpp>

namespace {

class FailingFinish final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "failing_finish";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: records a series, then throws in finish()";
  static constexpr const char* documentation = "Records the step number; finish() throws.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit FailingFinish(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    id_ = out.series("step", "1", "the step number");
  }
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    out.append(id_, static_cast<double>(ctx.step));
  }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink&) override {
    throw std::runtime_error("deliberate failure at the end of the run");
  }

 private:
  std::size_t id_ = 0;
};

}  // namespace

GDSMC_PLUGIN(FailingFinish)
