// Limits of the input, checked before anything runs: the memory a study needs is estimated and a
// study that cannot fit is refused with the figures (running out anyway says so); a pipeline file
// is a small regular file; a sweep's cases are loaded in linear time, and a problem of a sweep value
// is reported once, at its entry in the sweep, naming the cases it occurs in.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <string>
#include <vector>

#include "engine/cells.hpp"
#include "engine/engine.hpp"
#include "engine/particle_store.hpp"
#include "engine/memory_estimate.hpp"
#include "study/cases.hpp"
#include "test_support.hpp"
#include "util/text.hpp"

namespace gdsmc::test {
namespace {

// "FILE:LINE:COLUMN" of the first occurrence of `needle` in `text` (1-based, as gdsmc reports).
std::string location(const fs::path& file, const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) throw std::runtime_error("test bug: '" + needle + "' not in the pipeline");
  const auto line_start = text.rfind('\n', at);
  const std::size_t column = at - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
  const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n')) + 1;
  return file.string() + ":" + std::to_string(line) + ":" + std::to_string(column);
}

// gdsmc ARGS in `cwd` under an address-space limit of `kib` KiB (stdout and stderr together).
ShellResult under_limit(const fs::path& cwd, const std::string& kib, const std::vector<std::string>& args) {
  std::string command = "cd \"" + cwd.string() + "\" && bash -c 'ulimit -v " + kib + " && exec \"" + executable().string() + "\"";
  for (const auto& a : args) command += " \"" + a + "\"";
  return shell(command + "'");
}

// ---------------------------------------------------------------------------------------------
// Memory

// The particle arrays: one of a huge page (2 MiB) or more starts on a huge page, so the kernel can
// back it with them (huge_page_allocator.hpp); smaller ones and growth across the threshold keep
// their values, and the store's span shows the arrays it allocated.
TEST(MemoryCheck, ParticleArraysOfAHugePageOrMoreStartOnOneAndKeepTheirValuesAcrossGrowth) {
  host::ParticleStore store;
  const std::size_t n = host::kHugePage / sizeof(std::uint32_t) + 1000;  // every array over 2 MiB
  store.allocate(n, {}, false);
  const ParticleSpan span = store.span();
  for (const double* a : {span.vx.data, span.vy.data, span.vz.data})
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a) % host::kHugePage, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(span.id) % host::kHugePage, 0u);
  EXPECT_EQ(span.id[n - 1], n - 1);
  EXPECT_EQ(span.x.data, nullptr);  // a homogeneous store has no positions
  host::ParticleArray<double> grown;
  for (std::size_t k = 0; k < 2 * n; ++k) grown.push_back(static_cast<double>(k));  // through both allocation paths
  for (std::size_t k = 0; k < 2 * n; k += 4099) ASSERT_EQ(grown[k], static_cast<double>(k));
  grown.resize(10);
  grown.shrink_to_fit();
  EXPECT_EQ(grown[9], 9.0);
}

// The engine keeps a reference to its pipeline, so a temporary one does not compile.
static_assert(!std::is_constructible_v<host::Engine, host::Pipeline>);
static_assert(!std::is_constructible_v<host::Engine, host::Pipeline, std::uint32_t, unsigned>);
static_assert(std::is_constructible_v<host::Engine, const host::Pipeline&, std::uint32_t, unsigned>);

// 4e9 particles need 104 GiB: refused at run.particles with the estimate, what drives it, the
// memory available and how many particles would fit, by validate and run alike (no std::bad_alloc,
// nothing written), under an address-space limit and without one.
TEST(MemoryCheck, AStudyThatCannotFitIsRefusedWithTheEstimateAndTheMemoryAvailable) {
  TempDir dir;
  const std::string yaml = replace_once(kSmallHcsPipeline, "particles: 400", "particles: 4000000000");
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const std::string at = location(file, yaml, "4000000000") + ": run.particles: this run needs about 104 GiB of memory";
  for (const char* command : {"validate", "run"}) {
    const ShellResult limited = under_limit(dir.path(), "1000000", {command, file.string()});
    EXPECT_EQ(limited.status, 1) << command << "\n" << limited.out;
    EXPECT_TRUE(contains(limited.out, at)) << command << "\n" << limited.out;
    EXPECT_TRUE(contains(limited.out, "4000000000 particles x 28 bytes = 104 GiB")) << limited.out;
    EXPECT_TRUE(contains(limited.out, "is available (the address-space limit (ulimit -v) 977 MiB less ")) << limited.out;
    EXPECT_TRUE(contains(limited.out, "particles fit")) << limited.out;
    EXPECT_FALSE(contains(limited.out, "bad_alloc")) << limited.out;
  }
  const ProcessResult r = run_gdsmc({"run", file.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, at)) << r.describe();
  EXPECT_TRUE(contains(r.err, "is available (MemAvailable")) << r.describe();
  EXPECT_EQ(dir.files(), std::vector<std::string>{"pipeline.yaml"});
}

