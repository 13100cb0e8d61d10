// Checkpoints (run.checkpoint, `gdsmc run --resume`): a run killed with SIGKILL at any moment and
// resumed, as many times as it takes, writes the file the uninterrupted run writes: every dataset
// and attribute the same bytes but the wall times. Three random kill points per pipeline (a
// homogeneous run in sub-populations, a slab between walls with a body force and the particles
// written, a Lees-Edwards sweep with realizations on two runs at once); the kill times are drawn
// afresh each time and printed with a failure. A SIGINT saves the state and says how to resume;
// a checkpoint of another pipeline, gdsmc or plugin version is refused naming what differs, and a
// fresh run refuses to start over an existing checkpoint.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <random>
#include <sstream>
#include <thread>

#include "test_support.hpp"
#include "util/content_hash.hpp"

namespace {

using namespace gdsmc::test;
using Clock = std::chrono::steady_clock;

bool has_checkpoint(const TempDir& dir) { return fs::exists(dir / "out.h5.checkpoint" / "study"); }

// Runs `yaml` once uninterrupted (out_ref.h5) and once killed with SIGKILL at three random moments,
// resumed after each kill (with --resume when a checkpoint exists, as a user would), and compares.
void expect_kill_and_resume_gives_the_same_bits(const std::string& yaml, const std::vector<std::string>& extra,
                                                std::size_t min_entries) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  auto args = [&](const std::string& out, bool resume) {
    std::vector<std::string> a{"run", pipeline.string(), "--quiet", "-o", out};
    a.insert(a.end(), extra.begin(), extra.end());
    if (resume) a.push_back("--resume");
    return a;
  };
  const auto start = Clock::now();
  const ProcessResult ref = run_gdsmc(args("out_ref.h5", false), dir.path(), 300);
  ASSERT_EQ(ref.exit_code, 0) << ref.describe();
  double duration = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_FALSE(fs::exists(dir / "out_ref.h5.checkpoint")) << "the checkpoint is removed once the output is written";

  std::mt19937_64 rng(std::random_device{}());
  std::ostringstream trace;
  trace << "uninterrupted run " << duration << " s; kills at";
  int kills = 0, resumed_from_state = 0, early = 0;
  bool done = false;
  for (int k = 0; k < 3 && !done; ++k) {
    // The first kill within the middle half of the run (so that some state has been saved), the
    // others anywhere in a run's duration: before the first checkpoint, during a write, during the
    // final write of the output.
    const double at = k == 0 ? std::uniform_real_distribution<double>(0.25 * duration, 0.75 * duration)(rng)
                             : std::uniform_real_distribution<double>(0.0, duration)(rng);
    trace << " " << at << " s" << (has_checkpoint(dir) ? " (resumed)" : " (fresh)");
    resumed_from_state += has_checkpoint(dir) ? 1 : 0;
    Process p(args("out.h5", has_checkpoint(dir)), dir.path());
    const auto t0 = Clock::now();
    while (!p.ended() && std::chrono::duration<double>(Clock::now() - t0).count() < at)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (!p.ended()) {
      p.send(SIGKILL);
      ++kills;
    }
    const double ran = std::chrono::duration<double>(Clock::now() - t0).count();
    const ProcessResult r = p.wait(300);
    if (r.signal == SIGKILL) continue;
    ASSERT_EQ(r.exit_code, 0) << trace.str() << "\n" << r.describe();
    if (kills == 0 && early < 5) {
      // It finished before the first kill: the shared machine ran it faster than the uninterrupted
      // run it was timed on. Time the kills on this run instead and start again from nothing.
      trace << " (ended first, after " << ran << " s)";
      duration = ran;
      fs::remove(dir / "out.h5");
      ++early;
      --k;
      continue;
    }
    done = true;  // it finished before a later kill
  }
  SCOPED_TRACE(trace.str());
  if (!done) {
    const bool resume = has_checkpoint(dir);
    resumed_from_state += resume ? 1 : 0;
    const ProcessResult r = run_gdsmc(args("out.h5", resume), dir.path(), 300);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }
  EXPECT_GE(kills, 1) << "no kill landed while the run was under way";
  EXPECT_GE(resumed_from_state, 1) << "no run resumed from a saved state";
  EXPECT_FALSE(fs::exists(dir / "out.h5.checkpoint"));

