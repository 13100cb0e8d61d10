// Test plugin: a forcing that does nothing until step `step`, where it writes `value` (nan or inf)
// into vx of the particle in storage slot `slot`, or with `value: zero` sets every velocity to 0
// (all finite, a temperature of 0), and declares no energy change (finite).
#include <cstdint>
#include <limits>

#include <gdsmc/gdsmc.hpp>

namespace {

class NanForcing final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "nan_forcing";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a forcing that writes a non-finite velocity";
  static constexpr const char* documentation =
      "At step `step`, vx of the particle in storage slot `slot` becomes `value` (nan, inf), or every velocity\n"
      "becomes 0 (value: zero); the declared energy is 0.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("step", "the step of the bad write").at_least(0).default_value(5),
            gdsmc::ParamSpec::integer("slot", "the storage slot written").at_least(0).default_value(17),
            gdsmc::ParamSpec::choice("value", {"nan", "inf", "zero"}, "what it writes").default_value("nan")};
  }
  explicit NanForcing(const gdsmc::Params& p)
      : step_(p.integer("step")),
        slot_(p.integer("slot")),
        zero_(p.string("value") == "zero"),
        bad_(p.string("value") == "nan" ? std::numeric_limits<double>::quiet_NaN()
                                        : std::numeric_limits<double>::infinity()) {}
  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (static_cast<std::int64_t>(ctx.step) != step_) return 0.0;
    if (zero_) {
      for (std::size_t i = 0; i < p.count; ++i) p.vx[i] = p.vy[i] = p.vz[i] = 0.0;
    } else if (static_cast<std::size_t>(slot_) < p.count) {
      p.vx[slot_] = bad_;
    }
    return 0.0;
  }

 private:
  std::int64_t step_, slot_;
  bool zero_;
  double bad_;
};

}  // namespace

GDSMC_PLUGIN(NanForcing)
