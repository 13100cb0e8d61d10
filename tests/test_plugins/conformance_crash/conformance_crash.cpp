// Deliberately broken (conformance test): a collision rule that kills its process (abort) on
// the first collision. `gdsmc conformance` must print CRASH lines and carry on with other checks.
#include <cstdlib>

#include <gdsmc/gdsmc.hpp>

namespace {
struct CrashingRule {
  static constexpr const char* name = "conformance_crash";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that crashes";
  static constexpr const char* documentation = "collide() calls std::abort().";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit CrashingRule(const gdsmc::Params&) {}
  double collide(gdsmc::Vec3&, gdsmc::Vec3&, const gdsmc::Vec3&, gdsmc::PairContext&) const { std::abort(); }
};
}  // namespace

GDSMC_PLUGIN(CrashingRule)