  const auto expected = h5::contents(dir / "out_ref.h5"), got = h5::contents(dir / "out.h5");
  EXPECT_GE(expected.size(), min_entries);
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [key, bytes] : expected) {
    auto it = got.find(key);
    ASSERT_NE(it, got.end()) << key << " missing after the kills";
    EXPECT_TRUE(it->second == bytes) << key << " differs after kill and resume";
  }
}

const std::string kHomogeneous =
    "run:\n  seed: 5\n  particles: 100000\n  subpopulation: 20000\n"
    "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
    "  stop: {collisions_per_particle: 20}\n  record_every: 15\n  sample_every: 5\n"
    "  average_after: {collisions_per_particle: 3}\n"
    "  checkpoint: {every: {collisions_per_particle: 0.4}}\n"
    "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
    "collision: {plugin: inelastic_hard_spheres, alpha: 0.7}\n"
    "diagnostics: [temperature, cumulants, hcs_theory, cooling_rate, velocity_marginals]\n"
    "output: {file: out.h5}\n";

TEST(Checkpoint, AHomogeneousRunKilledThreeTimesAndResumedIsTheSameBits) {
  expect_kill_and_resume_gives_the_same_bits(kHomogeneous, {"--threads", "2"}, 40);
}

// A homogeneous system of one group whose sheared tails raise its uniform majorant, so that it
// switches to weighted pairs (run.pair_selection auto; the choice follows the saved majorant, and
// the weighted time counter's credit is the saved remainder).
TEST(Checkpoint, AShearedOneGroupRunDrawingWeightedPairsKilledAndResumedIsTheSameBits) {
  expect_kill_and_resume_gives_the_same_bits(
      "run:\n  seed: 8\n  particles: 10000\n"
      "  time_step: {value: 0.002, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 30}\n  record_every: 40\n  sample_every: 4\n"
      "  average_after: {collisions_per_particle: 10}\n"
      "  checkpoint: {every: {collisions_per_particle: 0.5}}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: {plugin: local_equilibrium, shear_rate: 4}\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.5}\n"
      "forcings: [{plugin: uniform_shear, shear_rate: 4}]\n"
      "diagnostics: [temperature, shear_rheology, collision_count]\n"
      "output: {file: out.h5}\n",
      {}, 20);
}

TEST(Checkpoint, ASlabBetweenWallsKilledThreeTimesAndResumedIsTheSameBits) {
  expect_kill_and_resume_gives_the_same_bits(
      "run:\n  seed: 11\n  particles: 30000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 16}\n"
      "  record_every: 20\n  average_after: {time: 4}\n  checkpoint: {every: {collisions_per_particle: 0.3}}\n"
      "system:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
      "  box: {y: {value: 1860, unit: sigma}}\n  layers: 40\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
      "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
      "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
      "diagnostics: [slab_averages, energy_balance, profiles, wall_fluxes]\n"
      "output: {file: out.h5, particles: true}\n",
      {"--threads", "2"}, 20);
}

// A mixture (two species, weighted pairs per pair of species in the layers, per-species wall
// tallies and species column): its class remainders, majorant scales and species travel too.
TEST(Checkpoint, ASlabMixtureKilledThreeTimesAndResumedIsTheSameBits) {
  expect_kill_and_resume_gives_the_same_bits(
      "run:\n  seed: 13\n  particles: 30000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 14}\n"
      "  record_every: 20\n  average_after: {time: 4}\n  checkpoint: {every: {collisions_per_particle: 0.3}}\n"
      "system:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
      "  box: {y: {value: 1860, unit: sigma}}\n  layers: 40\n  species:\n"
      "    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
      "    - {name: heavy, mass: 3, diameter: 1.4, fraction: 0.5}\n"
      "initial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
      "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
      "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
      "diagnostics: [energy_balance, species_moments, wall_fluxes]\n"
      "output: {file: out.h5, particles: true}\n",
      {"--threads", "2"}, 40);
}

