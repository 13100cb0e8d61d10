// No unbounded work from a pipeline that validates: case counts and memory are estimated before
// anything is expanded or allocated, absurd work per step is refused with the number, the memory
// estimate counts what realizations keep, and a plugin call that does not return after the first
// SIGINT ends the run anyway (instead of running out of memory, hanging, or naming nothing).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace {

using gdsmc::test::Process;
using gdsmc::test::ProcessLimits;
using gdsmc::test::ProcessResult;
using gdsmc::test::TempDir;
using gdsmc::test::contains;
using gdsmc::test::run_gdsmc;
using Clock = std::chrono::steady_clock;

using gdsmc::test::seconds_since;

std::filesystem::path config(const std::string& name) { return gdsmc::test::source_dir() / "configs" / name; }

std::string homogeneous(const std::string& run_extra = "", const std::string& diagnostics = "  - {plugin: temperature}\n") {
  return "run:\n"
         "  seed: 3\n"
         "  particles: 1000\n"
         "  time_step: {value: 0.01, unit: tau0}\n"
         "  stop: {collisions_per_particle: 5}\n" +
         run_extra +
         "system: {density: 1.0e-3, temperature: 1.0}\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
         "diagnostics:\n" +
         diagnostics + "output: {file: out.h5}\n";
}

// Nine keys of ten values: 10^9 cases. validate built every point of the product first and ran
// out of memory; the count is now checked before anything is expanded.
TEST(UnboundedWork, ASweepOfABillionCasesIsRefusedBeforeItIsExpanded) {
  TempDir dir;
  std::string sweep = "sweep:\n";
  const char* keys[] = {"collision.alpha", "run.seed", "system.temperature", "system.density", "run.particles",
                        "run.time_step.value", "run.stop.collisions_per_particle", "run.sample_every", "run.record_every"};
  for (const char* key : keys) sweep += std::string("  ") + key + ": [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n";
  const auto file = dir.write("pipeline.yaml", homogeneous() + sweep);
  ProcessLimits limits;
  limits.address_space = 2ull << 30;  // the old expansion took every byte it could get
  Process p({"validate", file.string()}, dir.path(), limits);
  const ProcessResult r = p.wait(60);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "pipeline.yaml:13:")) << r.describe();  // the sweep's first value
  EXPECT_TRUE(contains(r.err, "sweep: 10 (collision.alpha) x 10 (run.seed) x")) << r.describe();
  EXPECT_TRUE(contains(r.err, "make 1e+09 cases; at most 100000 are allowed")) << r.describe();
  EXPECT_FALSE(contains(r.err, "memory ran out")) << r.describe();
}

// system.bins: 1e8 made the plugins allocate their per-bin arrays (24 GB) before the estimate was
// looked at. The case is now set up with 4096 and 8192 bins, what its plugins allocate measured and
// extrapolated to 1e8 (135 GiB) and refused against the memory available, here a 3 GiB
// address-space limit, with the figures.
TEST(UnboundedWork, ManySamplingBinsAreEstimatedBeforeAnyPluginAllocatesThem) {
  TempDir dir;
  ProcessLimits limits;
  limits.address_space = 3ull << 30;
  Process p({"validate", config("poiseuille.yaml").string(), "--set", "system.bins=100000000", "-o",
             (dir / "out.h5").string()},
            dir.path(), limits);
  const ProcessResult r = p.wait(60);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "this run needs about")) << r.describe();
  EXPECT_TRUE(contains(r.err, "the address-space limit (ulimit -v) 3.0 GiB")) << r.describe();
  EXPECT_TRUE(contains(r.err, "(measured with 4096 and 8192 sampling bins, for 100000000): use fewer system.bins"))
      << r.describe();
  EXPECT_FALSE(contains(r.err, "memory ran out")) << r.describe();
  EXPECT_EQ(dir.entries_except({}), std::vector<std::string>{});
}

