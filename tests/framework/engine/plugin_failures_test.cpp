// A plugin that crashes or writes non-finite values explains itself: the host names the plugin, its
// role and pipeline entry, the call, the step and the run, and leaves no file; what the moment
// check says when every velocity was finite where the host checks it.
#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// A sweep of two variants on one thread: `fine` runs first; `bad` swaps in the collision rule
// `rule` (a test plugin) with `params`.
std::string two_variant_sweep(const std::string& rule, const std::string& params, const std::string& diagnostics) {
  return "run:\n  seed: 3\n  particles: 2000\n  time_step: {value: 0.02, unit: tau0}\n"
         "  stop: {collisions_per_particle: 4}\n  threads: 1\n"
         "system: {density: 1.0e-3, temperature: 1.0}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n" +
         diagnostics +
         "sweep:\n  model:\n    fine: {collision.alpha: 0.8}\n"
         "    bad: {collision: {plugin: " + rule + ", " + params + "}}\n"
         "output: {file: out.h5}\n";
}

// A collision rule that crashes mid-run (SIGSEGV by an invalid write, SIGBUS, SIGFPE, abort) used
// to kill gdsmc with no word and leave the hidden temporary file behind. Now the process still
// dies of its signal (exit status 128 + N, a core dump where enabled; a stack overflow too), after one message naming
// the plugin, its role and pipeline entry, the call, the step and the run, and with no file left.
TEST(PluginFailures, ACrashInsideAPluginNamesItItsRoleTheStepAndTheRunAndLeavesNoFile) {
  // STACK: a stack overflow, a SIGSEGV reported from the alternate signal stack.
  const std::tuple<const char*, const char*, int> signals[] = {
      {"SEGV", "SEGV", SIGSEGV}, {"BUS", "BUS", SIGBUS}, {"FPE", "FPE", SIGFPE}, {"ABRT", "ABRT", SIGABRT}, {"STACK", "SEGV", SIGSEGV}};
  for (const auto& [how, name, sig] : signals) {
    SCOPED_TRACE(how);
    TempDir dir;
    const auto file = dir.write(
        "pipeline.yaml", two_variant_sweep("crashing_rule", "after: 3000, signal: " + std::string(how), "diagnostics: [temperature]\n"));
    gdsmc::test::ProcessLimits limits;
    limits.core_dumps = false;
    Process p({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("crashing_rule").string()},
              dir.path(), limits);
    const ProcessResult r = p.wait(60);
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_EQ(r.signal, sig) << r.describe();
    EXPECT_TRUE(contains(r.err, std::string("gdsmc: crashed: SIG") + name + " (")) << r.describe();
    EXPECT_TRUE(contains(r.err, ") in the collision rule 'crashing_rule' (collision, " + file.string() + ":")) << r.describe();
    EXPECT_TRUE(contains(r.err, "; in collide_batch) at step ")) << r.describe();
    EXPECT_TRUE(contains(r.err, " of run 2 of 2 (model=bad): the plugin crashed")) << r.describe();
    EXPECT_TRUE(contains(r.err, "exit status " + std::to_string(128 + sig) + " (128 + the signal)")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{}) << "no output, temporary or lock file";
  }
}

