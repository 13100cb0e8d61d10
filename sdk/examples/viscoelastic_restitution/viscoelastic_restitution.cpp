// Viscoelastic spheres: a coefficient of normal restitution that depends on the impact speed.
//
// For viscoelastic spheres (Hertz contact plus dissipation proportional to the deformation rate)
// the restitution coefficient falls with the normal impact speed g_n as
//   epsilon(g_n) = 1 - C1 delta (g_n / v_ref)^(1/5) + C2 delta^2 (g_n / v_ref)^(2/5) - ...
// with C1 = 1.15344 and C2 = 0.79826 (Schwager & Poschel, Phys. Rev. E 57, 650 (1998);
// Ramirez, Poschel, Brilliantov & Schwager, Phys. Rev. E 60, 4465 (1999); Brilliantov & Poschel,
// "Kinetic Theory of Granular Gases", Oxford 2004). This plugin keeps the first order, which is
// the leading dissipation of a weakly dissipative gas, and clips the law at epsilon_min so that
// very fast impacts never give a negative restitution:
//   epsilon(g_n) = max(epsilon_min, 1 - C1 delta (g_n / v_ref)^(1/5)).
// delta (dimensionless) is the dissipation parameter at the reference speed v_ref, by default the
// thermal speed sqrt(2 T0 / m) of the initial state.
#include <algorithm>
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {

struct ViscoelasticRestitution {
  static constexpr const char* name = "viscoelastic_restitution";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Hard spheres with the viscoelastic restitution epsilon(g_n) of Brilliantov & Poschel";
  static constexpr const char* documentation =
      "Smooth hard spheres whose coefficient of normal restitution depends on the normal impact\n"
      "speed g_n = g.s (g = v1 - v2, s the impact direction), to first order in the dissipation\n"
      "parameter delta (Schwager & Poschel, PRE 57, 650 (1998); Brilliantov & Poschel, Kinetic\n"
      "Theory of Granular Gases, 2004):\n"
      "  epsilon(g_n) = max(epsilon_min, 1 - C1 delta (g_n / v_ref)^(1/5)),  C1 = 1.15344.\n"
      "Collision: v1' = v1 - (1 + epsilon)/2 g_n s, v2' = v2 + (1 + epsilon)/2 g_n s, which conserves\n"
      "momentum and changes the kinetic energy by -(1 - epsilon^2) g_n^2 / 4 (returned). Kernel: hard\n"
      "spheres, sigma^2 Theta(g_n) g_n. Slow collisions are nearly elastic, so a freely cooling gas\n"
      "cools more slowly than Haff's law (T ~ t^(-5/3) at late times instead of t^(-2)).\n"
      "Publishes 'viscoelastic_delta'.";

  static constexpr double C1 = 1.15344;

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("delta", "dissipation parameter delta at the reference speed").range(0.0, 0.5).default_value(0.1),
            gdsmc::ParamSpec::real("reference_speed", "reference impact speed v_ref")
                .above(0.0)
                .unit(gdsmc::Dimension::velocity)
                .default_value(1.0),
            gdsmc::ParamSpec::real("epsilon_min", "lower bound of the restitution coefficient").range(0.0, 1.0).default_value(0.0)};
  }
  explicit ViscoelasticRestitution(const gdsmc::Params& p)
      : delta(p.real("delta")), v_ref(p.real("reference_speed")), epsilon_min(p.real("epsilon_min")) {}

  void publish(gdsmc::QuantityBoard& board) const { board.publish("viscoelastic_delta", delta); }

  double restitution(double gn) const {
    if (gn <= 0) return 1.0;  // no approach, no dissipation
    return std::max(epsilon_min, 1.0 - C1 * delta * std::pow(gn / v_ref, 0.2));
  }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gn = dot(v1 - v2, s);
    const double eps = restitution(gn);
    const gdsmc::Vec3 dv = (0.5 * (1.0 + eps) * gn) * s;
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1.0 - eps * eps) * gn * gn;
  }

  double delta, v_ref, epsilon_min;
};

}  // namespace

GDSMC_PLUGIN(ViscoelasticRestitution)
