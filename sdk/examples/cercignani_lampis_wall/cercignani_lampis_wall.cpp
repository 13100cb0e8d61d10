// The Cercignani-Lampis wall: a gas-surface scattering kernel with separate accommodation of the
// normal and the tangential motion (C. Cercignani & M. Lampis, Transport Theory Stat. Phys. 1,
// 101 (1971)), sampled with the algorithm of R. G. Lord, Phys. Fluids A 3, 706 (1991) and
// Proc. 17th RGD (1991); see also G. A. Bird, "Molecular Gas Dynamics and the Direct Simulation
// of Gas Flows", Oxford 1994, Sec. 5.7).
//
// A wall at temperature T_w moving in its plane with velocity u = (u_x, 0, u_z). A particle that
// hits it with velocity v (normal component v_n = |v_y|, tangential v_t = (v_x, v_z)) leaves with
//   v_t' = u_t + sqrt(1 - a_t) (v_t - u_t) + sqrt(a_t T_w / m) (G_x, G_z)
//   v_n' = | (sqrt(1 - a_n) v_n + sqrt(a_n T_w / m) G_1 ,  sqrt(a_n T_w / m) G_2) |   (a 2-vector's norm)
// with G independent standard normals, v_n' pointing into the gas. a_n is the accommodation
// coefficient of the normal kinetic energy and a_t that of the tangential kinetic energy (the
// tangential momentum accommodation is sigma_t = 1 - sqrt(1 - a_t)):
//   <v_t'> = u_t + sqrt(1 - a_t)(v_t - u_t),  <|v_t' - u_t|^2> = (1 - a_t)|v_t - u_t|^2 + 2 a_t T_w/m,
//   <v_n'^2> = (1 - a_n) v_n^2 + 2 a_n T_w / m.
// The normal law is the CL kernel R(v_n -> v_n') = (2 v_n' / a_n c^2) I0(2 sqrt(1-a_n) v_n v_n' / a_n c^2)
// exp(-(v_n'^2 + (1-a_n) v_n^2) / a_n c^2), c^2 = 2 T_w/m, which Lord's construction samples
// exactly. The kernel obeys reciprocity with the Maxwellian at T_w: a gas at rest relative to the
// wall at T_w is in detailed balance with it. Limits: a_n = a_t = 1 is the fully diffuse wall
// (gdsmc::diffuse_emission), a_n = a_t = 0 specular reflection (bit for bit).
#include <cmath>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/walls.hpp>

namespace {

class CercignaniLampisWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "cercignani_lampis_wall";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Cercignani-Lampis wall: separate accommodation of normal (a_n) and tangential (a_t) energy at T_w";
  static constexpr const char* documentation =
      "Cercignani-Lampis scattering kernel (Transp. Theory Stat. Phys. 1, 101 (1971)), sampled as in\n"
      "Lord, Phys. Fluids A 3, 706 (1991). Wall at temperature T_w moving with u = (u_x, 0, u_z); a\n"
      "particle hitting it with v_n = |v_y| and v_t = (v_x, v_z) leaves at once with\n"
      "  v_t' = u_t + sqrt(1 - a_t)(v_t - u_t) + sqrt(a_t T_w/m) (G_x, G_z)\n"
      "  v_n' = norm of (sqrt(1 - a_n) v_n + sqrt(a_n T_w/m) G_1, sqrt(a_n T_w/m) G_2), into the gas,\n"
      "G standard normals. a_n (normal_accommodation) and a_t (tangential_accommodation) accommodate\n"
      "the normal and tangential kinetic energy: <v_n'^2> = (1-a_n) v_n^2 + 2 a_n T_w/m; the tangential\n"
      "momentum accommodation is 1 - sqrt(1 - a_t). Reciprocity holds with the Maxwellian at T_w: a\n"
      "gas at rest relative to the wall at T_w is in detailed balance with it. a_n = a_t = 1 is the\n"
      "fully diffuse wall (004 Eqs. 6-9; the default), a_n = a_t = 0 specular reflection; between,\n"
      "the re-emitted velocity remembers the incoming one (unlike maxwell_wall, whose particles either\n"
      "forget it entirely or keep it). Parameters: temperature, velocity_x, velocity_z as for\n"
      "diffuse_wall (gdsmc::ThermalWall), normal_accommodation and tangential_accommodation in [0, 1].\n"
      "Conserves mass only: heat and tangential momentum are exchanged with the gas.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    std::vector<gdsmc::ParamSpec> p = gdsmc::ThermalWall::parameters();
    p.push_back(gdsmc::ParamSpec::real("normal_accommodation", "a_n: accommodation of the normal kinetic energy (0 specular, 1 diffuse)")
                    .range(0.0, 1.0)
                    .default_value(1.0));
    p.push_back(gdsmc::ParamSpec::real("tangential_accommodation",
                                       "a_t: accommodation of the tangential kinetic energy (0 specular, 1 diffuse)")
                    .range(0.0, 1.0)
                    .default_value(1.0));
    return p;
  }
  explicit CercignaniLampisWall(const gdsmc::Params& p)
      : wall_(p), a_n_(p.real("normal_accommodation")), a_t_(p.real("tangential_accommodation")) {}

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    const double mass = ctx.system->mass;
    if (a_n_ >= 1.0 && a_t_ >= 1.0) {  // the diffuse limit: exactly the SDK's thermal wall
      wall_.reemit(hit, mass, rng);
      return gdsmc::HitResult::reflected;
    }
    const double thermal = std::sqrt(wall_.temperature / mass);  // sqrt(T_w/m)
    gdsmc::Vec3& v = hit.velocity;
    if (a_t_ > 0.0) {  // a_t = 0 keeps v_x, v_z exactly (specular tangential motion)
      const double keep = std::sqrt(1.0 - a_t_), spread = std::sqrt(a_t_) * thermal;
      v.x = wall_.velocity.x + keep * (v.x - wall_.velocity.x) + spread * rng.normal();
      v.z = wall_.velocity.z + keep * (v.z - wall_.velocity.z) + spread * rng.normal();
    }
    double vn = std::fabs(v.y);
    if (a_n_ > 0.0) {  // a_n = 0 keeps |v_y| exactly
      const double spread = std::sqrt(a_n_) * thermal;
      const double a = std::sqrt(1.0 - a_n_) * vn + spread * rng.normal(), b = spread * rng.normal();
      vn = std::hypot(a, b);
    }
    v.y = gdsmc::inward_normal_velocity(hit.side, vn);
    return gdsmc::HitResult::reflected;
  }

 private:
  gdsmc::ThermalWall wall_;
  double a_n_, a_t_;
};

}  // namespace

GDSMC_PLUGIN(CercignaniLampisWall)
