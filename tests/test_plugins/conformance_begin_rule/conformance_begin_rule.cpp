// Test plugin: inelastic hard spheres whose (1 + alpha) / 2 is computed in begin(), as a rule that
// reads the system or a published quantity would. Before begin() the factor is NaN, so a rule
// called without begin() writes NaN velocities: a conformance sweep that skips begin() fails it.
#include <limits>

#include <gdsmc/gdsmc.hpp>

namespace {

struct BeginRule {
  static constexpr const char* name = "conformance_begin_rule";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that needs begin()";
  static constexpr const char* documentation =
      "Inelastic hard spheres with restitution alpha; the factor (1 + alpha)/2 is set in begin().";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution").range(0, 1).default_value(0.9)};
  }
  explicit BeginRule(const gdsmc::Params& p) : alpha(p.real("alpha")) {}
  void begin(const gdsmc::SystemInfo&, gdsmc::QuantityBoard&) { half_one_plus_alpha = 0.5 * (1.0 + alpha); }
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gn = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = half_one_plus_alpha * gn * s;
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1.0 - alpha * alpha) * gn * gn;
  }
  double alpha;
  double half_one_plus_alpha = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace

GDSMC_PLUGIN(BeginRule)
