// A study over the ranks of an MPI job (`mpirun -np K gdsmc run`, docs/cluster.md): the file rank 0
// writes holds the same bytes, dataset by dataset and attribute by attribute (wall times aside),
// as the serial run's (--threads 1, no mpirun): a sweep with realizations, a slab between walls
// with the final particles (runs finished on rank 1 cross to rank 0), and a checkpoint of a job
// interrupted at 2 ranks resumed at 3. The summary is printed once; a run that throws on rank 1
// ends the job with exit 1, that rank's message, and no output file; a rank killed by a signal
// mid-run is named with its run (rank 0 by a rank on its host), and leaves no output file either. Skipped when the host was
// built without MPI (-DGDSMC_WITH_MPI=OFF) or no mpirun was found.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <thread>

#include "support/mpi.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;


std::size_t count_lines(const std::string& text, const std::string& prefix) { return lines_starting(text, prefix).size(); }
std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

// Runs `yaml` serially (--threads 1) and over 2 ranks of one thread each, and compares the files.
void expect_two_ranks_give_the_serial_bits(const std::string& yaml, std::size_t min_entries) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const ProcessResult serial =
      run_gdsmc({"run", pipeline.string(), "-o", "serial.h5", "--threads", "1", "--quiet"}, dir.path(), 300);
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  const ProcessResult mpi = mpirun(2, {"run", pipeline.string(), "-o", "mpi.h5", "--threads", "1"}, dir.path());
  ASSERT_EQ(mpi.exit_code, 0) << mpi.describe();
  EXPECT_EQ(count_lines(mpi.out, "output: "), 1u) << "the summary is printed once\n" << mpi.out;
  EXPECT_EQ(count_lines(mpi.out, "gdsmc: pipeline.yaml: "), 1u) << mpi.out;
  expect_same_contents(dir / "serial.h5", dir / "mpi.h5", min_entries);
}

TEST(Mpi, ASweepWithRealizationsOverTwoRanksIsTheSameBitsAsTheSerialRun) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_two_ranks_give_the_serial_bits(
      "run:\n  seed: 7\n  particles: 3000\n  time_step: {value: 0.02, unit: tau0}\n"
      "  stop: {collisions_per_particle: 4}\n  record_every: 10\n  realizations: 3\n"
      "  average_after: {collisions_per_particle: 1}\n"
      "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "diagnostics: [temperature, cumulants, hcs_theory]\n"
      "sweep:\n  collision.alpha: [0.6, 0.8, 0.95]\n"
      "output: {file: out.h5, realizations: true}\n",
      60);
}

TEST(Mpi, ASlabBetweenWallsWithItsParticlesOverTwoRanksIsTheSameBitsAsTheSerialRun) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  // Two cases of one realization each: case 1 runs on rank 1, whose final particles cross to rank 0.
  expect_two_ranks_give_the_serial_bits(
      "run:\n  seed: 11\n  particles: 6000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 3}\n"
      "  record_every: 20\n  average_after: {time: 1}\n"
      "system:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
      "  box: {y: {value: 1860, unit: sigma}}\n  layers: 20\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
      "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
      "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
      "diagnostics: [slab_averages, energy_balance, profiles, wall_fluxes]\n"
      "sweep:\n  boundaries.y_max.accommodation: [0.5, 1.0]\n"
      "output: {file: out.h5, particles: true}\n",
      40);
}

