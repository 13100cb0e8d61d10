// Deliberately broken (conformance test): a diffuse wall that claims the temperature T_w (its
// `temperature` parameter) but re-emits at 1.5 T_w. `gdsmc conformance` must report
// boundary.wall_flux FAIL.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {
class HotWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "conformance_hot_wall";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a diffuse wall that emits hotter than its temperature parameter";
  static constexpr const char* documentation =
      "Fully diffuse re-emission (gdsmc::diffuse_emission) at 1.5 times the declared wall temperature.";
  static std::vector<gdsmc::ParamSpec> parameters() { return gdsmc::ThermalWall::parameters(); }
  explicit HotWall(const gdsmc::Params& p) : wall_(p) {}
  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    hit.velocity = gdsmc::diffuse_emission(hit.side, 1.5 * wall_.temperature, wall_.velocity, ctx.system->mass, rng);
    return gdsmc::HitResult::reflected;
  }

 private:
  gdsmc::ThermalWall wall_;
};
}  // namespace

GDSMC_PLUGIN(HotWall)
