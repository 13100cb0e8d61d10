// Deliberately broken (conformance test): a specular wall that leaks. One hit in 50 leaves the
// particle beyond its plane (position.y outside the box), one in 70 returns it still moving
// outward. `gdsmc conformance` must report boundary.containment FAIL.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {
class LeakyWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "conformance_leaky_wall";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a specular wall that sometimes lets particles out";
  static constexpr const char* documentation =
      "Reflects specularly, except that hits whose stream draws below 1/50 are put 0.1 beyond the plane and hits "
      "drawing below 1/35 (and not the former) keep their outward velocity.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit LeakyWall(const gdsmc::Params&) {}
  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng& rng) const override {
    const double u = rng.uniform();
    if (u < 1.0 / 50) {
      gdsmc::specular_reflection(hit);
      hit.position.y = hit.side * (0.5 * ctx.system->box[1] + 0.1);  // outside the box
    } else if (u >= 1.0 / 35) {
      gdsmc::specular_reflection(hit);
    }  // else: v_y left pointing outward
    return gdsmc::HitResult::reflected;
  }
};
}  // namespace

GDSMC_PLUGIN(LeakyWall)