TEST(Mpi, AJobInterruptedAtTwoRanksResumesAtThreeRanksToTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  TempDir dir;
  const fs::path pipeline = dir.write(
      "pipeline.yaml",
      "run:\n  seed: 2001\n  particles: 10000\n  time_step: {value: 0.01, unit: tau0}\n"
      "  stop: {collisions_per_particle: 30}\n  record_every: 20\n  realizations: 2\n"
      "  checkpoint: {every: {collisions_per_particle: 0.5}}\n"
      "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
      "diagnostics: [temperature, cumulants]\n"
      "sweep:\n  collision.alpha: [0.7, 0.9]\noutput: {file: out.h5, realizations: true}\n");
  const auto start = std::chrono::steady_clock::now();
  const ProcessResult serial =
      run_gdsmc({"run", pipeline.string(), "-o", "serial.h5", "--threads", "1", "--quiet"}, dir.path(), 300);
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  const double serial_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Interrupted (SIGTERM to mpirun, as a batch system's time limit sends it) once every rank has
  // saved a state and before the job can end: two ranks take at least half the serial time.
  Process job(mpirun_args(2, {"run", pipeline.string(), "-o", "out.h5", "--threads", "1", "--quiet"}), dir.path(), {},
              GDSMC_MPIEXEC);
  const fs::path checkpoint = dir / "out.h5.checkpoint";
  auto saved_runs = [&] {
    std::size_t n = 0;
    std::error_code ec;
    for (int run = 0; run < 4; ++run) n += fs::exists(checkpoint / ("run-" + std::to_string(run)), ec) ? 1 : 0;
    return n;
  };
  const auto t0 = std::chrono::steady_clock::now();
  while (!job.ended() && saved_runs() < 2 &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 0.4 * serial_seconds + 30)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_FALSE(job.ended()) << "the job ended before it could be interrupted\n" << job.wait().describe();
  job.send(SIGTERM);
  const auto stop_start = std::chrono::steady_clock::now();
  const ProcessResult stopped = job.wait(60);
  const double stop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - stop_start).count();
  EXPECT_NE(stopped.exit_code, 0) << stopped.describe();
  EXPECT_LT(stop_seconds, 10.0) << "SIGTERM ends the job within seconds";
  // mpirun's SIGCONT before its SIGTERM makes rank 0 call the roll: every rank answers.
  EXPECT_FALSE(contains(stopped.err, "ended without a word")) << stopped.err;
  EXPECT_FALSE(fs::exists(dir / "out.h5")) << "an interrupted job writes nothing under the output name";
  ASSERT_TRUE(fs::exists(checkpoint / "study")) << stopped.describe();
  EXPECT_GE(saved_runs(), 2u);

  const ProcessResult resumed =
      mpirun(3, {"run", pipeline.string(), "-o", "out.h5", "--threads", "1", "--resume"}, dir.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.describe();
  EXPECT_EQ(count_lines(resumed.err, "gdsmc: resuming from "), 1u) << resumed.err;
  EXPECT_FALSE(fs::exists(checkpoint)) << "the checkpoint is removed once the output is written";
  expect_same_contents(dir / "serial.h5", dir / "out.h5", 30);
}

TEST(Mpi, ARunThatThrowsOnRankOneEndsTheJobWithExitOneItsMessageAndNoOutput) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  TempDir dir;
  // Case 0 runs on rank 0 and is fine; case 1 runs on rank 1, whose diagnostic throws as the run ends.
  const fs::path pipeline = dir.write(
      "pipeline.yaml",
      "run:\n  seed: 3\n  particles: 2000\n  time_step: {value: 0.02, unit: tau0}\n"
      "  stop: {collisions_per_particle: 2}\n"
      "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "diagnostics: [temperature]\n"
      "sweep:\n  model:\n    fine: {diagnostics: [temperature]}\n"
      "    failing: {diagnostics: [temperature, failing_finish]}\n"
      "output: {file: out.h5}\n");
  const ProcessResult r = mpirun(
      2, {"run", pipeline.string(), "--threads", "1", "--plugin-path", test_plugin("failing_finish").string()},
      dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "rank 1: ")) << r.err;
  EXPECT_TRUE(contains(r.err, "(run model=failing)")) << r.err;
  EXPECT_TRUE(contains(r.err, "deliberate failure at the end of the run")) << r.err;
  EXPECT_EQ(count_lines(r.err, "gdsmc: the run failed; nothing was written"), 1u) << r.err;
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{})
      << "no output file, no temporary file is left";
}

