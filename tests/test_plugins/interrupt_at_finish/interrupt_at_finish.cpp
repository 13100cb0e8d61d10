// Test plugin: a Ctrl-C that arrives when the computation is over and the file is being written.
// finish() is the last plugin call of a run; the host's handler only sets its interrupt flag, so
// the run itself completes and the flag is seen by the writing that follows.
#include <csignal>

#include <gdsmc/gdsmc.hpp>

namespace {

class InterruptAtFinish final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "interrupt_at_finish";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: records a series, then raises SIGINT in finish()";
  static constexpr const char* documentation = "Records the step number; finish() raises SIGINT in its own process.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit InterruptAtFinish(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    id_ = out.series("step", "1", "the step number");
  }
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    out.append(id_, static_cast<double>(ctx.step));
  }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink&) override { std::raise(SIGINT); }

 private:
  std::size_t id_ = 0;
};

}  // namespace

GDSMC_PLUGIN(InterruptAtFinish)
