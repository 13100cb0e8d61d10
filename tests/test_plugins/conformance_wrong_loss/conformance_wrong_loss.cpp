// Deliberately broken (conformance test): inelastic hard spheres with restitution e that declare
// the energy change with (1 - e) instead of (1 - e^2). The two agree at e = 0 and e = 1 (the
// default and the bounds), so only a check at an interior or random value of e sees it:
// `gdsmc conformance` must report parameter_interior FAIL (collision.energy passes at e = 1).
#include <gdsmc/gdsmc.hpp>

namespace {
struct WrongLossRule {
  static constexpr const char* name = "conformance_wrong_loss";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: inelastic hard spheres declaring the loss with (1 - e)";
  static constexpr const char* documentation =
      "v1' = v1 - (1+e)/2 (g.s) s, v2' = v2 + (1+e)/2 (g.s) s; declares -(1-e)/4 (g.s)^2 instead of "
      "-(1-e^2)/4 (g.s)^2 (deliberately).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("restitution", "coefficient of normal restitution e").range(0, 1).default_value(1.0)};
  }
  explicit WrongLossRule(const gdsmc::Params& p) : e(p.real("restitution")) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = (0.5 * (1 + e) * gs) * s;
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1 - e) * gs * gs;  // the bug: (1 - e), not (1 - e^2)
  }
  double e;
};
}  // namespace

GDSMC_PLUGIN(WrongLossRule)