// A rank that dies without a word (SIGKILL: the OOM killer, a user; SIGSEGV: a crashing plugin)
// mid-run, while the others still run theirs. Rank `dying` (1: mpirun's first signal, SIGCONT,
// makes rank 0 call the roll; 0: rank 1, on the same host, sees rank 0's process gone) ends the
// job with a message naming it, nothing under the output name and no temporary file. mpirun's
// exit status is its own: 128 + the signal of the rank that died.
void expect_a_dead_rank_is_named(int dying, const std::string& signal, int ranks, bool checkpoint) {
  TempDir dir;
  // Case k runs on rank k (equal costs, assigned in order). Case `dying` dies at step 200, a
  // fraction of a second in; the others run 1000 steps.
  std::string yaml =
      "run:\n  seed: 5\n  particles: 20000\n  time_step: {value: 0.02, unit: tau0}\n"
      "  stop: {collisions_per_particle: 40}\n";
  if (checkpoint) yaml += "  checkpoint: {every: {collisions_per_particle: 1}}\n";
  yaml +=
      "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "diagnostics: [temperature]\n"
      "sweep:\n  model:\n";
  for (int k = 0; k < ranks; ++k) {
    if (k == dying)
      yaml += "    dying: {diagnostics: [temperature, {plugin: dies_at_step, step: 200, signal: " + signal + "}]}\n";
    else
      yaml += "    long" + std::to_string(k) + ": {diagnostics: [temperature]}\n";
  }
  yaml += "output: {file: out.h5}\n";
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const auto start = std::chrono::steady_clock::now();
  Process job(mpirun_args(ranks, {"run", pipeline.string(), "--threads", "1", "--plugin-path",
                                  test_plugin("dies_at_step").string()}),
              dir.path(), {}, GDSMC_MPIEXEC);
  const ProcessResult r = job.wait(120);  // a bound against a hang, not a speed test
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(r.timed_out) << r.describe();
  EXPECT_NE(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "dies_at_step: raising SIG" + signal)) << "the rank died as planned\n" << r.err;
  const std::string of = " of " + std::to_string(ranks);
  if (dying == 0) {
    EXPECT_EQ(count_lines(r.err, "gdsmc: rank 1" + of + ": rank 0, which gathers the runs and writes the output, "
                                 "ended without a word"),
              1u)
        << "said once, by the lowest rank on rank 0's host\n" << r.err;
    EXPECT_EQ(occurrences(r.err, "rank 0, which gathers"), 1u) << r.err;
    EXPECT_EQ(count_lines(r.err, "gdsmc: rank 1" + of + ": removed .out.h5.gdsmc-partial-"), 1u) << r.err;
  } else {
    // Rank 0 names the run the rank had started ("while running") or, when the rank died before its
    // word that it started reached rank 0 (a loaded machine), the run it was given ("before it
    // finished"); either way the rank and its run, once.
    const std::string rank = "error: " + pipeline.string() + ": rank " + std::to_string(dying) + of + " ended without a word";
    const std::string run = "run " + std::to_string(dying + 1) + of + " (model=dying)";
    EXPECT_EQ(count_lines(r.err, rank + " while running " + run) + count_lines(r.err, rank + " before it finished " + run),
              1u)
        << r.err;
    EXPECT_EQ(count_lines(r.err, "gdsmc: the run failed; nothing was written"), 1u) << r.err;
  }
  EXPECT_LT(seconds, 60.0) << r.describe();
  std::vector<std::string> expected{};
  if (checkpoint) {
    // Every run's state is kept, the dead rank's as of its last checkpoint, and the message says
    // how to continue.
    EXPECT_TRUE(contains(r.err, "--resume` under mpirun")) << r.err;
    for (int run = 0; run < ranks; ++run) expected.push_back("out.h5.checkpoint/run-" + std::to_string(run));
    expected.push_back("out.h5.checkpoint");
    expected.push_back("out.h5.checkpoint/study");
    std::sort(expected.begin(), expected.end());
  }
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), expected) << "no output file, no temporary file is left\n"
                                                             << r.describe();
}

TEST(Mpi, ARankKilledMidRunEndsTheJobNamingTheRankAndItsRunWithNoOutput) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_a_dead_rank_is_named(1, "KILL", 3, false);
}

TEST(Mpi, ARankThatCrashesMidRunEndsTheJobNamingItAndKeepsTheCheckpoint) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_a_dead_rank_is_named(1, "SEGV", 2, true);
}

TEST(Mpi, RankZeroKilledMidRunIsNamedByARankOnItsHostWhichRemovesItsTemporaryFile) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_a_dead_rank_is_named(0, "KILL", 3, true);
}

TEST(Mpi, ValidateUnderMpirunChecksOnceAndABadPipelineIsReportedOnce) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  TempDir dir;
  const fs::path good = dir.write("good.yaml", kSmallHcsPipeline);
  ProcessResult r = mpirun(2, {"validate", good.string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(count_lines(r.out, good.string() + ": valid"), 1u) << r.out;
  const fs::path bad = dir.write("bad.yaml", replace_once(kSmallHcsPipeline, "alpha: 0.9", "alpha: 1.9"));
  r = mpirun(2, {"run", bad.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_EQ(count_lines(r.err, "error: "), 1u) << "every rank finds the error; rank 0 says it\n" << r.err;
  EXPECT_EQ(dir.entries_except({"good.yaml", "bad.yaml"}), std::vector<std::string>{});
}

}  // namespace