TEST(MemoryCheck, TheVerdictOfValidateGivesTheEstimate) {
  TempDir dir;
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline);
  const ProcessResult r = run_gdsmc({"validate", file.string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const host::Pipeline p = load_yaml(dir, kSmallHcsPipeline);
  const auto estimate = host::study_memory({host::case_memory(p, host::setup_layout(p))});
  EXPECT_GT(estimate.bytes, 400.0 * 28);
  EXPECT_TRUE(contains(r.out, "; about " + host::bytes_text(estimate.bytes) + " of memory)")) << r.out;
}

// The arithmetic of the estimate: 28 bytes per particle in a homogeneous system (velocities and
// 32-bit identity; +8 per attribute component), 64 in a slab (+ positions, layer index, layer lists,
// reordering scratch), each diagnostic's records over the steps to the stop, the realizations' copies, and what
// each sweep case keeps until the file is written.
TEST(MemoryCheck, TheEstimateCountsParticlesAttributesRecordsRealizationsAndKeptCases) {
  TempDir dir;
  const host::Pipeline p = load_yaml(dir, kSmallHcsPipeline);
  const host::RunLayout layout = host::setup_layout(p);
  ASSERT_EQ(layout.values_per_record.size(), 1u);
  EXPECT_GE(layout.values_per_record[0], 3u);  // time, s and at least the temperature
  EXPECT_EQ(layout.attribute_values, 0u);
  const host::CaseMemory m = host::case_memory(p, layout);
  EXPECT_EQ(m.bytes_per_particle, 28);
  EXPECT_EQ(m.steps, 89);  // s = 1 at dt/sqrt(pi) = 0.0113 a step of dt = 0.02 tau0
  EXPECT_EQ(m.records_bytes, 91.0 * static_cast<double>(layout.values_per_record[0]) * 8);  // + initial and final records
  EXPECT_EQ(m.setup_bytes, 0);  // the plugins' own allocations, counted from 1 MiB on
  EXPECT_EQ(m.peak, 400 * 28 + 4 * m.records_bytes);  // the running records up to twice their size
  EXPECT_EQ(m.kept, m.records_bytes);

  host::RunLayout declared{3, {10}};
  const host::CaseMemory a = host::case_memory(p, declared);
  EXPECT_EQ(a.bytes_per_particle, 28 + 3 * 8);
  EXPECT_EQ(a.records_bytes, 91.0 * 10 * 8);

  const host::Pipeline k = load_yaml(dir, kSmallHcsPipeline, {"run.realizations=3", "output.realizations=true", "run.record_every=5"});
  const host::CaseMemory r = host::case_memory(k, declared);
  EXPECT_EQ(r.records_bytes, (89 / 5 + 2) * 10.0 * 8);
  EXPECT_EQ(r.peak, 400 * 52 + 6 * r.records_bytes);  // three realizations, the running one (twice), the first output
  EXPECT_EQ(r.kept, (2 + 3) * r.records_bytes);       // mean and error, and each realization's own

  const host::Pipeline slab = load_yaml(dir, kSmallHcsPipeline + "boundaries: {y: periodic}\n",
                                        {"system={density: 1.0e-3, domain: slab, box: {y: 2}, layers: 4}"});
  // 64 bytes, and the sort's 4 layer counts per block of 16384 particles.
  EXPECT_EQ(host::case_memory(slab, host::setup_layout(slab)).bytes_per_particle,
            64 + 4.0 * 4 / host::CellGrid::kSortBlock);

  // Cases run one after another; each keeps its records until the file is written.
  host::CaseMemory small{}, big{};
  small.peak = 100, small.kept = 10;
  big.peak = 1000, big.kept = 50;
  const auto e = host::study_memory({small, small, big, small});
  EXPECT_EQ(e.peak_case, 2u);
  EXPECT_EQ(e.kept_before, 20);
  EXPECT_EQ(e.bytes, 1020);
}

// validate estimates the particles but never allocates them: 1e7 particles (about 305 MiB) are
// checked with a peak resident size of a few tens of MiB.
TEST(MemoryCheck, ValidateNeverHoldsTheParticlesItEstimates) {
  TempDir dir;
  const fs::path file = dir.write("pipeline.yaml", replace_once(kSmallHcsPipeline, "particles: 400", "particles: 10000000"));
  const std::string out = (dir / "verdict").string();
  host::SubprocessOptions options;
  options.stdout_file = out;
  options.unset_environment = {"GDSMC_PLUGIN_PATH"};
  host::Subprocess validate({executable().string(), "validate", file.string()}, options);
  ASSERT_EQ(validate.wait().exit_code, 0) << read_text(out);
  EXPECT_TRUE(contains(read_text(out), "about 267 MiB of memory")) << read_text(out);
  EXPECT_LT(validate.usage().ru_maxrss, 200 * 1024) << "KiB resident at the peak";
}

// 1e7 particles (about 570 MiB, which fits) under a 1 GB address-space limit: validate passes,
// because it only builds the plugin objects (4e9 would not fit and is refused with the estimate:
// AStudyThatCannotFitIsRefusedWithTheEstimateAndTheMemoryAvailable).
TEST(MemoryCheck, ValidateDoesNotAllocateParticles) {
  TempDir dir;
  std::string yaml = kSmallHcsPipeline;
  yaml.replace(yaml.find("particles: 400"), 14, "particles: 10000000");
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const ShellResult r = shell("bash -c 'ulimit -v 1000000 && exec \"" + executable().string() + "\" validate \"" +
                              file.string() + "\"'");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "10000000 particles")) << r.out;
}

