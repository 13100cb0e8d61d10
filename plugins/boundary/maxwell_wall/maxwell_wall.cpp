// Maxwell's partially diffuse wall (004 Sec. VI): diffuse with probability alpha, else specular.
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class MaxwellWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "maxwell_wall";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Thermal partially diffuse (Maxwell) wall with accommodation coefficient alpha: diffuse with probability alpha, else specular";
  static constexpr const char* documentation =
      "Maxwell's partially diffuse wall (paper 004, Sec. VI: accommodation coefficient alpha in [0, 1],\n"
      "1 fully diffuse, 0 fully specular). At the exact crossing time the particle stays on the plane;\n"
      "with probability alpha it is re-emitted as by the fully diffuse thermal wall (Eqs. 6-9: x and z\n"
      "Gaussian with variance T_w/m about the wall velocity u, |v_y| Rayleigh with\n"
      "p(v) = (m v / T_w) exp(-m v^2 / 2 T_w), never 0), otherwise reflected specularly (v_y -> -v_y);\n"
      "v_y points into the gas either way. The host then streams the remaining flight time of the step\n"
      "under the body acceleration (Eqs. 10-12). The physics is gdsmc::maxwell_reflection in\n"
      "gdsmc/physics/walls.hpp. accommodation = 1 draws exactly as diffuse_wall and 0 exactly as specular_wall\n"
      "(no extra random number is drawn at either end), so both limits reproduce those walls bit for bit.\n"
      "Parameters: accommodation alpha in [0, 1] (required); temperature T_w > 0 (bare numbers: T_w / T0;\n"
      "default 1); velocity_x and velocity_z the wall's velocity u in its plane (any real; bare numbers in\n"
      "units of sqrt(2 T0/m); default 0). Conserves mass; energy and tangential momentum only at\n"
      "alpha = 0: the diffuse part exchanges heat and shear stress with the gas, which the host tallies\n"
      "per side. See diffuse_wall (alpha = 1) and specular_wall (alpha = 0).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    std::vector<gdsmc::ParamSpec> specs{
        gdsmc::ParamSpec::real("accommodation", "accommodation coefficient alpha: probability of diffuse re-emission "
                                                "(0 specular, 1 fully diffuse)")
            .range(0.0, 1.0)};
    for (auto& s : gdsmc::ThermalWall::parameters()) specs.push_back(std::move(s));
    return specs;
  }
  explicit MaxwellWall(const gdsmc::Params& p) : accommodation_(p.real("accommodation")), wall_(p) {}

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    gdsmc::maxwell_reflection(hit, accommodation_, wall_, ctx.system->mass, rng);
    return gdsmc::HitResult::reflected;
  }

 private:
  double accommodation_;
  gdsmc::ThermalWall wall_;
};

}  // namespace

GDSMC_PLUGIN(MaxwellWall)
