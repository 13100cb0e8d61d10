// `gdsmc run --decompose` in one process (a decomposition over one rank, without mpirun): the file
// has the single-process run's bytes (wall times aside), which checks the decomposed run's own
// paths (order keys, gathered particles for the forcings and diagnostics, shared layer sums) on
// any machine; and what a decomposed run does not serve yet is refused before anything runs,
// naming it. The runs over several ranks are tests/framework/study/mpi_slab_test.cpp.
#include <gtest/gtest.h>

#include "support/mpi.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

void expect_the_serial_bits(const std::string& yaml, std::size_t min_entries) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const ProcessResult serial =
      run_gdsmc({"run", pipeline.string(), "-o", "serial.h5", "--threads", "1", "--quiet"}, dir.path(), 300);
  ASSERT_EQ(serial.exit_code, 0) << serial.describe();
  const ProcessResult one =
      run_gdsmc({"run", pipeline.string(), "-o", "one.h5", "--threads", "2", "--decompose"}, dir.path(), 300);
  ASSERT_EQ(one.exit_code, 0) << one.describe();
  EXPECT_TRUE(contains(one.err, "decomposed over 1 rank (")) << one.err;
  expect_same_contents(dir / "serial.h5", dir / "one.h5", min_entries);
}

// The bracketed diagnostics (the default run.sampling) sample before the collision stage on steps
// where the layers' member lists would otherwise be written by that stage: the decomposed run
// sorts the gathered particles afresh, so a stale list in the single-process run shows here.
TEST(DecomposedRun, ALeesEdwardsSlabWithBracketedSamplingHasTheSerialBitsOnOneRank) {
  expect_the_serial_bits(
      "run:\n  seed: 5\n  particles: 20000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 3}\n  moments_every: 4\n  sample_every: 2\n  record_every: 40\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 30\n"
      "initial_state: {plugin: maxwellian}\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 4}\n"
      "diagnostics: [collision_count, slab_averages, shear_rheology, pressure_tensor, energy_balance]\n"
      "output: {file: out.h5, particles: true}\n",
      40);
}

// A forcing that acts on the particles (the drag of the equivalent elastic model) runs on the
// gathered particles, whose velocities go back to their ranks.
TEST(DecomposedRun, AForcingThatActsOnTheParticlesHasTheSerialBitsOnOneRank) {
  expect_the_serial_bits(
      kDragSlabPipeline,
      20);
}

const char* const kSlab =
    "run: {seed: 1, particles: 2000, time_step: {value: 0.01, unit: tau0}, stop: {time: 0.1}}\n"
    "system: {density: 1.0e-3, domain: slab, box: {y: 2.0}, layers: 8}\n"
    "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
    "boundaries: {y: {plugin: specular_wall}}\ndiagnostics: [temperature]\n";

// A mixture: the species travel with their particles, each pair class's majorant and remainder
// and each species' layer moments come from the layer's owner.
TEST(DecomposedRun, AMixtureChannelHasTheSerialBitsOnOneRank) {
  expect_the_serial_bits(
      "run:\n  seed: 4\n  particles: 8000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 2}\n"
      "  sample_every: 2\n  record_every: 20\n"
      "system:\n  mean_free_path: 10\n  temperature: 1.0\n  domain: slab\n  box: {y: {value: 200, unit: sigma}}\n"
      "  layers: 20\n  species:\n    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
      "    - {name: heavy, mass: 3, diameter: 1.5, fraction: 0.5}\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 0.005, unit: reduced}}\n"
      "boundaries:\n  y: {plugin: diffuse_wall, temperature: 1.0}\n"
      "diagnostics: [species_moments, energy_balance]\n"
      "output: {file: out.h5, particles: true}\n",
      20);
}

TEST(DecomposedRun, WhatIsNotDecomposedYetIsRefusedBeforeAnythingRunsNamingIt) {
  const Refusal homogeneous =
      refuse("run: {seed: 1, particles: 2000, time_step: {value: 0.01, unit: tau0}, stop: {time: 0.1}}\n"
             "system: {density: 1.0e-3}\ninitial_state: maxwellian\n"
             "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\ndiagnostics: [temperature]\n",
             {"--decompose"});
  EXPECT_TRUE(contains(homogeneous.result.err, "--decompose: a homogeneous system has one collision cell"))
      << homogeneous.result.err;
  EXPECT_TRUE(contains(homogeneous.result.err, "run it without --decompose")) << homogeneous.result.err;
}

}  // namespace
