// Fully diffuse thermal wall (004 Eqs. 6-9).
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class DiffuseWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "diffuse_wall";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Fully diffuse thermal wall (004 Eqs. 6-9): re-emission from the half-Maxwellian at T_w about the wall velocity";
  static constexpr const char* documentation =
      "Fully diffuse thermal wall of paper 004 (Sec. III A, Eqs. 6-9). At the exact crossing time the\n"
      "particle stays on the plane and forgets its velocity: it is re-emitted with\n"
      "  v_x = u_x + sqrt(T_w/m) G,  v_z = u_z + sqrt(T_w/m) G   (Eqs. 6, 8; G standard normal),\n"
      "  |v_y| from p(v) = (m v / T_w) exp(-m v^2 / 2 T_w)      (Eqs. 7, 9; Rayleigh, the flux distribution),\n"
      "v_y pointing into the gas. |v_y| = sqrt(-2 (T_w/m) ln U) with U uniform on (0, 1], never 0. The\n"
      "host then streams the remaining flight time of the step under the body acceleration, which is\n"
      "the a t_post of Eq. 6 and Eqs. 10-12. The physics is gdsmc::ThermalWall / diffuse_emission in\n"
      "gdsmc/physics/walls.hpp. For a partially diffuse wall (accommodation coefficient between specular and\n"
      "diffuse, 004 Sec. VI) use maxwell_wall; accommodation 1 there reproduces this wall bit for bit.\n"
      "Parameters: temperature T_w > 0 (bare numbers: T_w / T0; default 1), velocity_x and velocity_z\n"
      "the wall's velocity u in its plane (any real; bare numbers in units of sqrt(2 T0/m); default 0:\n"
      "e.g. +-U/2 on y_max / y_min for Couette flow). Conserves mass only: the wall exchanges energy\n"
      "(heat) and tangential momentum (shear stress) with the gas, which the host tallies per side; a\n"
      "gas at rest relative to the wall at temperature T_w is in detailed balance with it.";

  static std::vector<gdsmc::ParamSpec> parameters() { return gdsmc::ThermalWall::parameters(); }
  explicit DiffuseWall(const gdsmc::Params& p) : wall_(p) {}

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    wall_.reemit(hit, ctx.system->mass, rng);
    return gdsmc::HitResult::reflected;
  }

 private:
  gdsmc::ThermalWall wall_;
};

}  // namespace

GDSMC_PLUGIN(DiffuseWall)
