// Runs at once (run.threads, --threads): the cases and realizations of a study run on a pool of
// workers, and the output does not depend on how many. Each run is a pure function of (case,
// realization) and the outputs are gathered in case order, so every dataset and every attribute
// but the wall times must be the same bytes for 1, 2 and 3 threads: a homogeneous sweep with
// realizations, a slab between walls, and Lees-Edwards boundaries. A single run uses the threads
// itself (collision groups, mover blocks, moment sums), with the same bits. A failing run ends the study
// with its own error, naming its case, and nothing is written.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "engine/work_pool.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

// Run `yaml` with --threads 1, 2 and 3 and expect the same contents each time.
void expect_same_bits_for_any_thread_count(const std::string& yaml, std::size_t min_datasets) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  std::map<std::string, std::string> first;
  for (const char* threads : {"1", "2", "3"}) {
    const std::string out = std::string("out") + threads + ".h5";
    const ProcessResult r = run_gdsmc({"run", pipeline.string(), "--quiet", "--threads", threads, "-o", out}, dir.path(), 300);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    const auto c = h5::contents(dir / out);
    if (first.empty()) {
      first = c;
      EXPECT_GE(first.size(), min_datasets);
      continue;
    }
    ASSERT_EQ(c.size(), first.size()) << threads << " threads";
    for (const auto& [key, bytes] : first) {
      auto it = c.find(key);
      ASSERT_NE(it, c.end()) << key << " missing with " << threads << " threads";
      EXPECT_TRUE(it->second == bytes) << key << " differs with " << threads << " threads";
    }
  }
}

TEST(Threads, HomogeneousSweepWithRealizationsIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 7\n  particles: 3000\n  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 6}\n  record_every: 20\n  realizations: 3\n"
      "  average_after: {collisions_per_particle: 2}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "diagnostics: [temperature, cumulants, pressure_tensor]\n"
      "sweep:\n  collision.alpha: [0.5, 0.9]\noutput: {file: out.h5, realizations: true}\n",
      40);
}

TEST(Threads, SlabBetweenDiffuseWallsIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 11\n  particles: 4000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 6}\n"
      "  record_every: 20\nsystem:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
      "  box: {y: {value: 1860, unit: sigma}}\n  layers: 40\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
      "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
      "diagnostics: [slab_averages, energy_balance]\n"
      "sweep:\n  collision.alpha: [0.7, 0.9, 1.0]\noutput: {file: out.h5, particles: true}\n",
      20);
}

TEST(Threads, LeesEdwardsSlabWithRealizationsIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 2001\n  particles: 2000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 3}\n  record_every: 40\n  realizations: 3\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 20\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 4}\n"
      "diagnostics: [slab_averages, shear_rheology]\noutput: {file: out.h5}\n",
      10);
}

// Threads inside one run (each system below is large enough for a run to use them: at least two
// sub-populations, or a slab of at least 16384 particles): a single run with --threads 2 or 3
// spreads its collision groups, the mover's blocks of 16384 particles (with their layer counts for
// the sort) and the moment sums over the threads, and must give the bits of one thread. A
// homogeneous run in 12 sub-populations (with the particles written, and a shear forcing), a slab
// of 2 mover blocks between walls with a body force, a Lees-Edwards slab.
TEST(Threads, OneHomogeneousRunInSubpopulationsIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 17\n  particles: 6000\n  subpopulation: 500\n"
      "  time_step: {value: 0.004, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 4}\n  record_every: 20\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: local_equilibrium\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
      "forcings: [{plugin: uniform_shear, shear_rate: 2}]\n"
      "diagnostics: [temperature, cumulants, pressure_tensor, collision_count]\n"
      "output: {file: out.h5, particles: true}\n",
      15);
}

TEST(Threads, OneSlabRunBetweenWallsIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 12\n  particles: 20000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 3}\n"
      "  record_every: 20\nsystem:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
      "  box: {y: {value: 1860, unit: sigma}}\n  layers: 40\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
      "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
      "diagnostics: [slab_averages, energy_balance, profiles]\n"
      "output: {file: out.h5, particles: true}\n",
      20);
}

TEST(Threads, OneLeesEdwardsRunIsTheSameBitsForOneTwoAndThreeThreads) {
  expect_same_bits_for_any_thread_count(
      "run:\n  seed: 2002\n  particles: 18000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 1}\n  record_every: 40\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 20\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 4}\n"
      "diagnostics: [slab_averages, shear_rheology]\noutput: {file: out.h5}\n",
      10);
}

