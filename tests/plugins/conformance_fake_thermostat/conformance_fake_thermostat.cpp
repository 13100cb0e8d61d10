// Deliberately broken (conformance test): declares that it conserves energy, but heats the gas.
// `gdsmc conformance` must report forcing.conservation FAIL.
#include <gdsmc/gdsmc.hpp>

namespace {
class FakeThermostat final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "conformance_fake_thermostat";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a forcing that breaks the conservation it declares";
  static constexpr const char* documentation = "Multiplies velocities by (1 + 0.01 dt/tau0); claims to conserve energy.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit FakeThermostat(const gdsmc::Params&) {}
  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {true, true}; }
  void apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, gdsmc::Rng&) override {
    const double f = 1.0 + 0.01 * ctx.dt / ctx.system->time_unit0;  // heats by 2% per tau0
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] *= f;
      p.vy[i] *= f;
      p.vz[i] *= f;
    }
  }
};
}  // namespace

GDSMC_PLUGIN(FakeThermostat)