// Memory a plugin takes for itself is not in the estimate: when it runs out anyway, the error says
// that memory ran out and gives the estimate, in validate (begin) and during a run (record).
TEST(MemoryCheck, RunningOutOfMemoryAnywaySaysSoWithTheEstimate) {
  TempDir dir;
  const fs::path file = dir.write("pipeline.yaml", replace_once(kSmallHcsPipeline, "[temperature]", "[temperature, memory_hog]"));
  const std::string hog = test_plugin("memory_hog").string();
  const ProcessResult run = run_gdsmc({"run", file.string(), "--quiet", "--plugin-path", hog}, dir.path());
  EXPECT_EQ(run.exit_code, 1) << run.describe();
  EXPECT_TRUE(contains(run.err, "memory ran out")) << run.describe();
  EXPECT_TRUE(contains(run.err, "the estimate was about")) << run.describe();
  EXPECT_TRUE(contains(run.err, "400 particles x 28 bytes")) << run.describe();
  EXPECT_FALSE(contains(run.err, "bad_alloc")) << run.describe();
  EXPECT_EQ(dir.files(), std::vector<std::string>{"pipeline.yaml"});

  const ProcessResult validate = run_gdsmc(
      {"validate", file.string(), "--plugin-path", hog, "--set", "diagnostics[1]={plugin: memory_hog, at: begin}"}, dir.path());
  EXPECT_EQ(validate.exit_code, 1) << validate.describe();
  EXPECT_TRUE(contains(validate.err, "plugin 'memory_hog'")) << validate.describe();
  EXPECT_TRUE(contains(validate.err, "memory ran out")) << validate.describe();
  EXPECT_FALSE(contains(validate.err, "bad_alloc")) << validate.describe();
}

// ---------------------------------------------------------------------------------------------
// The pipeline file

TEST(PipelineFile, ADevicePipeOrHugeFileIsRefusedBeforeItIsRead) {
  TempDir dir;
  // /dev/zero would be read until memory runs out; a FIFO without a writer would block in open().
  const ProcessResult zero = run_gdsmc({"validate", "/dev/zero"}, dir.path(), 20);
  EXPECT_EQ(zero.exit_code, 1) << zero.describe();
  EXPECT_TRUE(contains(zero.err, "/dev/zero: cannot read the pipeline file (it is a character device, not a regular "
                                 "file; a pipeline is a YAML text file of at most 16 MiB)"))
      << zero.describe();
  const fs::path fifo = dir / "fifo.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const ProcessResult pipe = run_gdsmc({"validate", fifo.string()}, dir.path(), 20);
  EXPECT_EQ(pipe.exit_code, 1) << pipe.describe();
  EXPECT_TRUE(contains(pipe.err, fifo.string() + ": cannot read the pipeline file (it is a pipe")) << pipe.describe();
  // One byte over the limit (a YAML comment: it would parse).
  const fs::path huge = dir.write("huge.yaml", std::string((16u << 20) + 1, '#'));
  const ProcessResult big = run_gdsmc({"validate", huge.string()}, dir.path(), 20);
  EXPECT_EQ(big.exit_code, 1) << big.describe();
  EXPECT_TRUE(contains(big.err, huge.string() + ": cannot read the pipeline file (it is 16 MiB (16777217 bytes); a "
                                                "pipeline file is at most 16 MiB)"))
      << big.describe();
}

// ---------------------------------------------------------------------------------------------
// Sweeps

