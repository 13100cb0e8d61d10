// Inelastic hard spheres with a constant coefficient of normal restitution alpha.
#include <gdsmc/gdsmc.hpp>

namespace {

struct InelasticHardSpheres {
  static constexpr const char* name = "inelastic_hard_spheres";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary = "Inelastic hard spheres (IHS) with constant restitution alpha";
  static constexpr const char* documentation =
      "Smooth inelastic hard spheres of diameter sigma and mass m = 1. A collision with impact\n"
      "direction s (g.s > 0, g = v1 - v2) gives (paper 000, Eq. 2.8)\n"
      "  v1' = v1 - (1+alpha)/2 (g.s) s,   v2' = v2 + (1+alpha)/2 (g.s) s,\n"
      "conserving momentum and losing kinetic energy (1 - alpha^2)/4 (g.s)^2. The collision\n"
      "kernel is the hard-sphere one, sigma^2 Theta(g.s)(g.s) (Eq. 2.6). alpha = 1 is the elastic\n"
      "gas. Publishes 'restitution' = alpha for diagnostics and forcings that need it.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution").range(0.0, 1.0).default_value(1.0)};
  }
  explicit InelasticHardSpheres(const gdsmc::Params& p) : alpha(p.real("alpha")), half_one_plus_alpha(0.5 * (1.0 + alpha)) {}

  void publish(gdsmc::QuantityBoard& board) const { board.publish("restitution", alpha); }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = (half_one_plus_alpha * gs) * s;  // Eq. (2.8)
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1.0 - alpha * alpha) * gs * gs;
  }

  double alpha;
  double half_one_plus_alpha;
};

}  // namespace

GDSMC_PLUGIN(InelasticHardSpheres)
