// Deliberately broken (conformance test): declares that it conserves energy, but heats the gas.
// `gdsmc conformance` must report forcing.conservation FAIL.
#include <gdsmc/gdsmc.hpp>

namespace {
class FakeThermostat final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "conformance_fake_thermostat";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a forcing that breaks the conservation it declares";
  static constexpr const char* documentation =
      "Multiplies velocities by (1 + 0.01 dt/tau0); claims to conserve energy (but reports the energy it adds).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit FakeThermostat(const gdsmc::Params&) {}
  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {true, true}; }
  // Returns the energy it really adds, so that only the declared conservation is broken.
  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double f = 1.0 + 0.01 * ctx.dt / ctx.system->time_unit0;  // heats by 2% per tau0
    double v2 = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
      p.vx[i] *= f;
      p.vy[i] *= f;
      p.vz[i] *= f;
    }
    return 0.5 * (f * f - 1.0) * v2;
  }
};
}  // namespace

GDSMC_PLUGIN(FakeThermostat)
