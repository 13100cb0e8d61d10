// Issue 9: every run can be stopped, and no value makes it spin. Hostile system values and time
// steps are refused before anything runs, naming the derived quantity that is unusable; SIGINT and
// SIGTERM end a run within a second (a second signal even inside a plugin call that never
// returns); the collision stage bounds its work and polls for an interrupt inside a large cell;
// the progress line, number messages and steady averages say what is actually wrong.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "app/progress.hpp"
#include "engine/collision_stage.hpp"
#include "engine/majorant.hpp"
#include "test_support.hpp"

namespace {

namespace host = gdsmc::host;
namespace h5 = gdsmc::test::h5;
using gdsmc::test::Process;
using gdsmc::test::contains;
using gdsmc::test::ProcessResult;
using gdsmc::test::TempDir;
using gdsmc::test::run_gdsmc;
using Clock = std::chrono::steady_clock;

using gdsmc::test::seconds_since;

// A small valid pipeline; the tests change it with --set.
std::string pipeline(const std::string& run_extra = "", const std::string& stop = "{collisions_per_particle: 5}",
                     int particles = 1000, double alpha = 0.9, const std::string& diagnostics = "  - {plugin: temperature}\n") {
  return "run:\n"
         "  seed: 3\n"
         "  particles: " + std::to_string(particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n" + run_extra +
         "system:\n"
         "  density: 1.0e-3\n"
         "  temperature: 1.0\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}\n"
         "diagnostics:\n" + diagnostics +
         "output: {file: out.h5}\n";
}

// `gdsmc <command> pipeline.yaml [args]` in a fresh directory; what it printed and what it left there.
struct Outcome {
  ProcessResult result;
  std::vector<std::string> left;  // entries other than the pipeline
};
Outcome gdsmc_in_dir(const std::string& command, const std::string& yaml, const std::vector<std::string>& args,
                     double timeout_s = 30) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", yaml);
  std::vector<std::string> argv = {command, file.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  Outcome o;
  o.result = run_gdsmc(argv, dir.path(), timeout_s);
  o.left = dir.entries_except({"pipeline.yaml"});
  return o;
}

// ---------------------------------------------------------------------------------------------
// Refusals before anything runs.

// Each of these validated and then hung in the first step (ignoring SIGINT and SIGTERM), looped
// forever or failed with a misleading message. Now: exit 1 at load time, the value's key and
// location, the derived quantity and its value, nothing written.
TEST(ReliabilityRun, HostileSystemValuesAndTimeStepsAreRefusedNamingTheDerivedQuantity) {
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
    const Outcome o = gdsmc_in_dir("run", pipeline(), {"--set", c.set});
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
TEST(ReliabilityRun, ADensityDerivedFromTheMeanFreePathMustBeUsableToo) {
  std::string yaml = pipeline();
  yaml.replace(yaml.find("  density: 1.0e-3\n"), 18, "  mean_free_path: 1\n  sigma: 1.0e200\n");
  const Outcome o = gdsmc_in_dir("validate", yaml, {});
  EXPECT_EQ(o.result.signal, 0) << o.result.describe();
  EXPECT_EQ(o.result.exit_code, 1) << o.result.describe();
  EXPECT_TRUE(contains(o.result.err, "system.sigma: the number density n is 0")) << o.result.describe();
}

// A shipped uniform-shear-flow pipeline with time_step 5 tau0 validated and never ended (the
// gas collapsed, and the BGK diagnostic then integrated its model over an ever longer time).
TEST(ReliabilityRun, ShippedShearFlowWithAStepOfFiveTau0IsRefused) {
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
TEST(ReliabilityRun, NumbersOutOfRangeSayWhatIsWrong) {
  struct Case {
    std::string set, says;
  };
  const std::vector<Case> cases = {
      {"run.particles=9223372036854775807", "particles must be between 2 and 4e9, got 9223372036854775807"},
      {"run.particles=9223372036854775808", "'9223372036854775808' is out of range: whole numbers must be between"},
      {"run.seed=1e19", "'1e19' is out of range: whole numbers must be between -9.2e18 and 9.2e18"},
      {"system.sigma=1e400", "'1e400' is out of range: numbers must be at most about 1.8e308"},
      {"system.sigma=1e-400", "'1e-400' is too small to represent (it would read as 0)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.set);
    const Outcome o = gdsmc_in_dir("validate", pipeline(), {"--set", c.set});
    EXPECT_EQ(o.result.exit_code, 1) << o.result.describe();
    EXPECT_TRUE(contains(o.result.err, c.says)) << o.result.describe();
    EXPECT_FALSE(contains(o.result.err, "expected a whole number")) << o.result.describe();
  }
}

// Warnings, not refusals: a step of more than half a mean free time; a last step that overshoots
// the stop time 5x; an average window that starts after the stop. The unchanged pipeline warns
// about nothing.
TEST(ReliabilityRun, LargeStepsAndUnreachableAverageWindowsAreWarnedAbout) {
  const Outcome plain = gdsmc_in_dir("validate", pipeline(), {});
  EXPECT_EQ(plain.result.exit_code, 0) << plain.result.describe();
  EXPECT_FALSE(contains(plain.result.err, "warning")) << plain.result.describe();

  const Outcome half = gdsmc_in_dir("validate", pipeline(), {"--set", "run.time_step.value=0.5"});
  EXPECT_EQ(half.result.exit_code, 0) << half.result.describe();
  EXPECT_TRUE(contains(half.result.err, "warning: --set run.time_step.value=0.5: run.time_step.value: a step of 0.5 tau0 "
                                        "is 0.56 mean free times")) << half.result.describe();

  const Outcome overshoot = gdsmc_in_dir("validate", pipeline("", "{time: 0.1}"), {"--set", "run.time_step.value=0.5"});
  EXPECT_EQ(overshoot.result.exit_code, 0) << overshoot.result.describe();
  EXPECT_TRUE(contains(overshoot.result.err, "the run stops at t = 0.5 tau0, 5 times run.stop.time 0.1 tau0"))
      << overshoot.result.describe();

  const Outcome window =
      gdsmc_in_dir("validate", pipeline("  average_after: {collisions_per_particle: 10}\n"), {});
  EXPECT_EQ(window.result.exit_code, 0) << window.result.describe();
  EXPECT_TRUE(contains(window.result.err, "run.average_after.collisions_per_particle: the steady window starts at 10, "
                                          "not before run.stop.collisions_per_particle 5")) << window.result.describe();
}

// ---------------------------------------------------------------------------------------------
// What a run reports.

// A window on the other clock (t) that the run never reaches: the summary warns, and the NaN
// datasets say why in their description.
TEST(ReliabilityRun, ASteadyWindowNeverReachedIsWarnedAboutAndDescribed) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline("  average_after: {time: 1000}\n", "{collisions_per_particle: 1}"));
  const ProcessResult r = run_gdsmc({"run", file.string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.out, "warning: run.average_after: the steady window t/tau0 >= 1000 holds no record (the last is at "
                              "t/tau0 = ")) << r.describe();
  h5::File f(dir / "out.h5");
  EXPECT_TRUE(std::isnan(h5::read_scalar(f.id(), "/diagnostics/temperature/temperature.steady_mean")));
  EXPECT_TRUE(contains(h5::read_string_attribute(f.id(), "/diagnostics/temperature/temperature.steady_mean", "description"),
                       "NaN: no record reached the window"));
}

// Without a terminal, progress is a line every 10 s for the whole study, not one per realization.
TEST(ReliabilityRun, ProgressWithoutATerminalIsNotALinePerRealization) {
  const Outcome o = gdsmc_in_dir("run", pipeline("  realizations: 300\n", "{collisions_per_particle: 0.2}", 50), {});
  ASSERT_EQ(o.result.exit_code, 0) << o.result.describe();
  int lines = 0;
  for (std::size_t pos = 0; (pos = o.result.err.find("[", pos)) != std::string::npos; ++pos)
    if (pos == 0 || o.result.err[pos - 1] == '\n') ++lines;
  EXPECT_LE(lines, 2) << o.result.err.substr(0, 2000);
}

// The time left, however large (an estimate from a tiny fraction done, a stop out of reach), is a
// short text.
TEST(ReliabilityRun, TimeLeftIsShortHoweverLarge) {
  EXPECT_EQ(host::format_seconds(42), "42s");
  EXPECT_EQ(host::format_seconds(5399.7), "90m00s");
  EXPECT_EQ(host::format_seconds(7200), "2.0h");
  EXPECT_EQ(host::format_seconds(3 * 86400.0), "3d");
  EXPECT_EQ(host::format_seconds(1e65), ">1000d");
  EXPECT_EQ(host::format_seconds(HUGE_VAL), ">1000d");
  EXPECT_EQ(host::format_seconds(std::nan("")), "?");
  EXPECT_EQ(host::format_seconds(-1), "?");
}

// ---------------------------------------------------------------------------------------------
// Signals.

// SIGINT and SIGTERM about 1.5 s into a long run (2e5 elastic particles to s = 1e5): exit 130
// within a second, "interrupted", nothing written.
TEST(ReliabilityRun, SigintAndSigtermEndALongRunWithinASecond) {
  for (const int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    TempDir dir;
    const auto file = dir.write("pipeline.yaml", pipeline("", "{collisions_per_particle: 100000}", 200000, 1.0));
    const auto start = Clock::now();
    Process p({"run", file.string(), "--quiet"}, dir.path());
    ASSERT_TRUE(p.wait_until_catches(sig)) << "the run never installed a handler for signal " << sig;
    std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.2, 1.5 - seconds_since(start))));
    const auto sent = Clock::now();
    p.send(sig);
    const ProcessResult r = p.wait(10);
    const double took = seconds_since(sent);
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_LT(took, 1.0) << r.describe();
    EXPECT_EQ(r.exit_code, 130) << r.describe();
    EXPECT_TRUE(contains(r.err, "interrupted; no output written")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

// A plugin call that never returns cannot poll the flag; a second signal ends the run at once.
TEST(ReliabilityRun, ASecondSignalEndsARunStuckInAPluginCall) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline("", "{collisions_per_particle: 5}", 1000, 0.9,
                                                        "  - {plugin: temperature}\n  - {plugin: stuck_sample}\n"));
  Process p({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("stuck_sample").string()},
            dir.path());
  ASSERT_TRUE(p.wait_until_catches(SIGINT));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // now inside step 1's sample()
  p.send(SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto sent = Clock::now();
  p.send(SIGTERM);
  const ProcessResult r = p.wait(10);
  ASSERT_FALSE(r.timed_out) << "a second signal did not end a run stuck in a plugin call";
  EXPECT_LT(seconds_since(sent), 1.0);
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  EXPECT_TRUE(contains(r.err, "interrupted again; stopped at once, no output written")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// ---------------------------------------------------------------------------------------------
// The collision stage in-process, with a rule that records what it is handed.

// Counts the pairs the host hands it, rejects every one, and can set an interrupt flag on its first
// call (a signal arriving while the first slice runs). One thread only (no pool in these tests).
class RecordingRule final : public gdsmc::CollisionRule {
 public:
  void bind(const gdsmc::ParticleSpan&) override {}
  gdsmc::KernelForm kernel_form() const override { return gdsmc::KernelForm::hard_sphere; }
  double pair_rate(const gdsmc::Vec3&, const gdsmc::Vec3&) const override { return 0; }
  double rate_bound(double speed) const override { return speed; }
  void collide_batch(gdsmc::PairBatch& b) const override {
    pairs += b.count;
    for (std::uint32_t q = 0; q < b.count; ++q) b.accepted[q] = 0;
    if (set_on_first_call) set_on_first_call->store(true);
  }
  mutable std::uint64_t pairs = 0;
  std::atomic<bool>* set_on_first_call = nullptr;
};

// One homogeneous cell of N particles at T = 1 and the dt that gives `per_particle` hard-sphere
// candidates per particle.
struct Cell {
  std::size_t n = 200000;
  double volume = 1e8;
  host::CellGrid grid;
  gdsmc::ParticleSpan span;
  host::StreamFactory streams{7, 0};
  std::vector<double> vx, vy, vz;  // all at rest: the rule reads nothing
  Cell() : vx(n), vy(n), vz(n) {
    grid.homogeneous(n, volume);
    span.count = n;
    span.vx = vx.data(); span.vy = vy.data(); span.vz = vz.data();
  }
  double dt_for(double per_particle) const {
    const double pairs = host::pair_count(host::PairCount::distinct, static_cast<std::uint32_t>(n));
    return per_particle * static_cast<double>(n) * volume / (pairs * M_PI * host::kInitialMajorantRatio);
  }
  host::CollisionStage::Totals run(host::CollisionStage& stage, const RecordingRule& rule, double dt) {
    return stage.run(rule, span, grid, nullptr, 1.0, 1.0, 1.0, dt, streams);
  }
};

// A cell of 4e6 candidates (x 4 for a general kernel > 2^20) is collided in slices of dt with the
// remainder carried from slice to slice, so its count is that of the whole step at once, and every
// candidate reaches the rule.
TEST(ReliabilityRun, ALargeCellsSlicesTestTheCandidatesOfTheWholeStep) {
  Cell cell;
  RecordingRule rule;
  host::CollisionStage stage;
  const auto t = cell.run(stage, rule, cell.dt_for(20));
  EXPECT_NEAR(static_cast<double>(t.candidates), 20 * 200000.0, 1.0);
  EXPECT_EQ(rule.pairs, t.candidates);
  EXPECT_EQ(t.accepted, 0u);
}

// An interrupt that arrives during the first slice ends the stage before the next one: the rule
// has seen at most one slice's candidates (16 slices here).
TEST(ReliabilityRun, TheCollisionStagePollsTheInterruptBetweenSlices) {
  Cell cell;
  std::atomic<bool> flag{false};
  RecordingRule rule;
  rule.set_on_first_call = &flag;
  host::CollisionStage stage;
  stage.set_interrupt(&flag);
  EXPECT_THROW(cell.run(stage, rule, cell.dt_for(20)), host::Interrupted);
  const double slices = std::ceil(4 * 20 * 200000.0 / host::kCandidatesPerSlice);
  EXPECT_GT(rule.pairs, 0u);
  EXPECT_LE(static_cast<double>(rule.pairs), std::ceil(20 * 200000.0 / slices) + 1);
}

// More than 100 candidates per particle, or a count that is not finite, is refused before any
// pair is tested.
TEST(ReliabilityRun, TheCollisionStageRefusesAbsurdWorkBeforeDoingAny) {
  Cell cell;
  for (const double dt : {cell.dt_for(150), HUGE_VAL, std::nan("")}) {
    RecordingRule rule;
    host::CollisionStage stage;
    try {
      cell.run(stage, rule, dt);
      ADD_FAILURE() << "dt " << dt << " was not refused";
    } catch (const host::CollisionStage::Overload& e) {
      EXPECT_TRUE(contains(e.what(), "candidate pairs")) << e.what();
    }
    EXPECT_EQ(rule.pairs, 0u);
  }
}

// ---------------------------------------------------------------------------------------------
// The engine's guards during a run (values that validation would refuse, set after loading, stand
// for a run whose temperature has drifted far from T0).

// Sets *flag after `seconds` unless stopped first: the old behaviour (running on) then ends in
// Interrupted instead of hanging the test.
class Watchdog {
 public:
  Watchdog(std::atomic<bool>& flag, double seconds)
      : thread_([this, &flag, seconds] {
          const auto start = Clock::now();
          while (!stop_ && seconds_since(start) < seconds) std::this_thread::sleep_for(std::chrono::milliseconds(5));
          if (!stop_) flag = true;
        }) {}
  ~Watchdog() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(ReliabilityRun, AStepTooLargeForTheCollisionsIsRefusedDuringTheRun) {
  TempDir dir;
  host::Pipeline p = gdsmc::test::load_yaml(dir, pipeline());
  p.time_step_tau0 = 60;  // ~127 candidates per particle per step
  p.time_step_follows_temperature = false;
  host::Engine engine(p);
  try {
    engine.run();
    ADD_FAILURE() << "the run was not refused";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "at step 0 (t = 0 tau0, T/T0 = ")) << m;
    EXPECT_TRUE(contains(m, "), with dt = 60 tau0: the collision stage would test about ")) << m;
    EXPECT_TRUE(contains(m, "use a smaller run.time_step or run.time_step.follow_temperature: true")) << m;
  }
}

TEST(ReliabilityRun, AStopTimeOutOfReachIsRefusedDuringTheRun) {
  TempDir dir;
  host::Pipeline p = gdsmc::test::load_yaml(dir, pipeline("", "{time: 1}"));
  p.time_step_tau0 = 1e-13;
  p.time_step_follows_temperature = false;
  host::Engine engine(p);
  std::atomic<bool> flag{false};
  Watchdog watchdog(flag, 10);
  try {
    engine.run({}, 1.0, &flag);
    ADD_FAILURE() << "the run ended";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "at step 0 (t = 0 tau0, T/T0 = ")) << e.what();
    EXPECT_TRUE(contains(e.what(), ": the stop time 1 tau0 is 1e+13 steps of dt = 1e-13 tau0 away (more than 1e+12)"))
        << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Crashes and bad values explain themselves (issue 30, item 3).

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
TEST(ReliabilityRun, ACrashInsideAPluginNamesItItsRoleTheStepAndTheRunAndLeavesNoFile) {
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
TEST(ReliabilityRun, ACrashInsideADiagnosticNamesItAndItsStep) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline("", "{collisions_per_particle: 5}", 1000, 0.9,
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
TEST(ReliabilityRun, ACollisionRuleWritingNonFiniteValuesIsNamedWithOrWithoutDiagnostics) {
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
TEST(ReliabilityRun, ANonFiniteDeclaredEnergyIsNamed) {
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
TEST(ReliabilityRun, AForcingWritingANonFiniteVelocityIsNamedAtThatStep) {
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
TEST(ReliabilityRun, ATemperatureOfZeroFromFiniteVelocitiesSaysWhatTheHostChecked) {
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