TEST(Checkpoint, ALeesEdwardsSweepWithRealizationsKilledThreeTimesAndResumedIsTheSameBits) {
  expect_kill_and_resume_gives_the_same_bits(
      "run:\n  seed: 2001\n  particles: 10000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 5}\n  record_every: 40\n  realizations: 3\n"
      "  checkpoint: {every: 0.3 s}\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 20\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 4}\n"
      "diagnostics: [slab_averages, shear_rheology]\n"
      "sweep:\n  collision.alpha: [0.7, 0.9]\noutput: {file: out.h5, realizations: true}\n",
      {"--threads", "2"}, 20);
}

// Replaces `from` by `to` (same length) inside a binary file.
void patch(const fs::path& file, const std::string& from, const std::string& to) {
  ASSERT_EQ(from.size(), to.size());
  std::string bytes = read_text(file);
  const auto at = bytes.find(from);
  ASSERT_NE(at, std::string::npos) << "'" << from << "' not in " << file;
  bytes.replace(at, from.size(), to);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

// Recomputes the checksum table of a checkpoint file whose entries were changed on purpose (a
// forgery: what another gdsmc or plugin version would have written), so that the checks behind
// the checksums are reached.
void reseal(const fs::path& file) {
  std::string bytes = read_text(file);
  ASSERT_GE(bytes.size(), 32u);
  std::uint64_t count = 0, data = 0;
  std::memcpy(&count, bytes.data() + bytes.size() - 32, 8);
  std::memcpy(&data, bytes.data() + bytes.size() - 24, 8);
  ASSERT_EQ(data + 8 * count + 32, bytes.size());
  std::vector<std::uint64_t> sums;
  for (std::size_t at = 0; at < data;) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + at, 4);
    std::uint64_t n = 0;
    std::memcpy(&n, bytes.data() + at + 4 + length + 2, 8);
    const std::size_t end = at + 4 + length + 10 + n * static_cast<unsigned char>(bytes[at + 4 + length + 1]);
    gdsmc::host::ContentHash h;
    h.update(bytes.data() + at, end - at);
    sums.push_back(h.finish());
    at = end;
  }
  ASSERT_EQ(sums.size(), count);
  std::memcpy(bytes.data() + data, sums.data(), 8 * count);
  gdsmc::host::ContentHash table;
  table.update(bytes.data() + data, 8 * count + 16);
  const std::uint64_t t = table.finish();
  std::memcpy(bytes.data() + bytes.size() - 16, &t, 8);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

// The byte offset of the first value of entry `name` in a checkpoint file.
std::size_t payload_of(const std::string& bytes, const std::string& name) {
  std::string framed(4, '\0');
  const auto length = static_cast<std::uint32_t>(name.size());
  std::memcpy(framed.data(), &length, 4);
  framed += name;
  const auto at = bytes.find(framed);
  return at == std::string::npos ? std::string::npos : at + framed.size() + 10;
}

// Runs `pipeline` until its first run has saved a state, then interrupts it (SIGINT: exit 130,
// the checkpoint kept).
void interrupt_after_first_checkpoint(const TempDir& dir, const std::vector<std::string>& run) {
  Process p(run, dir.path());
  ASSERT_TRUE(p.wait_until_catches(SIGINT));
  const auto t0 = Clock::now();
  while (!fs::exists(dir / "out.h5.checkpoint" / "run-0") && std::chrono::duration<double>(Clock::now() - t0).count() < 60)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  p.send(SIGINT);
  const ProcessResult r = p.wait(120);
  ASSERT_EQ(r.exit_code, 130) << r.describe();
  ASSERT_TRUE(fs::exists(dir / "out.h5.checkpoint" / "run-0"));
}

