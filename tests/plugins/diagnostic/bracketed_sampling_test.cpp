// Bracketed sampling (SDK 6.1): diagnostics that offer it sample the state before and after the
// collision stage, so that a stress the flow builds and the collisions relax is measured in the
// middle of its sawtooth, not at its low end.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace t = gdsmc::test;
using namespace gdsmc;

namespace {

// Elastic hard spheres in uniform shear at fixed temperature (energy_momentum_thermostat after the
// collisions), homogeneous, dt = 0.08 tau0.
std::string thermostatted_usf(const std::string& sampling) {
  return "run:\n  seed: 29\n  particles: 20000\n  time_step: {value: 0.08, unit: tau0}\n  stop: {time: 60}\n"
         "  sample_every: 1\n  record_every: 25\n  average_after: {time: 10}\n  sampling: " + sampling + "\n"
         "system: {density: 1.0e-3, temperature: 1.0, domain: homogeneous}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 1.0}\n"
         "forcings:\n  - {plugin: uniform_shear, shear_rate: 0.2}\n  - energy_momentum_thermostat\n"
         "diagnostics:\n  - shear_rheology\n  - collision_count\n"
         "output: {file: unused.h5}\n";
}

std::string sampling_attribute(const host::Engine& e, const std::string& group) {
  for (const auto& a : t::diagnostic(e, group).attributes)
    if (a.first == "sampling") return a.second;
  return "";
}

}  // namespace

// The same run (same seed: sampling never changes the dynamics) sampled after each step and on both
// sides of the collisions. Between the two samples of a step only the collisions act on -P_xy/nT
// (the thermostat rescales P_xy and T alike), relaxing it by the fraction f = 1 - exp(-nu dt), nu
// = p/eta of the first Sonine approximation = 1/((5 sqrt(pi)/8) tau0) at T = T0 (Grad's moment
// equation for P_xy; 000 Eq. 2.18 without the factor 1.016). So the bracketed mean exceeds the
// after-step mean by the fraction f/(2 - f) = 0.0361 at dt = 0.08 tau0. The tolerance, 8 % of
// that, covers the distribution's departure from Grad's (a* = 0.22 here) and the noise of the
// difference (0.7 %, the collisions' increments over 625 steps); a bracket that did nothing (0) or
// sampled one side twice (0 or 2 f/(2 - f)) is far outside.
TEST(Sampling, BracketedMeanSitsInTheMiddleOfTheCollisionSawtooth) {
  t::TempDir dir;
  double stress[2];
  std::vector<double> collisions[2];
  const std::string sampling[2] = {"after_step", "bracketed"};
  for (int k = 0; k < 2; ++k) {
    host::Pipeline p = t::load_yaml(dir, thermostatted_usf(sampling[k]));
    host::Engine e(p);
    e.run();
    stress[k] = t::scalar(e, "shear_rheology", "minus_Pxy_over_nT_mean");
    EXPECT_EQ(sampling_attribute(e, "shear_rheology").rfind(sampling[k], 0), 0u) << sampling_attribute(e, "shear_rheology");
    // collision_count reads event totals and does not offer the extension.
    EXPECT_EQ(sampling_attribute(e, "collision_count").rfind("after_step", 0), 0u);
    collisions[k] = t::series(e, "collision_count", "collisions");
  }
  EXPECT_EQ(collisions[0], collisions[1]) << "the sampling rule changed the dynamics";
  const double nu_dt = 0.08 / (5.0 * std::sqrt(M_PI) / 8.0);
  const double f = 1.0 - std::exp(-nu_dt);
  const double expected = f / (2.0 - f);
  const double measured = (stress[1] - stress[0]) / stress[1];
  EXPECT_NEAR(measured, expected, 0.08 * expected) << "after_step " << stress[0] << ", bracketed " << stress[1];
}

// The HCS has the collisions as its only process: it is sampled after the step alone, whatever
// the diagnostics offer, so its T(t) stays exact at t + dt.
TEST(Sampling, HomogeneousCoolingIsSampledAfterTheStepOnly) {
  t::TempDir dir;
  host::Pipeline p = t::load_yaml(dir, t::kSmallHcsPipeline);
  host::Engine e(p);
  e.run();
  for (const auto& d : e.diagnostics())
    EXPECT_EQ(sampling_attribute(e, d.group()).rfind("after_step", 0), 0u) << d.group();
}

TEST(Sampling, AnUnknownSamplingRuleIsRefusedWithTheValidOnes) {
  t::TempDir dir;
  const std::string yaml = t::replace_once(thermostatted_usf("bracketed"), "sampling: bracketed", "sampling: midpoint");
  try {
    t::load_yaml(dir, yaml);
    FAIL() << "run.sampling: midpoint was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_TRUE(t::contains(what, "run.sampling")) << what;
    EXPECT_TRUE(t::contains(what, "pipeline.yaml:")) << what;
    EXPECT_TRUE(t::contains(what, "bracketed") && t::contains(what, "after_step")) << what;
  }
}

// A new capability is a minor version (SDK 6.1 added this one): a diagnostic built against SDK 6.0
// (its entry claims ABI 6.0, it offers no extension) loads in this host and is sampled as 6.0 did,
// once per sampled step, after the step, beside a 6.1 diagnostic that is bracketed.
TEST(Sampling, ADiagnosticBuiltAgainstSdk60LoadsAndIsSampledOnceAStepAfterIt) {
  t::TempDir dir;
  std::string yaml = t::replace_once(thermostatted_usf("bracketed"), "  - collision_count\n",
                                     "  - collision_count\n  - sdk60_diagnostic\n");
  yaml = t::replace_once(yaml, "stop: {time: 60}", "stop: {time: 8}");
  const auto file = dir.write("pipeline.yaml", yaml);
  const t::ProcessResult r = t::run_gdsmc(
      {"run", file.string(), "--quiet", "--plugin-path", t::test_plugin("sdk60_diagnostic").string(), "-o", "out.h5"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  t::h5::File out(dir / "out.h5");
  EXPECT_EQ(t::h5::read_string_attribute(out.id(), "/diagnostics/sdk60_diagnostic", "sampling").rfind("after_step", 0), 0u);
  EXPECT_EQ(t::h5::read_string_attribute(out.id(), "/diagnostics/shear_rheology", "sampling").rfind("bracketed", 0), 0u);
  const std::vector<double> samples = t::h5::read_doubles(out.id(), "/diagnostics/sdk60_diagnostic/samples");
  const std::vector<double> steps = t::h5::read_doubles(out.id(), "/diagnostics/sdk60_diagnostic/steps");
  const std::vector<double> phase = t::h5::read_doubles(out.id(), "/diagnostics/sdk60_diagnostic/max_phase");
  ASSERT_GE(samples.size(), 4u);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    EXPECT_EQ(samples[k], steps[k]) << "record " << k << ": sampled more than once in a step";
    EXPECT_EQ(phase[k], 0.0) << "record " << k << ": sampled in a phase other than after_step";
  }
  EXPECT_EQ(samples[1], 25.0);  // record_every 25 steps, a sample every step
}
