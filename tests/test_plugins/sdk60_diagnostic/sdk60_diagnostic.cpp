// A diagnostic as a plugin built against SDK 6.0 presents itself: its entry claims ABI 6.0 (the
// fingerprint is the 6.0 prefix of every host-owned struct, which 6.1 keeps) and it offers no
// extension. A 6.1 host must load it and sample it once a step, after the step, as 6.0 did. Each
// record holds the samples it saw since the last one and the steps they came from.
#include <gdsmc/gdsmc.hpp>

namespace {

class Sdk60Diagnostic final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "sdk60_diagnostic";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a diagnostic built against SDK 6.0 (no extensions)";
  static constexpr const char* documentation = "Records its sample count and the number of distinct steps sampled per record.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Sdk60Diagnostic(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    samples_id_ = out.series("samples", "1", "sample() calls since the last record");
    steps_id_ = out.series("steps", "1", "distinct steps among them");
    phase_id_ = out.series("max_phase", "1", "the largest StepContext::sample_phase seen");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    ++samples_;
    if (ctx.step != last_step_) ++steps_;
    last_step_ = ctx.step;
    phase_ = std::max(phase_, static_cast<double>(ctx.sample_phase));
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.append(samples_id_, samples_);
    out.append(steps_id_, steps_);
    out.append(phase_id_, phase_);
    samples_ = steps_ = 0;
  }

 private:
  std::size_t samples_id_ = 0, steps_id_ = 0, phase_id_ = 0;
  double samples_ = 0, steps_ = 0, phase_ = 0;
  std::uint64_t last_step_ = ~std::uint64_t{0};
};

const gdsmc::PluginDescriptor* describe_sdk60() {
  static const gdsmc::PluginDescriptor descriptor = gdsmc::describe<Sdk60Diagnostic>();
  return &descriptor;
}

// GDSMC_PLUGIN's entry, with the minor of SDK 6.0.
const gdsmc::PluginEntry* sdk60_entry() {
  static const gdsmc::PluginEntry entry{gdsmc::plugin_magic, 6u, 0u, 0u, gdsmc::abi_fingerprint(), &describe_sdk60};
  return &entry;
}

}  // namespace

BOOST_DLL_ALIAS(sdk60_entry, gdsmc_plugin_entry)