TEST(Checkpoint, SigintSavesTheStateAndAForeignCheckpointIsRefusedNamingWhatDiffers) {
  TempDir dir;
  const std::string yaml = replace_once(kHomogeneous, "collisions_per_particle: 20", "collisions_per_particle: 60");
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  const std::vector<std::string> run{"run", pipeline.string(), "-o", "out.h5", "--threads", "2"};
  {
    Process p(run, dir.path());
    ASSERT_TRUE(p.wait_until_catches(SIGINT));
    const auto t0 = Clock::now();  // until the first runs have saved a state
    while (!has_checkpoint(dir) && std::chrono::duration<double>(Clock::now() - t0).count() < 60)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    p.send(SIGINT);
    const ProcessResult r = p.wait(120);
    ASSERT_EQ(r.exit_code, 130) << r.describe();
    EXPECT_TRUE(contains(r.err, "saved its state in out.h5.checkpoint")) << r.err;
    EXPECT_TRUE(contains(r.err, "--resume")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.h5"));
  }
  ASSERT_TRUE(fs::exists(dir / "out.h5.checkpoint" / "run-0"));

  // Not over it: a fresh run refuses; another pipeline text refuses, naming the line.
  ProcessResult r = run_gdsmc(run, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "holds the checkpoint of an earlier run")) << r.err;
  r = run_gdsmc({"validate", pipeline.string(), "-o", "out.h5"}, dir.path());  // validate says so too
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "so `run` would refuse to start over it")) << r.err;
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume", "--set", "collision.alpha=0.8"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "belongs to another run")) << r.err;
  EXPECT_TRUE(contains(r.err, "alpha: 0.8")) << r.err;
  // Another gdsmc version, another plugin version: both named. The study file is copied aside and
  // restored after.
  const fs::path study = dir / "out.h5.checkpoint" / "study";
  const std::string original = read_text(study);
  patch(study, gdsmc::version_string, std::string(gdsmc::version_string).replace(0, 1, "9"));
  patch(study, "diagnostics[0]: temperature 1.", "diagnostics[0]: temperature 9.");
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume"}, dir.path());  // as it is: damaged
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "the checkpoint out.h5.checkpoint is damaged: out.h5.checkpoint/study is damaged: entry "))
      << r.err;
  reseal(study);  // as another gdsmc would have written it
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "written by gdsmc 9")) << r.err;
  EXPECT_TRUE(contains(r.err, "the checkpoint has diagnostics[0]: temperature 9.")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
  std::ofstream(study, std::ios::binary | std::ios::trunc) << original;
  // A damaged run file is refused with its name (and nothing is written).
  const fs::path run0 = dir / "out.h5.checkpoint" / "run-0";
  const std::string state = read_text(run0);
  std::ofstream(run0, std::ios::binary | std::ios::trunc) << state.substr(0, state.size() / 2);
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume", "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "run-0")) << r.err;
  EXPECT_TRUE(contains(r.err, "truncated")) << r.err;
  // validate --resume reads every run file as run --resume does, and refuses it too.
  r = run_gdsmc({"validate", pipeline.string(), "-o", "out.h5", "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "the checkpoint out.h5.checkpoint is damaged: out.h5.checkpoint/run-0 is truncated")) << r.err;
  EXPECT_TRUE(contains(r.err, "Remove out.h5.checkpoint/run-0 to run that run again from its start")) << r.err;
  std::ofstream(run0, std::ios::binary | std::ios::trunc) << state;

  // validate --resume says what the checkpoint holds; the resumed run gives the uninterrupted bits.
  r = run_gdsmc({"validate", pipeline.string(), "-o", "out.h5", "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.out, "a checkpoint of this pipeline (1 run: 0 finished, 1 under way (at t = ")) << r.out;
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume", "--quiet", "--threads", "1"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_FALSE(fs::exists(dir / "out.h5.checkpoint"));
  r = run_gdsmc({"run", pipeline.string(), "-o", "ref.h5", "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto expected = h5::contents(dir / "ref.h5"), got = h5::contents(dir / "out.h5");
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [key, bytes] : expected) EXPECT_TRUE(got.at(key) == bytes) << key;
}

// A checkpoint that cannot be written (here: a file size limit below the state's size, as a full
// disk would) is a warning: the run goes on, its output is complete, no partial file is left.
TEST(Checkpoint, ACheckpointThatCannotBeWrittenIsAWarningAndTheRunGoesOn) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", kHomogeneous);  // a state of 100000 x 28 bytes
  const ShellResult r = shell("cd '" + dir.path().string() + "' && ulimit -f 1024 && exec '" + executable().string() +
                              "' run pipeline.yaml --quiet --threads 1 --set run.stop.collisions_per_particle=2");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "warning: checkpoint out.h5.checkpoint/run-0 not written: cannot write")) << r.out;
  EXPECT_TRUE(contains(r.out, "File too large; the run goes on")) << r.out;
  EXPECT_TRUE(fs::exists(dir / "out.h5"));
  EXPECT_FALSE(fs::exists(dir / "out.h5.checkpoint"));
}

TEST(Checkpoint, BadCheckpointSettingsAreRefusedWithTheValidForms) {
  TempDir dir;
  for (const auto& [value, words] : std::vector<std::pair<std::string, std::string>>{
           {"{every: 10 minutes}", "not a wall time"},
           {"{every: -5 s}", "not a wall time"},
           {"{every: {collisions_per_particle: 0}}", "must be > 0"},
           {"{often: yes}", "expected {every: WALL_TIME}"}}) {
    const fs::path pipeline =
        dir.write("p.yaml", replace_once(kHomogeneous, "checkpoint: {every: {collisions_per_particle: 0.4}}", "checkpoint: " + value));
    const ProcessResult r = run_gdsmc({"validate", pipeline.string()}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << value << "\n" << r.describe();
    EXPECT_TRUE(contains(r.err, "run.checkpoint")) << r.err;
    EXPECT_TRUE(contains(r.err, words)) << value << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "p.yaml:")) << r.err;
  }
  // --resume without a checkpoint.
  const fs::path pipeline = dir.write("q.yaml", kHomogeneous);
  const ProcessResult r = run_gdsmc({"run", pipeline.string(), "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "nothing to resume: there is no checkpoint at out.h5.checkpoint and no output out.h5"))
      << r.err;
}

// --resume tells apart a finished run (its output complete: nothing to do, exit 0), nothing to
// resume (no checkpoint, exit 1) and a damaged checkpoint (exit 1, naming the file).
TEST(Checkpoint, ResumeSaysFinishedNothingToResumeOrDamaged) {
  TempDir dir;
  const fs::path pipeline =
      dir.write("p.yaml", replace_once(kSmallHcsPipeline, "  stop:", "  checkpoint: {every: 1 h}\n  stop:"));
  ProcessResult r = run_gdsmc({"run", pipeline.string(), "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  ASSERT_FALSE(fs::exists(dir / "out.h5.checkpoint"));
  for (const std::string command : {"run", "validate"}) {
    r = run_gdsmc({command, pipeline.string(), "--resume"}, dir.path());
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.describe();
    EXPECT_TRUE(contains(r.err, "--resume: finished: out.h5 is the complete output of this pipeline")) << r.err;
    EXPECT_TRUE(contains(r.err, "nothing to resume")) << r.err;
  }
  // Another pipeline's output is not "finished".
  r = run_gdsmc({"run", pipeline.string(), "--resume", "--set", "run.seed=99"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "nothing to resume: there is no checkpoint at out.h5.checkpoint, and out.h5 is the output "
                              "of another pipeline"))
      << r.err;
  fs::remove(dir / "out.h5");
  r = run_gdsmc({"run", pipeline.string(), "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "nothing to resume: there is no checkpoint at out.h5.checkpoint and no output out.h5 (a run "
                              "writes a checkpoint there when its pipeline sets run.checkpoint)"))
      << r.err;
  r = run_gdsmc({"run", dir.write("q.yaml", kSmallHcsPipeline).string(), "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "which this one does not")) << r.err;
  // A checkpoint directory without its study file: damaged, not "nothing".
  fs::create_directory(dir / "out.h5.checkpoint");
  std::ofstream(dir / "out.h5.checkpoint" / "run-0") << "state";
  r = run_gdsmc({"run", pipeline.string(), "--resume"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "the checkpoint out.h5.checkpoint is damaged: it holds run files but not "
                              "out.h5.checkpoint/study"))
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
}

// A flipped bit in a saved particle velocity is refused at --resume (and by validate --resume)
// naming the file and the entry; before the checksums it resumed with exit 0 and another output.
TEST(Checkpoint, AFlippedBitInASavedVelocityIsRefusedNamingTheFileAndTheEntry) {
  TempDir dir;
  const std::string yaml = replace_once(kHomogeneous, "collisions_per_particle: 20", "collisions_per_particle: 60");
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  interrupt_after_first_checkpoint(dir, {"run", pipeline.string(), "-o", "out.h5", "--threads", "2", "--quiet"});
  const fs::path run0 = dir / "out.h5.checkpoint" / "run-0";
  const std::string state = read_text(run0);
  const std::size_t vx = payload_of(state, "particles.vx");
  ASSERT_NE(vx, std::string::npos);
  for (const std::size_t at : {vx + 8 * 777 + 3, payload_of(state, "engine.clocks") + 5}) {
    std::string flipped = state;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x10);
    std::ofstream(run0, std::ios::binary | std::ios::trunc) << flipped;
    const std::string entry = at > vx ? "'particles.vx'" : "'engine.clocks'";
    for (const std::string command : {"run", "validate"}) {
      const ProcessResult r = run_gdsmc({command, pipeline.string(), "-o", "out.h5", "--resume", "--quiet"}, dir.path());
      EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.describe();
      EXPECT_TRUE(contains(r.err, "the checkpoint out.h5.checkpoint is damaged: out.h5.checkpoint/run-0 is damaged: entry "))
          << r.err;
      EXPECT_TRUE(contains(r.err, entry + " (bytes ")) << r.err;
      EXPECT_TRUE(contains(r.err, "does not match its checksum")) << r.err;
      EXPECT_FALSE(fs::exists(dir / "out.h5"));
    }
  }
  // A damaged table of checksums, a run file in another run's place: refused too.
  std::string table = state;
  table[table.size() - 20] = static_cast<char>(table[table.size() - 20] ^ 1);
  std::ofstream(run0, std::ios::binary | std::ios::trunc) << table;
  ProcessResult r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume", "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "out.h5.checkpoint/run-0 is damaged")) << r.err;
  std::ofstream(run0, std::ios::binary | std::ios::trunc) << state;
  r = run_gdsmc({"run", pipeline.string(), "-o", "out.h5", "--resume", "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << "the file as it was resumes\n" << r.describe();
}

// A plugin library rebuilt with the same version string is another plugin: its content hash is
// recorded in the output's provenance and in the checkpoint, and a resume with another content is
// refused naming the plugin and both hashes.
TEST(Checkpoint, APluginLibraryWhoseContentChangedIsRefusedAtResume) {
  TempDir dir;
  fs::create_directory(dir / "mine");
  const fs::path copy = dir / "mine" / "gdsmc_temperature.so";
  fs::copy_file(plugin_dir() / "gdsmc_temperature.so", copy);
  const std::string before = gdsmc::host::ContentHash::hex(gdsmc::host::file_content_hash(copy));
  const std::string yaml = replace_once(kHomogeneous, "collisions_per_particle: 20", "collisions_per_particle: 60") +
                           "plugins: [mine]\n";
  const fs::path pipeline = dir.write("pipeline.yaml", yaml);
  // The output records each library's content hash.
  ProcessResult r = run_gdsmc({"run", pipeline.string(), "-o", "ref.h5", "--quiet", "--set", "run.particles=2000", "--set",
                               "run.subpopulation=1000", "--set", "run.stop.collisions_per_particle=4"},
                              dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  {
    h5::File out(dir / "ref.h5");
    EXPECT_EQ(h5::read_string_attribute(out.id(), "/plugins/diagnostics[0]", "library"), copy.string());
    EXPECT_EQ(h5::read_string_attribute(out.id(), "/plugins/diagnostics[0]", "library_hash"), before);
    EXPECT_EQ(h5::read_string_attribute(out.id(), "/plugins/collision", "library_hash"),
              gdsmc::host::ContentHash::hex(gdsmc::host::file_content_hash(plugin_dir() / "gdsmc_inelastic_hard_spheres.so")));
  }
  interrupt_after_first_checkpoint(dir, {"run", pipeline.string(), "-o", "out.h5", "--threads", "2", "--quiet"});
  // "Rebuilt": other bytes, the same plugin name and version (a loadable library still).
  std::ofstream(copy, std::ios::binary | std::ios::app) << std::string(64, 'x');
  const std::string after = gdsmc::host::ContentHash::hex(gdsmc::host::file_content_hash(copy));
  ASSERT_NE(before, after);
  for (const std::string command : {"run", "validate"}) {
    r = run_gdsmc({command, pipeline.string(), "-o", "out.h5", "--resume", "--quiet"}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.describe();
    EXPECT_TRUE(contains(r.err, "belongs to another run")) << r.err;
    EXPECT_TRUE(contains(r.err, "plugin 'diagnostics[0]' (temperature ")) << r.err;
    EXPECT_TRUE(contains(r.err, copy.string() + ") is not the library that wrote the checkpoint: its content hash is " +
                                    after + ", the checkpoint's " + before))
        << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
}

// When the output cannot be written at the end of a checkpointed study, the message says which
// runs' results the checkpoint keeps and which will run again (here: the final checkpoint of the
// run that records every step was larger than the file size limit, that of the other one not).
TEST(Checkpoint, AFailedOutputWriteSaysWhichRunsAreKeptAndWhichRunAgain) {
  TempDir dir;
  const fs::path pipeline = dir.write(
      "pipeline.yaml",
      "run:\n  seed: 5\n  particles: 2000\n  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 20}\n  record_every: 1\n  checkpoint: {every: {collisions_per_particle: 0.4}}\n"
      "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.7}\ndiagnostics: [temperature, velocity_marginals]\n"
      "sweep: {run.record_every: [1000, 1]}\noutput: {file: out.h5}\n");
  // dash's ulimit -f counts 512-byte blocks: 100 KiB.
  const ShellResult r = shell("cd '" + dir.path().string() + "' && ulimit -f 200 && exec '" + executable().string() +
                              "' run pipeline.yaml --quiet --threads 1");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "gdsmc: error: cannot write out.h5: File too large")) << r.out;
  EXPECT_TRUE(contains(r.out, "the results of 1 of the 2 runs are kept in out.h5.checkpoint (run-0); run-1 will run again "
                              "at --resume (its final checkpoint was not written), from its last saved state"))
      << r.out;
  EXPECT_FALSE(contains(r.out, "every run's results are kept")) << r.out;
  // And so it does: --resume writes the file.
  const ProcessResult resumed = run_gdsmc({"run", "pipeline.yaml", "--resume"}, dir.path());
  EXPECT_EQ(resumed.exit_code, 0) << resumed.describe();
  EXPECT_TRUE(contains(resumed.err, "(2 runs: 1 finished, 1 under way")) << resumed.err;
  EXPECT_TRUE(fs::exists(dir / "out.h5"));
}

// validate checks the checkpoint directory's name as run would create it: an output name that
// fits the file system but whose ".checkpoint" directory does not is refused by both.
TEST(Checkpoint, ACheckpointDirectoryNameTooLongIsRefusedByValidate) {
  TempDir dir;
  const fs::path pipeline = dir.write("pipeline.yaml", kHomogeneous);
  const std::string name = std::string(250, 'o') + ".h5";  // 253 bytes; its checkpoint directory 264
  for (const std::string command : {"validate", "run"}) {
    const ProcessResult r = run_gdsmc({command, pipeline.string(), "-o", name, "--quiet"}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.describe();
    EXPECT_TRUE(contains(r.err, "the checkpoint directory this run creates (run.checkpoint)")) << r.err;
    EXPECT_TRUE(contains(r.err, "is 264 bytes long")) << r.err;
    EXPECT_TRUE(contains(r.err, "give the output a name of at most 244 bytes")) << r.err;
  }
  const fs::path plain =
      dir.write("plain.yaml", replace_once(kHomogeneous, "  checkpoint: {every: {collisions_per_particle: 0.4}}\n", ""));
  const ProcessResult ok = run_gdsmc({"validate", plain.string(), "-o", name}, dir.path());
  EXPECT_EQ(ok.exit_code, 0) << "without checkpoints the name is fine\n" << ok.describe();
}

}  // namespace
