// One slab run decomposed over the ranks of an MPI job (`mpirun -np K gdsmc run --decompose`,
// engine/decomposition.hpp): the file rank 0 writes holds the same bytes, dataset by dataset and
// attribute by attribute (wall times aside), as the single-process run's, at 2 and 3 ranks
// (oversubscribed on this 2-core machine), with 1 or 2 threads per rank: a channel between a
// diffuse and a Maxwell wall driven by a body force, a Lees-Edwards slab, and a hot slab of thin
// blocks whose particles cross between ranks every step, a gas settling under gravity whose blocks
// are rebalanced, layers sized from the density profile, a mixture, and a forcing that acts on the
// particles. A decomposed job interrupted at 2 ranks
// resumes at 3 to the same bits. Skipped when the host was built without MPI or no mpirun was found.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <regex>
#include <thread>

#include "support/mpi.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

// The rebalancings of the blocks, as rank 0 reports them (-1: no report).
int rebalancings(const std::string& err) {
  std::smatch m;
  const std::regex line(R"(; ([0-9]+) rebalancings\))");
  return std::regex_search(err, m, line) ? std::stoi(m[1]) : -1;
}

// The particles that changed rank per step, as rank 0 reports them.
double migrated_per_step(const std::string& err) {
  std::smatch m;
  const std::regex line(R"(: ([0-9.eE+-]+) particles changed rank per step)");
  return std::regex_search(err, m, line) ? std::stod(m[1]) : -1.0;
}

// The gathers of every particle to rank 0, as rank 0 reports them.
long gathers(const std::string& err) {
  std::smatch m;
  const std::regex line(R"( in ([0-9]+) gather\(s\) of every particle)");
  return std::regex_search(err, m, line) ? std::stol(m[1]) : -1;
}

// The pipeline run serially (--threads 1) and over each of `ranks` ranks with `threads` threads
// each, decomposed: the same file contents. Returns rank 0's stderr of the last job.
std::string expect_decomposed_runs_give_the_serial_bits(const std::string& yaml, std::size_t min_entries,
                                                        const std::vector<std::pair<int, int>>& ranks_threads) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const ProcessResult serial =
      run_gdsmc({"run", pipeline.string(), "-o", "serial.h5", "--threads", "1", "--quiet"}, dir.path(), 300);
  EXPECT_EQ(serial.exit_code, 0) << serial.describe();
  std::string err;
  for (const auto& [ranks, threads] : ranks_threads) {
    const std::string out = "mpi" + std::to_string(ranks) + "x" + std::to_string(threads) + ".h5";
    const ProcessResult mpi = mpirun(ranks, {"run", pipeline.string(), "-o", out, "--threads", std::to_string(threads),
                                             "--decompose"},
                                     dir.path());
    EXPECT_EQ(mpi.exit_code, 0) << mpi.describe();
    EXPECT_TRUE(contains(mpi.err, "decomposed over " + std::to_string(ranks) + " ranks")) << mpi.err;
    EXPECT_EQ(lines_starting(mpi.out, "output: ").size(), 1u) << "the summary is printed once\n" << mpi.out;
    SCOPED_TRACE(out);
    expect_same_contents(dir / "serial.h5", dir / out, min_entries);
    err = mpi.err;
  }
  return err;
}

const char* const kChannel =
    "run:\n  seed: 11\n  particles: 20000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 4}\n"
    "  sample_every: 2\n  record_every: 20\n"
    "system:\n  mean_free_path: 10\n  temperature: 1.0\n  domain: slab\n  box: {y: {value: 200, unit: sigma}}\n"
    "  layers: 40\n  bins: 30\n"
    "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
    "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 0.005, unit: reduced}}\n"
    "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
    "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.7}\n"
    "diagnostics:\n  - {plugin: poiseuille_channel, steady_window: 100, min_time: 200}\n  - energy_balance\n"
    "  - wall_fluxes\n  - profiles\n"
    "output: {file: out.h5, particles: true}\n";

TEST(MpiSlab, AChannelWithADiffuseAndAMaxwellWallAndABodyForceHasTheSerialBitsAtTwoAndThreeRanks) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  const std::string err = expect_decomposed_runs_give_the_serial_bits(kChannel, 60, {{2, 1}, {3, 1}, {2, 2}});
  // Its diagnostics read the host's shared moments and bin sums, no particle (MomentsRead): the
  // particles are gathered once, for the output and the diagnostics' finish. Its 30 sampling bins
  // cut its 40 layers, so bins straddle the blocks' boundaries.
  EXPECT_EQ(gathers(err), 1) << err;
}

