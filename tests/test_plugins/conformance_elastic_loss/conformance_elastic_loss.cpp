// Deliberately broken (conformance test): impacts with a normal speed |g.s| below `elastic_below`
// are elastic, faster ones have restitution `alpha`; the rule declares the inelastic loss
// -(1-alpha^2)/4 (g.s)^2 for every impact, the elastic ones included. At the defaults
// (alpha = 1, elastic_below = 0) and with one parameter at a bound and the other at its default
// the declared change is right; only with alpha < 1 and elastic_below > 0 together (a random
// point of the parameter ranges) is it wrong: `gdsmc conformance` must report parameter_interior
// FAIL.
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {
struct ElasticLossRule {
  static constexpr const char* name = "conformance_elastic_loss";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: declares the inelastic loss for elastic impacts too";
  static constexpr const char* documentation =
      "e = 1 for |g.s| < elastic_below, else alpha; declares -(1-alpha^2)/4 (g.s)^2 always (deliberately).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "restitution of impacts faster than elastic_below").range(0, 1).default_value(1.0),
            gdsmc::ParamSpec::real("elastic_below", "normal impact speed (reduced units) below which impacts are elastic")
                .range(0, 4)
                .default_value(0.0)};
  }
  explicit ElasticLossRule(const gdsmc::Params& p) : alpha(p.real("alpha")), v_el(p.real("elastic_below")) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const double e = std::fabs(gs) < v_el ? 1.0 : alpha;
    const gdsmc::Vec3 dv = (0.5 * (1 + e) * gs) * s;
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1 - alpha * alpha) * gs * gs;  // the bug: alpha, not e
  }
  double alpha, v_el;
};
}  // namespace

GDSMC_PLUGIN(ElasticLossRule)
