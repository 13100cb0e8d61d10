// Test plugin: the process that runs it dies of a signal at a given step, as a rank of an MPI job
// does when the OOM killer or a node failure takes it (SIGKILL: no handler runs) or a plugin
// crashes (SIGSEGV, through whatever handler is installed for it, as a real crash goes: Open MPI's
// prints a backtrace, then the process dies of the signal). Raised in sample(), from the run's own
// thread, mid-run.
#include <csignal>
#include <cstdio>

#include <gdsmc/gdsmc.hpp>

namespace {

class DiesAtStep final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "dies_at_step";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: its process dies of SIGKILL or SIGSEGV at a given step";
  static constexpr const char* documentation =
      "Records the step number; at the first sample (every step by default) of a step >= `step` it raises "
      "`signal` (KILL or SEGV) in its own process.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("step", "the step at which the process dies").at_least(1).default_value(1),
            gdsmc::ParamSpec::choice("signal", {"KILL", "SEGV"}, "the signal it dies of").default_value("KILL")};
  }
  explicit DiesAtStep(const gdsmc::Params& p)
      : step_(p.integer("step")), signal_(p.string("signal") == "SEGV" ? SIGSEGV : SIGKILL) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    id_ = out.series("step", "1", "the step number");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    if (static_cast<std::int64_t>(ctx.step) < step_) return;
    std::fprintf(stderr, "dies_at_step: raising SIG%s at step %lld\n", signal_ == SIGKILL ? "KILL" : "SEGV",
                 static_cast<long long>(ctx.step));
    std::fflush(stderr);
    std::raise(signal_);
  }
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    out.append(id_, static_cast<double>(ctx.step));
  }

 private:
  std::int64_t step_;
  int signal_;
  std::size_t id_ = 0;
};

}  // namespace

GDSMC_PLUGIN(DiesAtStep)