TEST(MpiSlab, ALeesEdwardsSlabHasTheSerialBitsAtTwoAndThreeRanks) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  const std::string err = expect_decomposed_runs_give_the_serial_bits(
      "run:\n  seed: 5\n  particles: 8000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 3}\n  moments_every: 4\n  sample_every: 4\n  record_every: 40\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 30\n"
      "initial_state: {plugin: maxwellian}\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 4}\n"
      "diagnostics:\n  - collision_count\n  - {plugin: local_equilibrium_clock, sample_every: 1}\n"
      "  - slab_averages\n  - shear_rheology\n  - energy_balance\n"
      "output: {file: out.h5, particles: true}\n",
      40, {{2, 1}, {3, 1}});
  EXPECT_EQ(gathers(err), 1) << "no diagnostic here reads particles: one gather, at the end\n" << err;
}

// Three layers a rank and a gas so hot for its step that a particle flies about half a block per
// step: particles cross between ranks at every step (and across the Lees-Edwards seam).
TEST(MpiSlab, ParticlesCrossingBetweenRanksEveryStepKeepTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  const std::string err = expect_decomposed_runs_give_the_serial_bits(
      "run:\n  seed: 8\n  particles: 6000\n  time_step: {value: 0.1, unit: tau0}\n  stop: {time: 4}\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 1.0}\n  layers: 9\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 1}\n"
      "diagnostics: [slab_averages, energy_balance, {plugin: velocity_marginals, sample_every: 10, record_every: 20}]\n"
      "output: {file: out.h5, particles: true}\n",
      20, {{3, 1}});
  // velocity_marginals reads the particles: they are gathered for both sides of its bracketed pairs
  // at steps 10, 20, 30 and 40, and once at the end (the initial record is taken before the run is
  // decomposed, while every rank holds the whole state).
  EXPECT_EQ(gathers(err), 9) << err;
  // mean |v_y| dt / block = sqrt(2 T / pi m) 0.1 tau0 / (Ly / 3): of 6000 particles, about 1/4 cross
  // a block boundary in a step; 40 steps.
  EXPECT_GT(migrated_per_step(err), 500.0) << err;
}

// The channel with two species: light (m = 1, sigma = 1) and heavy (m = 3, sigma = 1.5).
const char* const kMixtureChannel =
    "run:\n  seed: 12\n  particles: 20000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 3}\n"
    "  sample_every: 2\n  record_every: 20\n"
    "system:\n  mean_free_path: 10\n  temperature: 1.0\n  domain: slab\n  box: {y: {value: 200, unit: sigma}}\n"
    "  layers: 40\n  species:\n    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
    "    - {name: heavy, mass: 3, diameter: 1.5, fraction: 0.5}\n"
    "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
    "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 0.005, unit: reduced}}\n"
    "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
    "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.7}\n"
    "diagnostics: [species_moments, energy_balance, wall_fluxes]\n"
    "output: {file: out.h5, particles: true}\n";

// A forcing that acts on the particles (the drag of the equivalent elastic model): rank 0 applies it
// to the gathered particles and sends each rank its particles back.
TEST(MpiSlab, AForcingThatActsOnTheParticlesHasTheSerialBitsAtTwoRanks) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_decomposed_runs_give_the_serial_bits(
      kDragSlabPipeline,
      20, {{2, 1}});
}

// A mixture of two species in a channel: species columns migrate, and each pair class's majorant
// and remainder and each species' layer moments come from the layer's owner.
TEST(MpiSlab, AMixtureChannelHasTheSerialBitsAtTwoAndThreeRanks) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_decomposed_runs_give_the_serial_bits(kMixtureChannel, 40, {{2, 1}, {3, 1}});
}

// Layers sized from the density profile at the end of the transient (system.layers): rank 0 sets
// them on the gathered particles, and every rank takes its new layers.
TEST(MpiSlab, LayersSizedFromTheDensityProfileHaveTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  std::string yaml = kChannel;
  yaml.replace(yaml.find("  layers: 40\n"), 13, "  layers: {mean_free_paths: 0.5, after: 2}\n");
  const std::string err = expect_decomposed_runs_give_the_serial_bits(yaml, 60, {{2, 1}, {3, 1}});
  EXPECT_TRUE(contains(err, "layers")) << err;
}

