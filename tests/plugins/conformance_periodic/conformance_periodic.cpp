// A correct test boundary (conformance test): periodic in x, y and z over the box
// [0, Lx) x [-Ly/2, Ly/2) x [0, Lz). `gdsmc conformance` must pass boundary.containment.
#include <cmath>

#include <gdsmc/gdsmc.hpp>

namespace {
class Periodic final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "conformance_periodic";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: periodic boundaries on every face";
  static constexpr const char* documentation = "Wraps positions back into the box.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Periodic(const gdsmc::Params&) {}
  void apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, gdsmc::Rng&) override {
    const double* L = ctx.system->box;
    auto wrap = [](double x, double lo, double len) {
      double r = std::fmod(x - lo, len);
      if (r < 0) r += len;
      return lo + r;
    };
    for (std::size_t i = 0; i < p.count; ++i) {
      p.x[i] = wrap(p.x[i], 0.0, L[0]);
      p.y[i] = wrap(p.y[i], -0.5 * L[1], L[1]);
      p.z[i] = wrap(p.z[i], 0.0, L[2]);
    }
  }
};
}  // namespace

GDSMC_PLUGIN(Periodic)
