// Rough inelastic hard spheres: normal restitution alpha, tangential restitution beta, and an
// angular velocity per particle that the rule declares as an extra attribute.
//
// Collision rule (Huthmann & Zippelius, Phys. Rev. E 56, R6275 (1997); Luding, Huthmann,
// McNamara & Zippelius, Phys. Rev. E 58, 3416 (1998)). Spheres of diameter sigma, mass m = 1,
// moment of inertia I = kappa m sigma^2 / 4 (kappa = 2/5 for a uniform sphere). With g = v1 - v2
// and s the unit vector from the centre of 1 to that of 2 (g.s > 0 on approach), the relative
// velocity of the contact points is
//   G = g + (sigma/2) (w1 + w2) x s,       G_n = (G.s) s = (g.s) s,  G_t = G - G_n,
// and the collision reverses and shrinks them: G_n' = -alpha G_n, G_t' = -beta G_t. The impulse
// on particle 1 (particle 2 receives -J) that does this is
//   J = -(1 + alpha)/2 (g.s) s - eta_t G_t,   eta_t = kappa (1 + beta) / (2 (1 + kappa)),
// and v1' = v1 + J, v2' = v2 - J, w1' = w1 + (2 / (kappa sigma)) s x J, w2' = w2 + (2 / (kappa sigma)) s x J.
// beta = -1 is the smooth sphere (no spin change), beta = +1 the perfectly rough one; with
// alpha = beta = 1 the total (translational + rotational) energy is conserved.
//
// sigma is the run's diameter, which the host passes with every pair (PairContext::sigma); the
// angular velocity is stored in reduced units (speed / length).
#include <gdsmc/gdsmc.hpp>

namespace {

struct RoughSpheres {
  static constexpr const char* name = "rough_spheres";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary = "Rough inelastic hard spheres: normal (alpha) and tangential (beta) restitution";
  static constexpr const char* documentation =
      "Rough hard spheres (Huthmann & Zippelius, PRE 56, R6275 (1997); Luding et al., PRE 58,\n"
      "3416 (1998)). Contact-point relative velocity G = g + (sigma/2)(w1 + w2) x s; after the\n"
      "collision G_n' = -alpha G_n and G_t' = -beta G_t, through the impulse\n"
      "  J = -(1+alpha)/2 (g.s) s - eta_t G_t,  eta_t = kappa (1+beta) / (2 (1+kappa)),\n"
      "  v1' = v1 + J, v2' = v2 - J, w_i' = w_i + 2/(kappa sigma) s x J,\n"
      "with the moment of inertia I = kappa m sigma^2 / 4 and sigma the run's diameter (PairContext::sigma). Momentum is conserved; the returned energy\n"
      "change is that of the translational kinetic energy, J.g + J.J (the rotational part is in the\n"
      "attribute). Declares the per-particle attribute 'angular_velocity' (3 components, reduced\n"
      "units: speed / length). Publishes normal_restitution, tangential_restitution and\n"
      "moment_of_inertia_factor (kappa) for the rotational_temperature diagnostic.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution").range(0.0, 1.0).default_value(0.9),
            gdsmc::ParamSpec::real("beta", "coefficient of tangential restitution (-1 smooth, +1 perfectly rough)")
                .range(-1.0, 1.0)
                .default_value(0.0),
            gdsmc::ParamSpec::real("kappa", "moment of inertia I = kappa m sigma^2 / 4 (2/5: uniform sphere)")
                .range(0.0, 2.0 / 3.0)
                .default_value(0.4)};
  }
  explicit RoughSpheres(const gdsmc::Params& p)
      : alpha(p.real("alpha")), beta(p.real("beta")), kappa(p.real("kappa")) {
    if (kappa <= 0) throw gdsmc::ParameterError("kappa", "kappa must be > 0 (a sphere with no moment of inertia)");
    eta_t = kappa * (1.0 + beta) / (2.0 * (1.0 + kappa));
    spin_factor = 2.0 / kappa;  // 2 / (kappa sigma) times sigma: divided by pair.sigma in collide()
  }

  std::vector<gdsmc::AttributeSpec> attributes() const {
    return {{"angular_velocity", 3, "sqrt(T_u/m)/length (reduced)", "angular velocity w of each sphere"}};
  }
  void publish(gdsmc::QuantityBoard& board) const {
    board.publish("normal_restitution", alpha);
    board.publish("tangential_restitution", beta);
    board.publish("moment_of_inertia_factor", kappa);
  }
  // Called once before the first step (storage never moves): look the attribute up here. collide()
  // runs concurrently for different cells and only reads these members.
  void bind(const gdsmc::ParticleSpan& p) {
    omega = p.attribute("angular_velocity");
    count = p.count;
  }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    double* wx = omega;
    double* wy = omega + count;
    double* wz = omega + 2 * count;
    const std::uint32_t i = pair.i, j = pair.j;
    const gdsmc::Vec3 w1{wx[i], wy[i], wz[i]}, w2{wx[j], wy[j], wz[j]};
    const gdsmc::Vec3 g = v1 - v2;
    const double gn = dot(g, s);
    const gdsmc::Vec3 G = g + (0.5 * pair.sigma) * cross(w1 + w2, s);
    const gdsmc::Vec3 Gt = G - dot(G, s) * s;
    const gdsmc::Vec3 J = (-0.5 * (1.0 + alpha) * gn) * s - eta_t * Gt;
    v1 += J;
    v2 -= J;
    const gdsmc::Vec3 dw = (spin_factor / pair.sigma) * cross(s, J);  // 2/(kappa sigma) s x J
    wx[i] = w1.x + dw.x; wy[i] = w1.y + dw.y; wz[i] = w1.z + dw.z;
    wx[j] = w2.x + dw.x; wy[j] = w2.y + dw.y; wz[j] = w2.z + dw.z;
    return dot(J, g) + dot(J, J);  // change of translational kinetic energy (m = 1)
  }

  double alpha, beta, kappa, eta_t = 0, spin_factor = 0;
  double* omega = nullptr;
  std::size_t count = 0;
};

}  // namespace

GDSMC_PLUGIN(RoughSpheres)
