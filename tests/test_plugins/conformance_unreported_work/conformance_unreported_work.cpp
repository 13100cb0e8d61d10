// Deliberately broken (conformance test): heats the gas but returns 0 from apply(), so the run's
// energy ledger would hide its work. `gdsmc conformance` must report forcing.energy FAIL.
#include <gdsmc/gdsmc.hpp>

namespace {
class UnreportedWork final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "conformance_unreported_work";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a forcing that does not report the energy it adds";
  static constexpr const char* documentation = "Multiplies velocities by (1 + 0.01 dt/tau0) and returns 0.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit UnreportedWork(const gdsmc::Params&) {}
  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double f = 1.0 + 0.01 * ctx.dt / ctx.system->time_unit0;
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] *= f;
      p.vy[i] *= f;
      p.vz[i] *= f;
    }
    return 0.0;
  }
};
}  // namespace

GDSMC_PLUGIN(UnreportedWork)
