// Deliberately broken (conformance test): the second particle receives only 90% of the impulse,
// so every collision leaks momentum. `gdsmc conformance` must report collision.momentum FAIL.
#include <gdsmc/gdsmc.hpp>

namespace {
struct LeakyRule {
  static constexpr const char* name = "conformance_leaky";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that does not conserve momentum";
  static constexpr const char* documentation = "v1' = v1 - dv, v2' = v2 + 0.9 dv: momentum leaks (deliberately).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit LeakyRule(const gdsmc::Params&) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = gs * s;  // elastic impulse
    v1 -= dv;
    v2 += 0.9 * dv;  // the leak
    return 0.0;
  }
};
}  // namespace

GDSMC_PLUGIN(LeakyRule)