// Case 1 of 3 fails in its diagnostic's finish(); with two workers the study stops, reports that
// run's own error (not the interruption of the others) and writes nothing.
TEST(Threads, AFailingRunEndsTheStudyWithItsOwnErrorAndWritesNothing) {
  TempDir dir;
  const fs::path plugins = dir / "plugins";
  fs::create_directories(plugins);
  fs::copy_file(test_plugin("failing_finish"), plugins / "gdsmc_failing_finish.so");
  const fs::path pipeline = dir.write(
      "p.yaml",
      "run: {seed: 3, particles: 2000, time_step: 0.01, stop: {collisions_per_particle: 2}}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\ndiagnostics: [temperature]\n"
      "sweep:\n  variant:\n    a: {}\n    b: {diagnostics: [temperature, failing_finish]}\n    c: {}\n"
      "output: {file: out.h5}\n");
  const ProcessResult r =
      run_gdsmc({"run", pipeline.string(), "--quiet", "--threads", "2", "--plugin-path", plugins.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "deliberate failure")) << r.err;
  EXPECT_FALSE(contains(r.err, "interrupted")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
}

TEST(Threads, ThreadCountsOutsideTheirRangeAreRefusedWithTheValidRange) {
  TempDir dir;
  const fs::path pipeline = dir.write(
      "p.yaml",
      "run: {particles: 100, time_step: 0.01, stop: {time: 0.1}, threads: -2}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\noutput: {file: out.h5}\n");
  ProcessResult r = run_gdsmc({"validate", pipeline.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "run.threads")) << r.err;
  EXPECT_TRUE(contains(r.err, "0 (every core)")) << r.err;
  r = run_gdsmc({"run", pipeline.string(), "--threads", "two"}, dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_TRUE(contains(r.err, "--threads needs a whole number")) << r.err;
}

}  // namespace

// The pool itself: many short stages in a row (workers spin between them, WorkPool::kSpinSeconds),
// stages far apart (workers asleep), an exception from a piece, and destruction right after a
// stage. Every piece must run exactly once per stage, and the lowest throwing piece's error reach
// the caller.
TEST(WorkPool, EveryPieceRunsOnceInShortAndSpacedStagesAndTheLowestErrorIsRethrown) {
  gdsmc::host::WorkPool pool(3);
  std::vector<std::atomic<int>> ran(64);
  for (int stage = 0; stage < 20000; ++stage) {
    const std::size_t count = 1 + static_cast<std::size_t>(stage % 64);
    pool.run(count, [&](std::size_t k) { ran[k].fetch_add(1, std::memory_order_relaxed); });
    if (stage % 5000 == 4999) std::this_thread::sleep_for(std::chrono::milliseconds(5));  // workers fall asleep
  }
  for (std::size_t k = 0; k < ran.size(); ++k) {
    int expected = 0;
    for (int stage = 0; stage < 20000; ++stage) expected += k < 1 + static_cast<std::size_t>(stage % 64);
    EXPECT_EQ(ran[k].load(), expected) << "piece " << k;
  }
  try {
    pool.run(40, [&](std::size_t k) {
      if (k == 7 || k == 30) throw std::runtime_error("piece " + std::to_string(k));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "piece 7");
  }
  std::atomic<int> after{0};
  pool.run(10, [&](std::size_t) { after.fetch_add(1); });  // the pool works after an error
  EXPECT_EQ(after.load(), 10);
}

// run_beside: the pieces run on the workers only, each once, while the caller keeps calling its
// own task (the study's main thread polls the interrupt and the MPI exchange, which only it may
// call); a piece's exception comes back to the caller.
TEST(WorkPool, RunBesideKeepsTheCallerOffThePiecesAndCallsItsTaskWhileTheyRun) {
  gdsmc::host::WorkPool pool(3);
  const std::thread::id caller = std::this_thread::get_id();
  std::vector<std::atomic<int>> runs(7);
  std::atomic<int> on_caller{0};
  int beside = 0;
  pool.run_beside(
      runs.size(),
      [&](std::size_t k) {
        if (std::this_thread::get_id() == caller) ++on_caller;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        ++runs[k];
      },
      [&] { ++beside; }, std::chrono::milliseconds(1));
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  EXPECT_EQ(on_caller.load(), 0);
  EXPECT_GE(beside, 1);  // 7 pieces of 10 ms on 2 workers: 40 ms or more of 1 ms periods
  EXPECT_THROW(pool.run_beside(
                   3, [](std::size_t k) { if (k == 1) throw std::runtime_error("piece 1"); }, [] {},
                   std::chrono::milliseconds(1)),
               std::runtime_error);
  // The caller's task throws: no further piece starts, and its exception comes back once the pieces
  // begun have returned (200 pieces of 5 ms on 2 workers would take 0.5 s).
  std::atomic<int> started{0};
  EXPECT_THROW(pool.run_beside(
                   200,
                   [&](std::size_t) {
                     ++started;
                     std::this_thread::sleep_for(std::chrono::milliseconds(5));
                   },
                   [] { throw std::runtime_error("beside"); }, std::chrono::milliseconds(1)),
               std::runtime_error);
  EXPECT_LT(started.load(), 200);
  gdsmc::host::WorkPool alone(1);
  EXPECT_THROW(alone.run_beside(1, [](std::size_t) {}, [] {}, std::chrono::milliseconds(1)), std::logic_error);
}
