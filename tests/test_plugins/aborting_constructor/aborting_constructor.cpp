// Deliberately broken (loader test): an otherwise ordinary diagnostic plugin whose library aborts
// in a static constructor, before the host can look at its entry point. A host that loads it
// in its own process dies of SIGABRT; gdsmc must warn and carry on.
#include <cstdlib>

#include <gdsmc/gdsmc.hpp>

namespace {

struct AbortOnLoad {
  AbortOnLoad() { std::abort(); }
} abort_on_load;

struct Nothing final : gdsmc::Diagnostic {
  static constexpr const char* name = "aborting_constructor";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: its library aborts when loaded";
  static constexpr const char* documentation = "A static constructor calls std::abort().";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Nothing(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink&) override {}
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  void record(const gdsmc::StepContext&, gdsmc::OutputSink&) override {}
};

}  // namespace

GDSMC_PLUGIN(Nothing)
