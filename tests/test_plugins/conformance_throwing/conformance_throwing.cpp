// Deliberately broken (conformance test): the factory throws whatever the parameters.
// `gdsmc conformance` must report defaults_construct FAIL (and not crash).
#include <stdexcept>

#include <gdsmc/gdsmc.hpp>

namespace {
struct ThrowingRule {
  static constexpr const char* name = "conformance_throwing";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule whose factory throws";
  static constexpr const char* documentation = "Its constructor always throws std::runtime_error.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "unused").range(0.0, 1.0).default_value(0.5)};
  }
  explicit ThrowingRule(const gdsmc::Params&) { throw std::runtime_error("conformance_throwing: the factory always fails"); }
  double collide(gdsmc::Vec3&, gdsmc::Vec3&, const gdsmc::Vec3&, gdsmc::PairContext&) const { return 0.0; }
};
}  // namespace

GDSMC_PLUGIN(ThrowingRule)
