#include <stdexcept>

#include <gdsmc/gdsmc.hpp>

namespace {

class ThrowingFactory final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "throwing_factory";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: its constructor throws";
  static constexpr const char* documentation = "Throws from its constructor, as `mode` says.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::choice("mode", {"runtime_error", "parameter_error", "none"}, "what the constructor throws")
                .default_value("runtime_error"),
            gdsmc::ParamSpec::real("limit", "a value the constructor refuses above 1 (ParameterError)").default_value(0.5)};
  }
  explicit ThrowingFactory(const gdsmc::Params& p) {
    const std::string mode = p.string("mode");
    if (mode == "runtime_error") throw std::runtime_error("deliberate failure in the throwing_factory constructor");
    if (mode == "parameter_error" || p.real("limit") > 1)
      throw gdsmc::ParameterError("limit", "limit must not exceed 1 (deliberate ParameterError)");
  }
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink&) override {}
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  void record(const gdsmc::StepContext&, gdsmc::OutputSink&) override {}
};

}  // namespace

GDSMC_PLUGIN(ThrowingFactory)
