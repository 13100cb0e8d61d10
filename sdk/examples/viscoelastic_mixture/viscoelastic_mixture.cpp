// Viscoelastic spheres of several species: a coefficient of normal restitution that depends on the
// pair of species and on the impact speed.
//
// For viscoelastic spheres (Hertz contact plus dissipation proportional to the deformation rate)
// the restitution coefficient of a pair falls with the normal impact speed g_n as
//   epsilon(g_n) = 1 - C1 A alpha^(2/5) g_n^(1/5) + ...,  alpha = (3/2) Y sqrt(R_eff) / (m_eff (1 - nu^2)),
// C1 = 1.15344, with the pair's effective radius R_eff = R_a R_b / (R_a + R_b) and effective mass
// m_eff = m_a m_b / (m_a + m_b) (Schwager & Poschel, Phys. Rev. E 57, 650 (1998); Ramirez,
// Poschel, Brilliantov & Schwager, Phys. Rev. E 60, 4465 (1999)). Particles of one material (the
// same Y, nu and dissipative constant A) but of different sizes and masses thus dissipate
// differently in each pair of species: with delta the first-order dissipation parameter of two
// reference particles (unit mass, diameter sigma), the pair (a, b) has
//   delta_ab = delta (alpha_ab / alpha_ref)^(2/5) = delta (R_ab / R_ref)^(1/5) (m_ref / m_ab)^(2/5),
// R_ref = sigma / 4, m_ref = m / 2: light, small particles dissipate more than heavy, large ones.
// As the one-species example viscoelastic_restitution, the law is kept to first order and clipped:
//   epsilon_ab(g_n) = max(epsilon_min, 1 - C1 delta_ab (g_n / v_ref)^(1/5)).
// The collision itself is the binary collision of a granular mixture (Garzo & Dufty, Phys. Rev. E
// 60, 5706 (1999), Eq. 2): v1' = v1 - m_b/(m_a+m_b) (1+eps)(g.s) s, v2' = v2 + m_a/(m_a+m_b) (1+eps)(g.s) s.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>

namespace {

struct ViscoelasticMixture {
  static constexpr const char* name = "viscoelastic_mixture";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Viscoelastic spheres of several species: restitution epsilon_ab(g_n) per pair of species";
  static constexpr const char* documentation =
      "Smooth viscoelastic spheres of one material, several species (system.species: masses m_a,\n"
      "diameters sigma_a). The pair (a, b) has the restitution coefficient, to first order in the\n"
      "dissipation (Schwager & Poschel, PRE 57, 650 (1998); Ramirez et al., PRE 60, 4465 (1999)),\n"
      "  epsilon_ab(g_n) = max(epsilon_min, 1 - C1 delta_ab (g_n / v_ref)^(1/5)),  C1 = 1.15344,\n"
      "  delta_ab = delta (R_ab / R_ref)^(1/5) (m_ref / m_ab)^(2/5),\n"
      "R_ab = sigma_a sigma_b / (2 (sigma_a + sigma_b)), m_ab = m_a m_b / (m_a + m_b), R_ref = sigma/4,\n"
      "m_ref = m/2 (delta is that of two particles of unit mass and diameter sigma). Collision (Garzo &\n"
      "Dufty, PRE 60, 5706 (1999), Eq. 2): v1' = v1 - m_b/(m_a+m_b)(1+eps) g_n s, v2' = v2 +\n"
      "m_a/(m_a+m_b)(1+eps) g_n s, conserving m_a v1 + m_b v2 and changing the kinetic energy by\n"
      "-m_ab/2 (1 - eps^2) g_n^2 (returned). Kernel: hard spheres at the contact distance sigma_ab.\n"
      "A one-species run is the viscoelastic gas of delta with unit masses. Publishes\n"
      "'viscoelastic_delta' = delta and, in a mixture, 'viscoelastic_delta[a,b]' for a <= b.";

  static constexpr double C1 = 1.15344;
  static constexpr bool species_aware = true;  // SDK 6.5: collide() weighs the pair by its species

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("delta", "dissipation parameter of two reference particles (mass m, diameter sigma) at v_ref")
                .range(0.0, 0.5)
                .default_value(0.1),
            gdsmc::ParamSpec::real("reference_speed", "reference impact speed v_ref")
                .above(0.0)
                .unit(gdsmc::Dimension::velocity)
                .default_value(1.0),
            gdsmc::ParamSpec::real("epsilon_min", "lower bound of the restitution coefficient").range(0.0, 1.0).default_value(0.0)};
  }
  explicit ViscoelasticMixture(const gdsmc::Params& p)
      : delta(p.real("delta")), v_ref(p.real("reference_speed")), epsilon_min(p.real("epsilon_min")) {}

  void publish(gdsmc::QuantityBoard& board) const { board.publish("viscoelastic_delta", delta); }

  // What collide() needs of the ordered pair (a, b), computed once in begin(): a table lookup per
  // pair, no SystemInfo access in the hot loop.
  struct Pair {
    double share1, share2;  // m_b/(m_a+m_b), m_a/(m_a+m_b): the shares of the momentum transfer
    double reduced_mass;    // m_ab
    double c1_delta;        // C1 delta_ab / v_ref^(1/5)
  };

  void begin(const gdsmc::SystemInfo& system, gdsmc::QuantityBoard& board) {
    count = system.species_count;
    pairs.assign(count * count, {});
    const double r_ref = 0.25 * system.sigma, m_ref = 0.5 * system.mass;
    for (std::size_t a = 0; a < count; ++a)
      for (std::size_t b = 0; b < count; ++b) {
        const double ma = system.species_mass(a), mb = system.species_mass(b);
        const double sa = system.species_diameter(a), sb = system.species_diameter(b);
        const double r_ab = sa * sb / (2.0 * (sa + sb)), m_ab = ma * mb / (ma + mb);
        const double delta_ab = delta * std::pow(r_ab / r_ref, 0.2) * std::pow(m_ref / m_ab, 0.4);
        pairs[a * count + b] = {mb / (ma + mb), ma / (ma + mb), m_ab, C1 * delta_ab / std::pow(v_ref, 0.2)};
        if (system.species && a <= b)
          board.publish("viscoelastic_delta[" + std::to_string(a) + "," + std::to_string(b) + "]", delta_ab);
      }
  }

  double restitution(const Pair& p, double gn) const {
    if (gn <= 0) return 1.0;  // no approach, no dissipation
    return std::max(epsilon_min, 1.0 - p.c1_delta * std::pow(gn, 0.2));
  }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    const Pair& p = pairs[pair.particles.species_of(pair.i) * count + pair.particles.species_of(pair.j)];
    const double gn = dot(v1 - v2, s);
    const double eps = restitution(p, gn);
    v1 -= (p.share1 * (1.0 + eps) * gn) * s;
    v2 += (p.share2 * (1.0 + eps) * gn) * s;
    return -0.5 * p.reduced_mass * (1.0 - eps * eps) * gn * gn;
  }

  double delta, v_ref, epsilon_min;
  std::size_t count = 1;
  std::vector<Pair> pairs;
};

}  // namespace

GDSMC_PLUGIN(ViscoelasticMixture)
