// Deliberately broken (conformance test): a species-aware rule that collides a mixture's pair with
// the right masses (momentum m_a v1 + m_b v2 conserved) but declares the energy loss of unit
// masses, (1 - e^2)/4 (g.s)^2, instead of m_a m_b/(2(m_a+m_b)) (1 - e^2)(g.s)^2. Right in a
// one-species gas; `gdsmc conformance` must report collision.species FAIL (energy).
#include <vector>

#include <gdsmc/gdsmc.hpp>

namespace {
struct UnweightedEnergyRule {
  static constexpr const char* name = "conformance_unweighted_energy";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a mixture rule declaring the energy loss of unit masses";
  static constexpr const char* documentation =
      "v1' = v1 - m_b/(m_a+m_b)(1+e)(g.s) s, v2' = v2 + m_a/(m_a+m_b)(1+e)(g.s) s; declares -(1-e^2)/4 (g.s)^2\n"
      "(deliberately: the loss of two unit masses).";
  static constexpr bool species_aware = true;
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("restitution", "coefficient of normal restitution e").range(0, 1).default_value(0.8)};
  }
  explicit UnweightedEnergyRule(const gdsmc::Params& p) : e(p.real("restitution")) {}
  void begin(const gdsmc::SystemInfo& system, gdsmc::QuantityBoard&) {
    mass.assign(system.species_count, 1.0);
    for (std::size_t k = 0; k < system.species_count; ++k) mass[k] = system.species_mass(k);
  }
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    const double ma = mass[pair.particles.species_of(pair.i)], mb = mass[pair.particles.species_of(pair.j)];
    const double gs = dot(v1 - v2, s);
    v1 -= (mb / (ma + mb) * (1 + e) * gs) * s;
    v2 += (ma / (ma + mb) * (1 + e) * gs) * s;
    return -0.25 * (1 - e * e) * gs * gs;  // the bug: the reduced mass taken as 1/2
  }
  double e;
  std::vector<double> mass;
};
}  // namespace

GDSMC_PLUGIN(UnweightedEnergyRule)
