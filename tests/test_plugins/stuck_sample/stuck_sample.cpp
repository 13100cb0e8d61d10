#include <chrono>
#include <thread>

#include <gdsmc/gdsmc.hpp>

namespace {

class StuckSample final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "stuck_sample";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: sample() blocks forever from the first step on";
  static constexpr const char* documentation = "Samples the initial state normally; from step 1 on, sample() never returns.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit StuckSample(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    id_ = out.series("step", "1", "the step number");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    while (ctx.step > 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    out.append(id_, static_cast<double>(ctx.step));
  }

 private:
  std::size_t id_ = 0;
};

}  // namespace

GDSMC_PLUGIN(StuckSample)