// A slab 1e-6 lambda0 wide validated and then spent ~17 s a step reflecting particles. Each
// particle meets the walls about dt/(sqrt(pi) Ly) times a step: refused above 100 with the
// number, warned about above 1.
TEST(UnboundedWork, AGapCrossedManyTimesAStepIsRefusedOrWarnedWithTheWallHits) {
  TempDir dir;
  const ProcessResult refused = run_gdsmc({"validate", config("poiseuille.yaml").string(), "--set", "system.box.y=1e-6",
                                           "--set", "system.layers=10", "-o", (dir / "out.h5").string()},
                                          dir.path(), 30);
  ASSERT_FALSE(refused.timed_out) << refused.describe();
  EXPECT_EQ(refused.exit_code, 1) << refused.describe();
  // dt = 0.02 tau0 across 1e-6 lambda0: 0.02 / (sqrt(pi) 1e-6) = 1.13e4 hits a particle a step.
  EXPECT_TRUE(contains(refused.err, "--set system.box.y=1e-6: system.box.y: a step of 0.02 tau0 across a gap "
                                    "Ly = 1e-06 lambda0: each particle would meet the walls about 1.13e+04 times a step"))
      << refused.describe();
  EXPECT_TRUE(contains(refused.err, "1.13e+09 wall hits a step for 100000 particles")) << refused.describe();
  EXPECT_TRUE(contains(refused.err, "use a time step of at most 1.77e-06 tau0")) << refused.describe();

  // 0.02 / (sqrt(pi) 0.002) = 5.64: valid, with a warning.
  const ProcessResult warned = run_gdsmc({"validate", config("poiseuille.yaml").string(), "--set", "system.box.y=0.002",
                                          "--set", "system.layers=10", "-o", (dir / "out.h5").string()},
                                         dir.path(), 30);
  EXPECT_EQ(warned.exit_code, 0) << warned.describe();
  EXPECT_TRUE(contains(warned.err, "each particle would meet the walls about 5.64 times a step")) << warned.describe();
  EXPECT_TRUE(contains(warned.err, "a step of at most 0.00354 tau0 resolves it")) << warned.describe();
}

// A shipped uniform-shear pipeline with shear_rate 1e6 validated and never finished: the gas
// gained 1e5 times its energy a step and the BGK diagnostic integrated its model for ever. The
// forcing's heating over the step is refused at the first step, naming it, with the factor.
TEST(UnboundedWork, AForcingThatMultipliesTheEnergyInOneStepIsRefusedNamingIt) {
  TempDir dir;
  const ProcessResult r = run_gdsmc({"run", config("usf_ehs_refined_alpha0.5_shear4.yaml").string(), "--set",
                                     "run.particles=1000", "--set", "forcings.0.shear_rate=1e6", "--quiet", "-o",
                                     (dir / "out.h5").string()},
                                    dir.path(), 60);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "uniform_shear")) << r.describe();
  EXPECT_TRUE(contains(r.err, "times the gas's thermal energy (3/2 N T = ")) << r.describe();
  EXPECT_TRUE(contains(r.err, "in one step at step 0 (t = 0 tau0, dt = 0.001 tau0)")) << r.describe();
  EXPECT_EQ(dir.entries_except({}), std::vector<std::string>{});
}

