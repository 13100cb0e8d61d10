// Deliberately broken (conformance test): declares that it runs in mixtures (species_aware) but
// collides every pair as if both particles had unit mass, v1' = v1 - (1+e)/2 (g.s) s. It passes
// every one-species check; in a mixture of unequal masses it does not conserve m_a v1 + m_b v2:
// `gdsmc conformance` must report collision.species FAIL (momentum).
#include <gdsmc/gdsmc.hpp>

namespace {
struct MasslessMixtureRule {
  static constexpr const char* name = "conformance_massless_mixture";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a species-aware rule that ignores the species' masses";
  static constexpr const char* documentation =
      "v1' = v1 - (1+e)/2 (g.s) s, v2' = v2 + (1+e)/2 (g.s) s whatever the species (deliberately): in a mixture\n"
      "the total momentum m_a v1 + m_b v2 changes.";
  static constexpr bool species_aware = true;
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("restitution", "coefficient of normal restitution e").range(0, 1).default_value(0.8)};
  }
  explicit MasslessMixtureRule(const gdsmc::Params& p) : e(p.real("restitution")) {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = (0.5 * (1 + e) * gs) * s;  // the bug: m_b/(m_a+m_b) taken as 1/2
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1 - e * e) * gs * gs;
  }
  double e;
};
}  // namespace

GDSMC_PLUGIN(MasslessMixtureRule)