// The same for a diagnostic (its sample() at a given step), in a run of one case: the step is the
// one the plugin saw.
TEST(PluginFailures, ACrashInsideADiagnosticNamesItAndItsStep) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", small_pipeline("", "{collisions_per_particle: 5}", 1000, 0.9,
                                                        "  - {plugin: temperature}\n"
                                                        "  - {plugin: dies_at_step, step: 7, signal: SEGV}\n"));
  gdsmc::test::ProcessLimits limits;
  limits.core_dumps = false;
  Process p({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("dies_at_step").string()},
            dir.path(), limits);
  const ProcessResult r = p.wait(60);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.signal, SIGSEGV) << r.describe();
  EXPECT_TRUE(contains(r.err, "gdsmc: crashed: SIGSEGV (invalid memory access) in the diagnostic 'dies_at_step' "
                              "(diagnostics[1], " + file.string() + ":")) << r.describe();
  EXPECT_TRUE(contains(r.err, "; in sample) at step 7: the plugin crashed")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// A collision rule that writes NaN (or infinite) velocities while declaring a finite energy change
// ran to exit 0 with NaN particles when no diagnostic measured the temperature. The host checks
// what leaves every batch of the collision stage: the run stops at that step, naming the rule,
// with or without diagnostics; a non-finite declared energy change is named too.
TEST(PluginFailures, ACollisionRuleWritingNonFiniteValuesIsNamedWithOrWithoutDiagnostics) {
  struct Case {
    std::string params, diagnostics, expected;
  };
  const std::vector<Case> cases = {
      {"after: 500", "diagnostics: []\n", "wrote a non-finite velocity at step "},
      {"after: 500", "diagnostics: [temperature]\n", "wrote a non-finite velocity at step "},
      {"after: 500, value: inf", "diagnostics: []\n", "wrote a non-finite velocity at step "},
      {"after: 500, energy: bad", "diagnostics: []\n", "wrote a non-finite velocity at step "},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.params + "; " + c.diagnostics);
    TempDir dir;
    const auto file = dir.write("pipeline.yaml", two_variant_sweep("nan_rule", c.params, c.diagnostics));
    const ProcessResult r =
        run_gdsmc({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("nan_rule").string()},
                  dir.path(), 60);
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_TRUE(contains(r.err, "plugin 'nan_rule' (collision, " + file.string() + ":")) << r.describe();
    EXPECT_TRUE(contains(r.err, c.expected)) << r.describe();
    EXPECT_TRUE(contains(r.err, " tau0, run 2 of 2 (model=bad)): particles ")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

// A rule whose velocities are finite but whose declared energy change is not.
TEST(PluginFailures, ANonFiniteDeclaredEnergyIsNamed) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", "run:\n  seed: 3\n  particles: 2000\n  time_step: {value: 0.02, unit: tau0}\n"
                                               "  stop: {collisions_per_particle: 2}\n"
                                               "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
                                               "collision: conformance_nan\ndiagnostics: []\noutput: {file: out.h5}\n");
  const ProcessResult r = run_gdsmc(
      {"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("conformance_nan").string()}, dir.path(), 60);
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "plugin 'conformance_nan' (collision, " + file.string() + ":")) << r.describe();
  EXPECT_TRUE(contains(r.err, "declared a non-finite kinetic-energy change (nan) at step 0")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// A forcing that writes a non-finite velocity while declaring a finite energy was caught only
// through the temperature of the next moment update (every run.moments_every steps, and named only
// as "one of the forcings"). The host now checks the velocities after every apply(): the run stops
// at that very step naming the forcing, with or without diagnostics.
TEST(PluginFailures, AForcingWritingANonFiniteVelocityIsNamedAtThatStep) {
  for (const char* diagnostics : {"diagnostics: []\n", "diagnostics: [temperature]\n"})
    for (const char* value : {"nan", "inf"}) {
      SCOPED_TRACE(std::string(diagnostics) + value);
      TempDir dir;
      const auto file = dir.write(
          "pipeline.yaml",
          "run:\n  seed: 3\n  particles: 2000\n  time_step: {value: 0.02, unit: tau0}\n"
          "  stop: {collisions_per_particle: 2}\n  moments_every: 1000\n"
          "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
          "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
          "forcings: [drag, {plugin: nan_forcing, step: 5, value: " + std::string(value) + "}]\n" +
              diagnostics + "output: {file: out.h5}\n");
      const ProcessResult r = run_gdsmc(
          {"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("nan_forcing").string()}, dir.path(), 60);
      EXPECT_EQ(r.exit_code, 1) << r.describe();
      EXPECT_TRUE(contains(r.err, "plugin 'nan_forcing' (forcings[1], " + file.string() + ":")) << r.describe();
      EXPECT_TRUE(contains(r.err, std::string(" wrote a non-finite velocity (") + value + ", ")) << r.describe();
      EXPECT_TRUE(contains(r.err, " in apply() at step 5 (t = ")) << r.describe();
      EXPECT_FALSE(contains(r.err, "plugin 'drag'")) << r.describe();
      EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
    }
}

// What the moment check says when every velocity was finite where the host checks it: a forcing
// that sets every velocity to 0 (finite, declared energy 0) makes the temperature 0. The message
// used to blame "one of the forcings" as if only the collision rule and the boundaries were
// checked; it now says what the host checks (the collision rule's batches, every forcing's apply(),
// every wall hit) and names the plugins that write velocities in this run.
TEST(PluginFailures, ATemperatureOfZeroFromFiniteVelocitiesSaysWhatTheHostChecked) {
  TempDir dir;
  const auto file = dir.write(
      "pipeline.yaml",
      "run:\n  seed: 3\n  particles: 2000\n  time_step: {value: 0.02, unit: tau0}\n"
      "  stop: {collisions_per_particle: 2}\n"
      "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings: [drag, {plugin: nan_forcing, step: 5, value: zero}]\n"
      "diagnostics: []\noutput: {file: out.h5}\n");
  const ProcessResult r = run_gdsmc(
      {"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("nan_forcing").string()}, dir.path(), 60);
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "pipeline.yaml: the temperature became ")) << r.describe();  // 0 up to rounding
  EXPECT_TRUE(contains(r.err, "so either finite velocities give this temperature (all equal: 0 up to rounding")) << r.describe();
  EXPECT_TRUE(contains(r.err, "every velocity was finite where the host checks it (the collision rule's as they leave "
                              "each batch, each forcing's after every apply(), each boundary's at every wall hit)"))
      << r.describe();
  for (const std::string who : {"plugin 'inelastic_hard_spheres' (collision, ", "plugin 'drag' (forcings[0], ",
                                "plugin 'nan_forcing' (forcings[1], "})
    EXPECT_TRUE(contains(r.err, who + file.string() + ":")) << who << "\n" << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

}  // namespace
}  // namespace gdsmc::test
