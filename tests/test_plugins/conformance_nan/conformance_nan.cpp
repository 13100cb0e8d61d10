// Deliberately broken (conformance test): divides by g.sigma_hat, so a grazing or zero-relative-
// velocity pair gives NaN or infinite velocities, and the declared energy change is NaN.
// `gdsmc conformance` must report collision.finite FAIL.
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {
struct NanRule {
  static constexpr const char* name = "conformance_nan";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that returns NaN";
  static constexpr const char* documentation = "Elastic velocities, but the declared energy change is NaN.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit NanRule(const gdsmc::Params&) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = gs * s;
    v1 -= dv;
    v2 += dv;
    return std::nan("");  // the bug
  }
};
}  // namespace

GDSMC_PLUGIN(NanRule)
