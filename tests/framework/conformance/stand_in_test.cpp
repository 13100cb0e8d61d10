// The fillers of a conformance test pipeline: a required slot the plugin under test does not occupy
// gets its kind's stand-in (plugins/kinds.hpp) when the search path has it, else the first plugin
// of that kind with no required parameters, else an error that names the kind.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "conformance/internal.hpp"

namespace {

namespace fs = std::filesystem;
using gdsmc::PluginKind;
using gdsmc::host::PluginRegistry;
using gdsmc::host::conformance::stand_in;

// A registry of the in-tree plugins named, in that order.
PluginRegistry registry_of(const std::vector<std::string>& names) {
  PluginRegistry reg;
  for (const auto& name : names) reg.add(fs::path(GDSMC_TEST_PLUGIN_DIR) / ("gdsmc_" + name + ".so"));
  return reg;
}

TEST(ConformanceStandIn, TheKindsStandInWhenItIsOnTheSearchPath) {
  const PluginRegistry reg = registry_of({"delta_shell", "enskog_hard_spheres", "maxwellian", "inelastic_hard_spheres"});
  EXPECT_EQ(stand_in(reg, PluginKind::initial_state), "maxwellian");
  EXPECT_EQ(stand_in(reg, PluginKind::collision_rule), "{plugin: inelastic_hard_spheres, alpha: 0.8}");
}

TEST(ConformanceStandIn, ElseTheFirstPluginOfTheKindWithoutRequiredParameters) {
  // drag is loaded first but is a forcing: the slots are filled by kind, not by order alone.
  const PluginRegistry reg = registry_of({"drag", "local_equilibrium", "delta_shell", "enskog_hard_spheres"});
  EXPECT_EQ(stand_in(reg, PluginKind::initial_state), "local_equilibrium");
  EXPECT_EQ(stand_in(reg, PluginKind::collision_rule), "enskog_hard_spheres");
}

TEST(ConformanceStandIn, NoPluginOfTheKindIsAnErrorNamingTheKind) {
  const PluginRegistry reg = registry_of({"drag", "maxwellian"});
  EXPECT_EQ(stand_in(reg, PluginKind::initial_state), "maxwellian");
  try {
    (void)stand_in(reg, PluginKind::collision_rule);
    FAIL() << "a registry without a collision rule gave a stand-in";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("no collision rule plugin (kind 'collision')"), std::string::npos) << m;
    EXPECT_NE(m.find("--plugin-path"), std::string::npos) << m;
  }
}

}  // namespace