// One SIGINT while a plugin call never returns: the run used to wait for ever (a second signal
// was needed). Now it ends kStuckCallSeconds (3 s) later, naming the plugin and the call, exit
// 130, nothing left behind.
TEST(UnboundedWork, OneSignalEndsARunStuckInAPluginCallNamingThePlugin) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", homogeneous("", "  - {plugin: temperature}\n  - {plugin: stuck_sample}\n"));
  Process p({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("stuck_sample").string()},
            dir.path());
  ASSERT_TRUE(p.wait_until_catches(SIGINT));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // now inside step 1's sample()
  const auto sent = Clock::now();
  p.send(SIGINT);
  const ProcessResult r = p.wait(30);
  const double took = seconds_since(sent);
  ASSERT_FALSE(r.timed_out) << "one SIGINT did not end a run stuck in a plugin call\n" << r.describe();
  EXPECT_GE(took, 2.5) << r.describe();  // the call was given its 3 s
  EXPECT_LT(took, 20.0) << r.describe();
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  EXPECT_TRUE(contains(r.err, "interrupted, but the diagnostic 'stuck_sample' (")) << r.describe();
  EXPECT_TRUE(contains(r.err, "; in sample) at step 1 had not returned 3 s after the interrupt")) << r.describe();
  EXPECT_TRUE(contains(r.err, "no output written (the temporary file is removed)")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// The peak resident size (KiB) of `gdsmc args...` run to its end in `dir`, and what it printed.
struct Peak {
  long kib = 0;
  int status = -1;
  std::string out;
};
Peak peak_of(const TempDir& dir, const std::vector<std::string>& args) {
  const std::string out = (dir / "stdout").string();
  std::vector<std::string> argv = {gdsmc::test::executable().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  gdsmc::host::SubprocessOptions options;
  options.cwd = dir.path();
  options.stdout_file = out;
  options.unset_environment = {"GDSMC_PLUGIN_PATH"};
  gdsmc::host::Subprocess child(argv, options);
  Peak p;
  p.status = child.wait().exit_code;
  p.kib = child.usage().ru_maxrss;
  p.out = gdsmc::test::read_text(out);
  std::filesystem::remove(out);
  return p;
}

// "...; about 12 MiB of memory)" of validate's verdict, in MiB.
double estimate_mib(const std::string& verdict) {
  const auto at = verdict.find("; about ");
  if (at == std::string::npos) return -1;
  char unit[8] = {};
  double value = -1;
  if (std::sscanf(verdict.c_str() + at + 8, "%lf %7s", &value, unit) != 2) return -1;
  const std::string u = unit;
  return u == "KiB" ? value / 1024 : u == "MiB" ? value : u == "GiB" ? value * 1024 : -1;
}

// 128 realizations of an HCS at a step that follows the temperature: the estimate of what they
// keep (each run's records, their average) against the peak resident size measured, less that of
// a run of one realization (the program, its libraries and plugins). The estimate said 59 MiB of a
// study that took 278-703 MB: it took s per step as dt/tau0 (1.77 times too few steps) and the
// steps at T0 for a gas that cooled at a fixed step.
TEST(UnboundedWork, TheMemoryEstimateOfManyRealizationsCoversTheMeasuredPeak) {
  TempDir dir;
  const std::string yaml = homogeneous("  realizations: 128\n  threads: 1\n");
  std::string follow = yaml;
  follow.replace(follow.find("unit: tau0}"), 11, "unit: tau0, follow_temperature: true}");
  follow.replace(follow.find("collisions_per_particle: 5"), 26, "collisions_per_particle: 20");
  dir.write("many.yaml", follow);
  std::string one = follow;
  one.replace(one.find("realizations: 128"), 17, "realizations: 1");
  dir.write("one.yaml", one);
  const Peak verdict = peak_of(dir, {"validate", "many.yaml"});
  ASSERT_EQ(verdict.status, 0) << verdict.out;
  const double estimate = estimate_mib(verdict.out);
  ASSERT_GT(estimate, 0) << verdict.out;
  const Peak base = peak_of(dir, {"run", "one.yaml", "--quiet", "-o", "one.h5"});
  const Peak many = peak_of(dir, {"run", "many.yaml", "--quiet", "-o", "many.h5"});
  ASSERT_EQ(base.status, 0);
  ASSERT_EQ(many.status, 0);
  const double measured = (many.kib - base.kib) / 1024.0;
  std::cout << "estimate " << estimate << " MiB, measured " << measured << " MiB (peaks " << many.kib / 1024.0
            << " and " << base.kib / 1024.0 << " MiB)\n";
  // Measured: estimate 21 MiB, 21.1 MiB more than one realization (the old estimate: about 12).
  EXPECT_GE(estimate, 0.9 * measured) << "the estimate is more than 10 % below the memory measured";
  EXPECT_LE(estimate, 3 * measured + 2) << "the estimate is more than 3 times the memory measured";
}

}  // namespace

namespace {

// A gas that cools at a fixed step takes many more steps to a stop at s than the estimate assumes
// (here 32 871, not about 7 090), and keeps every step's record: 200 realizations validated
// against a 300 MiB address-space limit and then ran out of memory after computing. Now the first
// run's records are measured and the study stops at once, saying why.
TEST(UnboundedWork, ACoolingGasKeepingMoreThanEstimatedStopsAfterItsFirstRun) {
  TempDir dir;
  std::string yaml = homogeneous("  realizations: 200\n  threads: 1\n");
  yaml.replace(yaml.find("collisions_per_particle: 5"), 26, "collisions_per_particle: 40");
  const auto file = dir.write("pipeline.yaml", yaml);
  ProcessLimits limits;
  limits.address_space = 300ull << 20;
  Process validate({"validate", file.string()}, dir.path(), limits);
  const ProcessResult v = validate.wait(60);
  ASSERT_EQ(v.exit_code, 0) << v.describe();
  Process run({"run", file.string(), "--quiet"}, dir.path(), limits);
  const ProcessResult r = run.wait(120);
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "memory: run 'realization 0' took ")) << r.describe();
  EXPECT_TRUE(contains(r.err, " steps (the estimate assumed about 7090) and keeps ")) << r.describe();
  EXPECT_TRUE(contains(r.err, "the case's 199 runs left and its average would keep about")) << r.describe();
  EXPECT_FALSE(contains(r.err, "memory ran out")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

}  // namespace
