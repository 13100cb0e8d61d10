// Test plugin: a diagnostic that declares it reads only the kinetic energy of the sampled moments
// (MomentsRead) but records the temperature as well. Conformance check `diagnostic.moments_read`
// must fail: with only the declared part measured, its temperature is NaN.
#include <gdsmc/gdsmc.hpp>

namespace {

class UndeclaredMoments final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "conformance_undeclared_moments";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Test: reads a part of the sampled moments it does not declare";
  static constexpr const char* documentation = "Records E/(N T0) and T/T0 of each sample; declares only the energy.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit UndeclaredMoments(const gdsmc::Params&) {}
  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    t0_ = sys.initial_temperature;
    energy_ = out.series("energy_per_particle", "T0", "E / (N T0)");
    temperature_ = out.series("temperature", "T0", "T / T0");
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    e_ = ctx.moments->kinetic_energy / (static_cast<double>(p.count) * t0_);
    t_ = ctx.moments->local.temperature / t0_;  // the bug: not among the declared parts
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.append(energy_, e_);
    out.append(temperature_, t_);
  }
  const void* extension(const char* id) const override { return gdsmc::offer_moments_read<gdsmc::moments_energy>(id); }

 private:
  double t0_ = 1, e_ = 0, t_ = 0;
  std::size_t energy_ = 0, temperature_ = 0;
};

}  // namespace

GDSMC_PLUGIN(UndeclaredMoments)