// A gas settling under an acceleration along y piles up at the top wall: the blocks, equal in
// particles at the start, are moved to follow the cost, and the bits stay the serial ones.
TEST(MpiSlab, BlocksRebalancedAsAGasSettlesKeepTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  const std::string err = expect_decomposed_runs_give_the_serial_bits(
      "run:\n  seed: 21\n  particles: 20000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 6}\n"
      "  record_every: 50\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 4.0}\n  layers: 24\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.95}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: 0.5, axis: y}\n"
      "boundaries:\n  y: {plugin: specular_wall}\n"
      "diagnostics: [slab_averages, energy_balance, profiles]\n"
      "output: {file: out.h5, particles: true}\n",
      30, {{3, 1}});
  EXPECT_GE(rebalancings(err), 1) << err;
}

// A plugin that throws on one rank (a diagnostic's finish(), on rank 0 which runs the diagnostics)
// ends the job at once: exit status not 0, that rank's message, and nothing left in the directory.
TEST(MpiSlab, ARunThatThrowsOnARankEndsTheJobWithItsMessageAndNoOutput) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  TempDir dir;
  std::string yaml = kChannel;
  yaml.replace(yaml.find("  - energy_balance\n"), 19, "  - energy_balance\n  - failing_finish\n");
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const ProcessResult r = mpirun(2, {"run", pipeline.string(), "--threads", "1", "--decompose", "--plugin-path",
                                     test_plugin("failing_finish").string()},
                                 dir.path());
  EXPECT_NE(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "gdsmc: rank 0 of 2: error: ")) << r.err;
  EXPECT_TRUE(contains(r.err, "deliberate failure at the end of the run")) << r.err;
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{})
      << "no output file, no temporary file, no lock is left";
}

// `yaml` (without run.checkpoint) run serially, and decomposed at 2 ranks, SIGTERMed once a state
// is saved, resumed at 3: the same file.
void expect_an_interrupted_decomposed_job_to_resume(std::string yaml, const std::string& stop, std::size_t min_entries) {
  TempDir dir;
  yaml.replace(yaml.find(stop), stop.size(),
               "stop: {time: 40}\n  checkpoint: {every: {collisions_per_particle: 0.2}}");
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const ProcessResult serial =
      run_gdsmc({"run", pipeline.string(), "-o", "serial.h5", "--threads", "1", "--quiet"}, dir.path(), 300);
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  Process job(mpirun_args(2, {"run", pipeline.string(), "-o", "out.h5", "--threads", "1", "--quiet", "--decompose"}),
              dir.path(), {}, GDSMC_MPIEXEC);
  const fs::path run = dir / "out.h5.checkpoint" / "run-0";
  const auto t0 = std::chrono::steady_clock::now();
  while (!job.ended() && !fs::exists(run) && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 60)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_FALSE(job.ended()) << "the job ended before it could be interrupted\n" << job.wait().describe();
  job.send(SIGTERM);
  const ProcessResult stopped = job.wait(60);
  EXPECT_NE(stopped.exit_code, 0) << stopped.describe();
  EXPECT_FALSE(fs::exists(dir / "out.h5")) << "an interrupted job writes nothing under the output name";
  ASSERT_TRUE(fs::exists(run)) << stopped.describe();
  const ProcessResult resumed =
      mpirun(3, {"run", pipeline.string(), "-o", "out.h5", "--threads", "1", "--resume", "--decompose"}, dir.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.describe();
  EXPECT_TRUE(contains(resumed.err, "gdsmc: resuming from ")) << resumed.err;
  expect_same_contents(dir / "serial.h5", dir / "out.h5", min_entries);
}

TEST(MpiSlab, ADecomposedJobInterruptedAtTwoRanksResumesAtThreeRanksToTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_an_interrupted_decomposed_job_to_resume(kChannel, "stop: {time: 4}", 60);
}

// A mixture's state holds its species' layer moments (the majorants' scales): rank 0 writes the
// shared ones.
TEST(MpiSlab, AnInterruptedDecomposedMixtureResumesToTheSerialBits) {
  if (const std::string why = why_no_mpi(); !why.empty()) GTEST_SKIP() << why;
  expect_an_interrupted_decomposed_job_to_resume(kMixtureChannel, "stop: {time: 3}", 40);
}

}  // namespace
