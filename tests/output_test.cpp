// The HDF5 file of a run: layout, units, provenance; and that a failed or interrupted run leaves
// no file under the final name.
#include <gtest/gtest.h>

#include <signal.h>

#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string pipeline_yaml(const std::string& diagnostics, const std::string& stop = "{collisions_per_particle: 3}",
                          const std::string& output = "out.h5", int particles = 500, double alpha = 0.8) {
  return "run:\n"
         "  seed: 99\n"
         "  particles: " + std::to_string(particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n"
         "  sample_every: 5\n"
         "  record_every: 10\n"
         "system:\n"
         "  density: 1.0e-3\n"
         "  temperature: 1.0\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}\n"
         "diagnostics:\n" + diagnostics +
         "output: {file: " + output + "}\n";
}

const std::string kDiagnostics =
    "  - {plugin: collision_count}\n"
    "  - {plugin: temperature}\n"
    "  - {plugin: pressure_tensor}\n"
    "  - {plugin: cumulants, record_every: 7}\n"
    "  - {plugin: hcs_theory, average_after: 1}\n";

TEST(Output, ShortRunFileLayout) {
  TempDir dir;
  const std::string yaml = pipeline_yaml(kDiagnostics);
  const auto file = dir.write("pipeline.yaml", yaml);
  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  ASSERT_EQ(dir.files(), (std::vector<std::string>{"out.h5", "pipeline.yaml"}));

  // The same pipeline in-process tells which names are series (one value per record).
  TempDir dir2;
  const gdsmc::host::Pipeline p = load_yaml(dir2, yaml);
  gdsmc::host::Engine engine(p);
  engine.run();
  ASSERT_EQ(engine.diagnostics().size(), 5u);

  h5::File h(dir / "out.h5");
  const hid_t f = h.id();
  EXPECT_GE(h5::read_number_attribute(f, "/run", "collisions_per_particle"), 3.0);
  for (const auto& d : engine.diagnostics()) {
    const std::string g = "/diagnostics/" + d.group();
    SCOPED_TRACE(g);
    ASSERT_TRUE(h5::is_dataset(f, g + "/time"));
    ASSERT_TRUE(h5::is_dataset(f, g + "/collisions_per_particle"));
    const auto time = h5::read_doubles(f, g + "/time");
    const auto s = h5::read_doubles(f, g + "/collisions_per_particle");
    EXPECT_EQ(h5::shape(f, g + "/time").size(), 1u);
    ASSERT_GE(time.size(), 3u);  // the initial record, at least one more, the final one
    EXPECT_EQ(s.size(), time.size());
    EXPECT_EQ(time.front(), 0.0);
    EXPECT_EQ(s.front(), 0.0);
    for (std::size_t k = 1; k < time.size(); ++k) {
      EXPECT_GT(time[k], time[k - 1]) << k;
      EXPECT_GE(s[k], s[k - 1]) << k;
    }
    // Each record is the mean over its window's samples; the last window ends at the final state.
    EXPECT_GT(s.back(), 2.0);
    EXPECT_LE(s.back(), h5::read_number_attribute(f, "/run", "collisions_per_particle"));
    EXPECT_LE(time.back(), h5::read_number_attribute(f, "/run", "final_time_tau0"));
    ASSERT_FALSE(d.columns.empty());
    for (const auto& c : d.columns) {
      ASSERT_TRUE(h5::is_dataset(f, g + "/" + c.name)) << c.name;
      EXPECT_EQ(h5::shape(f, g + "/" + c.name), std::vector<hsize_t>{time.size()}) << c.name;
    }
  }
  // Different record intervals give different lengths (so the check above compares real lengths).
  EXPECT_NE(h5::read_doubles(f, "/diagnostics/cumulants/time").size(),
            h5::read_doubles(f, "/diagnostics/temperature/time").size());

  // Every dataset carries its unit.
  const auto all = h5::datasets(f);
  ASSERT_GE(all.size(), 25u);
  for (const auto& name : all) EXPECT_TRUE(h5::has_attribute(f, name, "unit")) << name << " has no 'unit'";
  EXPECT_EQ(h5::read_string_attribute(f, "/diagnostics/temperature/time", "unit"), "tau0");
  EXPECT_EQ(h5::read_string_attribute(f, "/diagnostics/temperature/temperature", "unit"), "T0");

  // Root provenance.
  EXPECT_EQ(h5::read_string_attribute(f, "/", "gdsmc_version"), gdsmc::version_string);
  EXPECT_EQ(h5::read_string_attribute(f, "/", "sdk_abi"),
            std::to_string(gdsmc::sdk_abi_major) + "." + std::to_string(gdsmc::sdk_abi_minor));
  const std::string pipeline = h5::read_string_attribute(f, "/", "pipeline");
  EXPECT_TRUE(contains(pipeline, "inelastic_hard_spheres")) << pipeline;
  EXPECT_TRUE(contains(pipeline, "hcs_theory")) << pipeline;
  EXPECT_EQ(h5::read_number_attribute(f, "/", "seed"), 99.0);

  // /plugins/<role>: which plugin (and version) played each role.
  gdsmc::host::PluginRegistry reg;
  reg.add(plugin_dir());
  auto check_role = [&](const std::string& role, const std::string& plugin) {
    const std::string g = "/plugins/" + role;
    ASSERT_TRUE(h5::exists(f, g)) << g;
    EXPECT_EQ(h5::read_string_attribute(f, g, "plugin"), plugin) << g;
    ASSERT_NE(reg.find(plugin), nullptr) << plugin;
    EXPECT_EQ(h5::read_string_attribute(f, g, "version"), reg.find(plugin)->descriptor->version) << g;
  };
  check_role("initial_state", "maxwellian");
  check_role("collision", "inelastic_hard_spheres");
  const std::vector<std::string> diagnostics = {"collision_count", "temperature", "pressure_tensor", "cumulants",
                                                "hcs_theory"};
  // Diagnostics are listed by their position in the pipeline.
  std::vector<std::string> roles = h5::members(f, "/plugins");
  for (std::size_t k = 0; k < diagnostics.size(); ++k) check_role("diagnostics[" + std::to_string(k) + "]", diagnostics[k]);
  EXPECT_EQ(roles.size(), 2 + diagnostics.size()) << join(roles);
}

// A diagnostic that throws in finish(): exit 1, the plugin named, and no file under the final
// name (nor a partial one).
TEST(Output, FailedRunLeavesNoFile) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml("  - {plugin: temperature}\n  - {plugin: failing_finish}\n"));
  const ProcessResult r =
      run_gdsmc({"run", file.string(), "--quiet", "--plugin-path", test_plugin("failing_finish").string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "failing_finish")) << r.describe();
  EXPECT_TRUE(contains(r.err, "deliberate failure at the end of the run")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

TEST(Output, MissingOutputDirectoryIsRefused) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", pipeline_yaml("  - {plugin: temperature}\n", "{collisions_per_particle: 3}",
                                                             "no_such_dir/out.h5"));
  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "no_such_dir")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  // --output into a missing directory too.
  const ProcessResult r2 = run_gdsmc({"run", file.string(), "--quiet", "--output", "missing/x.h5"}, dir.path());
  EXPECT_EQ(r2.exit_code, 1) << r2.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

// SIGINT during a run: exit status 130, "interrupted", nothing written. The run (elastic, so it
// never cools, N = 20000 to s = 1e5) would take far longer than the test waits.
TEST(Output, InterruptedRunLeavesNoFile) {
  for (const int sig : {SIGINT, SIGTERM}) {
    TempDir dir;
    const auto file = dir.write("pipeline.yaml", pipeline_yaml("  - {plugin: temperature}\n",
                                                               "{collisions_per_particle: 100000}", "out.h5", 20000, 1.0));
    Process p({"run", file.string(), "--quiet"}, dir.path());
    // Signal it once it handles the signal (installed just before the step loop), and a little
    // later, so that it is inside the loop.
    ASSERT_TRUE(p.wait_until_catches(sig)) << "the run never installed a handler for signal " << sig;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    p.send(sig);
    const ProcessResult r = p.wait(60);
    EXPECT_FALSE(r.timed_out) << "the run did not stop on signal " << sig;
    EXPECT_EQ(r.exit_code, 130) << r.describe();
    EXPECT_TRUE(contains(r.err, "interrupted")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

}  // namespace
