// Test plugin: elastic hard spheres until `after` collisions (counted over the process); from then
// on the first particle of every collision gets `value` (nan or inf) in vx, while the declared
// energy change stays 0 (`energy: finite`) or is `value` too (`energy: bad`).
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

#include <gdsmc/gdsmc.hpp>

namespace {

std::atomic<std::int64_t> g_collisions{0};

struct NanRule {
  static constexpr const char* name = "nan_rule";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: a collision rule that writes NaN velocities";
  static constexpr const char* documentation =
      "Elastic hard spheres; from the collision numbered `after` (counted over the process) on, vx of the first "
      "particle becomes `value`; the declared energy change is 0 (energy: finite) or `value` (energy: bad).";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("after", "the collisions before the first bad one").at_least(0).default_value(1000),
            gdsmc::ParamSpec::choice("value", {"nan", "inf"}, "what it writes").default_value("nan"),
            gdsmc::ParamSpec::choice("energy", {"finite", "bad"}, "the energy change it declares").default_value("finite")};
  }
  explicit NanRule(const gdsmc::Params& p)
      : after(p.integer("after")),
        bad(p.string("value") == "nan" ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity()),
        bad_energy(p.string("energy") == "bad") {}
  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const gdsmc::Vec3 dv = dot(v1 - v2, s) * s;
    v1 -= dv;
    v2 += dv;
    if (g_collisions.fetch_add(1, std::memory_order_relaxed) < after) return 0.0;
    v1.x = bad;
    return bad_energy ? bad : 0.0;
  }
  std::int64_t after;
  double bad;
  bool bad_energy;
};

}  // namespace

GDSMC_PLUGIN(NanRule)
