// Values of the system and the run that no step can use: hostile system values and time steps are
// refused before anything runs, naming the derived quantity that is unusable; numbers out of range
// say what is wrong; large steps and unreachable average windows are warned about.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// Each of these validated and then hung in the first step (ignoring SIGINT and SIGTERM), looped
// forever or failed with a misleading message. Now: exit 1 at load time, the value's key and
// location, the derived quantity and its value, nothing written.
TEST(SystemValues, HostileSystemValuesAndTimeStepsAreRefusedNamingTheDerivedQuantity) {
  struct Case {
    std::string set;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"system.sigma=1e308", {"system.sigma", "sigma^2 is infinite"}},
      {"system.sigma=1e-300", {"system.sigma", "sigma^2 is 0"}},
      {"system.density=1e308", {"system.density", "the mean free path lambda0", "is 0"}},
      {"system.density=1e-306", {"system.density", "the volume N/n is infinite"}},
      {"system.density=1e-308", {"system.density", "'1e-308' is too small to represent"}},
      {"system.temperature=1e308", {"system.temperature", "the thermal speed sqrt(2 T0/m) is infinite"}},
      {"system.temperature=1e-300", {"system.temperature", "105 N T0^3"}},
      {"run.time_step.value=5e-324", {"run.time_step.value", "'5e-324' is too small to represent"}},
      {"run.time_step.value=1e308", {"run.time_step.value", "mean free times"}},
      {"run.time_step.value=5", {"run.time_step.value", "5.64 mean free times"}},
      {"run.time_step.value=1e-300", {"run.time_step.value", "steps, more than 1e+12"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.set);
    const Outcome o = gdsmc_in_dir("run", small_pipeline(), {"--set", c.set});
    ASSERT_FALSE(o.result.timed_out) << o.result.describe();
    EXPECT_EQ(o.result.exit_code, 1) << o.result.describe();
    EXPECT_TRUE(contains(o.result.err, "--set " + c.set)) << o.result.describe();
    for (const auto& s : c.says) EXPECT_TRUE(contains(o.result.err, s)) << "expected '" << s << "'\n" << o.result.describe();
    EXPECT_FALSE(contains(o.result.err, "0.000000")) << o.result.describe();
    EXPECT_EQ(o.left, std::vector<std::string>{});
  }
}

// A density derived from a mean free path can be 0 (sigma^2 overflows): refused, where it used to
// pass the checks with no plugin read and crash.
TEST(SystemValues, ADensityDerivedFromTheMeanFreePathMustBeUsableToo) {
  std::string yaml = small_pipeline();
  yaml.replace(yaml.find("  density: 1.0e-3\n"), 18, "  mean_free_path: 1\n  sigma: 1.0e200\n");
  const Outcome o = gdsmc_in_dir("validate", yaml, {});
  EXPECT_EQ(o.result.signal, 0) << o.result.describe();
  EXPECT_EQ(o.result.exit_code, 1) << o.result.describe();
  EXPECT_TRUE(contains(o.result.err, "system.sigma: the number density n is 0")) << o.result.describe();
}

// A shipped uniform-shear-flow pipeline with time_step 5 tau0 validated and never ended (the
// gas collapsed, and the BGK diagnostic then integrated its model over an ever longer time).
TEST(SystemValues, ShippedShearFlowWithAStepOfFiveTau0IsRefused) {
  TempDir dir;
  const auto config = gdsmc::test::source_dir() / "configs" / "usf_ehs_refined_alpha0.5_shear4.yaml";
  const ProcessResult r = run_gdsmc({"run", config.string(), "--set", "run.particles=1000", "--set",
                                     "run.time_step.value=5", "--quiet", "-o", (dir / "out.h5").string()},
                                    dir.path(), 30);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "run.time_step.value: a step of 5 tau0 is 5.64 mean free times")) << r.describe();
  EXPECT_TRUE(contains(r.err, "use at most 0.886")) << r.describe();
  EXPECT_EQ(dir.entries_except({}), std::vector<std::string>{});
}

// 2^63 - 1 is a whole number (it was "expected a whole number"); 1e400 is a number beyond the
// range of a double (it was "expected a number").
TEST(SystemValues, NumbersOutOfRangeSayWhatIsWrong) {
  struct Case {
    std::string set, says;
  };
  const std::vector<Case> cases = {
      {"run.particles=9223372036854775807", "value 9223372036854775807 is out of range for run key 'particles' (the number of simulated particles N); valid: [2, 4000000000]"},
      {"run.particles=9223372036854775808", "'9223372036854775808' is out of range: whole numbers must be between"},
      {"run.seed=1e19", "'1e19' is out of range: whole numbers must be between -9.2e18 and 9.2e18"},
      {"system.sigma=1e400", "'1e400' is out of range: numbers must be at most about 1.8e308"},
      {"system.sigma=1e-400", "'1e-400' is too small to represent (it would read as 0)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.set);
    const Outcome o = gdsmc_in_dir("validate", small_pipeline(), {"--set", c.set});
    EXPECT_EQ(o.result.exit_code, 1) << o.result.describe();
    EXPECT_TRUE(contains(o.result.err, c.says)) << o.result.describe();
    EXPECT_FALSE(contains(o.result.err, "expected a whole number")) << o.result.describe();
  }
}

// Warnings, not refusals: a step of more than half a mean free time; a last step that overshoots
// the stop time 5x; an average window that starts after the stop. The unchanged pipeline warns
// about nothing.
TEST(SystemValues, LargeStepsAndUnreachableAverageWindowsAreWarnedAbout) {
  const Outcome plain = gdsmc_in_dir("validate", small_pipeline(), {});
  EXPECT_EQ(plain.result.exit_code, 0) << plain.result.describe();
  EXPECT_FALSE(contains(plain.result.err, "warning")) << plain.result.describe();

  const Outcome half = gdsmc_in_dir("validate", small_pipeline(), {"--set", "run.time_step.value=0.5"});
  EXPECT_EQ(half.result.exit_code, 0) << half.result.describe();
  EXPECT_TRUE(contains(half.result.err, "warning: --set run.time_step.value=0.5: run.time_step.value: a step of 0.5 tau0 "
                                        "is 0.56 mean free times")) << half.result.describe();

  const Outcome overshoot = gdsmc_in_dir("validate", small_pipeline("", "{time: 0.1}"), {"--set", "run.time_step.value=0.5"});
  EXPECT_EQ(overshoot.result.exit_code, 0) << overshoot.result.describe();
  EXPECT_TRUE(contains(overshoot.result.err, "the run stops at t = 0.5 tau0, 5 times run.stop.time 0.1 tau0"))
      << overshoot.result.describe();

  const Outcome window =
      gdsmc_in_dir("validate", small_pipeline("  average_after: {collisions_per_particle: 10}\n"), {});
  EXPECT_EQ(window.result.exit_code, 0) << window.result.describe();
  EXPECT_TRUE(contains(window.result.err, "run.average_after.collisions_per_particle: the steady window starts at 10, "
                                          "not before run.stop.collisions_per_particle 5")) << window.result.describe();
}

}  // namespace
}  // namespace gdsmc::test