// alpha = 1.5 is out of range in the three cases that have it: one error, at the sweep entry of
// 1.5, naming those cases; not three errors phrased as a --set the user never gave.
TEST(SweepErrors, AProblemOfASweepValueIsReportedOnceAtItsEntryWithItsCases) {
  TempDir dir;
  const std::string yaml = kSmallHcsPipeline + "sweep:\n  collision.alpha: [0.5, 1.5]\n  run.seed: [1, 2, 3]\n";
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const ProcessResult r = run_gdsmc({"validate", file.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  const auto errors = lines_starting(r.err, "error: ");
  ASSERT_EQ(errors.size(), 1u) << r.describe();
  EXPECT_EQ(errors[0].rfind("error: " + location(file, yaml, "1.5]") + ": collision.alpha: ", 0), 0u) << errors[0];
  EXPECT_TRUE(contains(errors[0], "[0, 1]")) << errors[0];
  EXPECT_TRUE(contains(errors[0], "; in the 3 sweep cases with collision.alpha=1.5 (of 6)")) << errors[0];
  EXPECT_FALSE(contains(r.err, "--set")) << r.describe();

  // A sweep value that cannot be applied is located at its entry too (here, each value its own):
  // run.seed is a single value, so it has no key 'x'.
  const std::string scalar = kSmallHcsPipeline + "sweep:\n  run.seed.x: [2, 4]\n";
  const fs::path second = dir.write("scalar.yaml", scalar);
  const ProcessResult s = run_gdsmc({"validate", second.string()}, dir.path());
  EXPECT_EQ(s.exit_code, 1) << s.describe();
  const auto lines = lines_starting(s.err, "error: ");
  ASSERT_EQ(lines.size(), 2u) << s.describe();
  EXPECT_EQ(lines[0], "error: " + location(second, scalar, "2, 4]") +
                          ": sweep value run.seed.x=2: run.seed is a single value ('3'), "
                          "not a mapping, so it has no key 'x'; in sweep case 0 (run.seed.x=2)");
  EXPECT_EQ(lines[1].rfind("error: " + location(second, scalar, "4]") + ": sweep value run.seed.x=4", 0), 0u)
      << lines[1];

  // A plugin entry given by its name alone takes keys: "- temperature" becomes
  // {plugin: temperature} when a sweep value (or a --set) sets one inside it.
  const std::string named = kSmallHcsPipeline + "sweep:\n  diagnostics.0.record_every: [2, 4]\n";
  const fs::path third = dir.write("named.yaml", named);
  const ProcessResult n = run_gdsmc({"validate", third.string()}, dir.path());
  EXPECT_EQ(n.exit_code, 0) << n.describe();
  EXPECT_TRUE(contains(n.out, "valid (2 cases")) << n.describe();
  const ProcessResult set = run_gdsmc({"validate", file.string(), "--set", "collision.alpha=0.5", "--set",
                                       "diagnostics[0].record_every=5", "--set", "sweep={run.seed: [1]}"},
                                      dir.path());
  EXPECT_EQ(set.exit_code, 0) << set.describe();
}

// 2000 cases (50 x 40) are validated. Expansion is linear by construction: the pipeline file is
// read once (it may be gone by the time the cases are loaded), and the cases do not each hold a
// copy of the file, whose sweep grows with the number of cases.
TEST(SweepExpansion, TwoThousandCasesAreLoadedFromOneReadingOfTheFile) {
  TempDir dir;
  std::string alphas, seeds;
  for (int k = 0; k < 50; ++k) alphas += (k ? ", " : "") + std::to_string(0.5 + 0.01 * k).substr(0, 4);
  for (int k = 0; k < 40; ++k) seeds += (k ? ", " : "") + std::to_string(k + 1);
  const std::string yaml = kSmallHcsPipeline + "sweep:\n  collision.alpha: [" + alphas + "]\n  run.seed: [" + seeds + "]\n";
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const ProcessResult r = run_gdsmc({"validate", file.string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.out, "valid (2000 cases x 1 realization;")) << r.out;

  const host::LoadedPipeline loaded = load_study(dir, yaml, {"run.particles=300"}, "gone.yaml");
  const host::Pipeline& base = loaded.pipeline;
  fs::remove(dir / "gone.yaml");
  const auto cases = host::expand_cases(loaded);
  ASSERT_EQ(cases.size(), 2000u);
  EXPECT_EQ(cases[1999].label, "collision.alpha=0.99, run.seed=40");
  EXPECT_EQ(cases[1999].pipeline.collision.params.real("alpha"), 0.99);
  EXPECT_EQ(cases[1999].pipeline.seed, 40u);
  EXPECT_EQ(cases[1999].pipeline.particles, 300u);  // the --set applies to every case
  // The study's provenance: the file as read, as resolved with the --set, and the --set itself.
  EXPECT_EQ(cases[0].pipeline.source_text, base.source_text);
  EXPECT_EQ(cases[0].pipeline.resolved_text, base.resolved_text);
  EXPECT_EQ(cases[0].pipeline.overrides, std::vector<std::string>{"run.particles=300"});
  for (std::size_t c = 1; c < cases.size(); ++c) ASSERT_TRUE(cases[c].pipeline.source_text.empty()) << c;
}

}  // namespace
}  // namespace gdsmc::test
