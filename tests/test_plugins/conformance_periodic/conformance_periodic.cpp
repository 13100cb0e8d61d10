// A correct test boundary (conformance test): periodic in y over [-Ly/2, Ly/2] (x and z are
// periodic in every slab already). A particle that meets one y plane re-enters through the other
// with its velocity unchanged. `gdsmc conformance` must pass boundary.containment.
#include <gdsmc/gdsmc.hpp>

namespace {
class Periodic final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "conformance_periodic";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: periodic boundary in y";
  static constexpr const char* documentation =
      "Transfers every particle that meets y = -+Ly/2 to the opposite plane, velocity unchanged.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Periodic(const gdsmc::Params&) {}
  bool transfers() const override { return true; }
  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng&) const override {
    hit.position.y = -hit.side * 0.5 * ctx.system->box[1];  // the opposite plane
    return gdsmc::HitResult::transferred;
  }
};
}  // namespace

GDSMC_PLUGIN(Periodic)
