// The HDF5 file of a run: layout, units, provenance; and that a failed or interrupted run leaves
// no file under the final name.
#include <gtest/gtest.h>

#include <signal.h>

#include <string>
#include <thread>
#include <vector>

#include "output/hdf5_file.hpp"
#include "study/statistics.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

std::string pipeline_yaml(const std::string& diagnostics, const std::string& stop = "{collisions_per_particle: 3}",
                          const std::string& output = "out.h5", int particles = 500, double alpha = 0.8) {
  return "run:\n"
         "  seed: 99\n"
         "  particles: " + std::to_string(particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n"
         "  sample_every: 5\n"
         "  record_every: 10\n"
         "  average_after: {collisions_per_particle: 1}\n"
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
    "  - {plugin: hcs_theory}\n";

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

// Profiles, in-process: each is a (record x bin) dataset with its unit and description, beside one
// bin_centre [lambda0] per group that has profiles (SystemInfo::bin_centre / lambda0).
TEST(Output, ProfilesAreRecordByBinDatasetsBesideTheBinCentres) {
  gdsmc::SystemInfo sys;
  sys.bins = 4;
  sys.box[1] = 8.0;  // bins of width 2 centred at -3, -1, 1, 3 (sigma)
  sys.mean_free_path0 = 2.0;
  std::vector<std::string> summary;
  gdsmc::host::DiagnosticOutput d("profiles", &summary);
  d.set_bins(gdsmc::host::bin_centres_lambda0(sys));
  const auto density = d.profile("density", "n", "number density per bin");
  const auto total = d.series("total", "1", "a series beside the profile");
  std::vector<double> expected;
  for (int k = 0; k < 3; ++k) {
    d.begin_record(0.5 * k, 0.25 * k);
    const double row[4] = {10.0 * k + 1, 10.0 * k + 2, 10.0 * k + 3, 10.0 * k + 4};
    d.append_profile(density, row);
    expected.insert(expected.end(), row, row + 4);
    d.append(total, k);
    d.check_record("test_profiles");
  }
  gdsmc::host::DiagnosticOutput plain("plain", &summary);  // no profiles: no bin_centre
  plain.set_bins(gdsmc::host::bin_centres_lambda0(sys));
  plain.series("x", "1", "a series");

  gdsmc::host::StudyOutput out;
  out.cases.emplace_back();
  out.cases[0].diagnostics = {d, plain};
  TempDir dir;
  gdsmc::host::write_hdf5(dir / "profiles.h5", out);
  ASSERT_EQ(dir.files(), std::vector<std::string>{"profiles.h5"});

  h5::File h(dir / "profiles.h5");
  const hid_t f = h.id();
  const std::string g = "/diagnostics/profiles/";
  EXPECT_EQ(h5::shape(f, g + "density"), (std::vector<hsize_t>{3, 4}));
  EXPECT_EQ(h5::read_doubles(f, g + "density"), expected);
  EXPECT_EQ(h5::read_string_attribute(f, g + "density", "unit"), "n");
  EXPECT_EQ(h5::read_string_attribute(f, g + "density", "description"), "number density per bin");
  EXPECT_EQ(h5::shape(f, g + "total"), std::vector<hsize_t>{3});
  EXPECT_EQ(h5::shape(f, g + "time"), std::vector<hsize_t>{3});
  EXPECT_EQ(h5::shape(f, g + "bin_centre"), std::vector<hsize_t>{4});
  EXPECT_EQ(h5::read_doubles(f, g + "bin_centre"), (std::vector<double>{-1.5, -0.5, 0.5, 1.5}));
  EXPECT_EQ(h5::read_string_attribute(f, g + "bin_centre", "unit"), "lambda0");
  EXPECT_TRUE(h5::is_dataset(f, "/diagnostics/plain/x"));
  EXPECT_FALSE(h5::exists(f, "/diagnostics/plain/bin_centre"));
}

// A record in which a declared profile got no append (or two) is refused, naming the plugin, the
// group and the profile; so is a profile declared before the host set the bins, or named bin_centre.
TEST(Output, ProfileRecordsAreCheckedAndNamed) {
  std::vector<std::string> summary;
  gdsmc::host::DiagnosticOutput d("slab", &summary);
  d.set_bins({-1.0, 0.0, 1.0});
  const auto u = d.profile("velocity", "sqrt(2T0/m)", "mean velocity per bin");
  d.profile("temperature", "T0", "temperature per bin");
  const double row[3] = {1, 2, 3};
  d.begin_record(0, 0);
  d.append_profile(u, row);  // "temperature" got nothing
  try {
    d.check_record("slab_profiles");
    FAIL() << "a record without an append to a declared profile was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "slab_profiles")) << m;
    EXPECT_TRUE(contains(m, "'slab'")) << m;
    EXPECT_TRUE(contains(m, "profile 'temperature'")) << m;
    EXPECT_TRUE(contains(m, "exactly one append_profile per record")) << m;
  }
  // Two appends in one record are refused too.
  gdsmc::host::DiagnosticOutput twice("slab", &summary);
  twice.set_bins({0.0});
  const auto p = twice.profile("n", "n", "density");
  twice.begin_record(0, 0);
  twice.append_profile(p, row);
  twice.append_profile(p, row);
  EXPECT_THROW(twice.check_record("slab_profiles"), std::runtime_error);

  gdsmc::host::DiagnosticOutput no_bins("nobins", &summary);
  try {
    no_bins.profile("n", "n", "density");
    FAIL() << "a profile was declared without sampling bins";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "set_bins")) << e.what();
    EXPECT_TRUE(contains(e.what(), "profile 'n'")) << e.what();
  }
  EXPECT_THROW(d.profile("bin_centre", "lambda0", "reserved"), std::runtime_error);
  EXPECT_THROW(d.profile("velocity", "1", "declared twice"), std::runtime_error);
}

// An output file of one run holding the diagnostic d, written as the host writes it.
fs::path write_one_diagnostic(const TempDir& dir, const std::string& file, const gdsmc::host::DiagnosticOutput& d) {
  gdsmc::host::StudyOutput out;
  out.cases.emplace_back();
  out.cases[0].diagnostics = {d};
  gdsmc::host::write_hdf5(dir / file, out);
  return dir / file;
}

// OutputSink::theory (SDK 6.3): the tag becomes the attributes role, theory_of and equation of the
// dataset (a histogram's group included), survives a checkpoint, and is refused for a dataset or
// a measured twin not yet written, twice, or without its equation.
TEST(Output, TheoryTagsAreAttributesOfTheirDatasets) {
  std::vector<std::string> summary;
  gdsmc::host::DiagnosticOutput d("theory", &summary);
  d.series("T", "T0", "measured");
  d.series("T_haff", "T0", "Haff's law");
  d.scalar("T_mean", 1.0, "T0", "measured mean");
  d.histogram("g", {0, 1, 2}, {0.5, 0.5}, "1", "1", "measured");
  d.histogram("g_maxwell", {0, 1, 2}, {0.6, 0.4}, "1", "1", "theory");
  d.scalar("rate", 2.0, "1", "theory without a measured twin");
  EXPECT_THROW(d.theory("T_sonine", "T", "001 Eq. 2.16"), std::runtime_error);  // not written
  EXPECT_THROW(d.theory("T_haff", "T_later", "001 Eq. 2.15"), std::runtime_error);  // twin not written
  EXPECT_THROW(d.theory("T_haff", "T_haff", "001 Eq. 2.15"), std::runtime_error);  // itself
  EXPECT_THROW(d.theory("T_haff", "T", ""), std::runtime_error);  // no equation
  d.theory("T_haff", " T , T_mean ", "001 Eqs. 2.14-2.15");
  EXPECT_THROW(d.theory("T_haff", "T", "001 Eq. 2.15"), std::runtime_error);  // twice
  d.theory("g_maxwell", "g", "Maxwell");
  d.theory("rate", "", "van Noije & Ernst 1998");

  gdsmc::BufferStateWriter saved;
  d.save(saved);
  gdsmc::host::DiagnosticOutput resumed("theory", &summary);
  resumed.series("T", "T0", "measured");
  resumed.series("T_haff", "T0", "Haff's law");
  gdsmc::BufferStateReader in(saved.bytes());
  resumed.load(in);
  ASSERT_EQ(resumed.theory_tags.size(), 3u);
  EXPECT_EQ(resumed.theory_tags.at("T_haff").measured, "T,T_mean");

  TempDir dir;
  h5::File h(write_one_diagnostic(dir, "theory.h5", resumed));
  const hid_t f = h.id();
  const std::string g = "/diagnostics/theory/";
  EXPECT_EQ(h5::read_string_attribute(f, g + "T_haff", "role"), "theory");
  EXPECT_EQ(h5::read_string_attribute(f, g + "T_haff", "theory_of"), "T,T_mean");
  EXPECT_EQ(h5::read_string_attribute(f, g + "T_haff", "equation"), "001 Eqs. 2.14-2.15");
  EXPECT_EQ(h5::read_string_attribute(f, g + "g_maxwell", "theory_of"), "g");
  EXPECT_EQ(h5::read_string_attribute(f, g + "rate", "theory_of"), "");
  EXPECT_EQ(h5::read_string_attribute(f, g + "rate", "equation"), "van Noije & Ernst 1998");
  for (const char* measured : {"T", "T_mean", "g"}) EXPECT_FALSE(h5::has_attribute(f, g + measured, "role")) << measured;
}

// OutputSink::axis (SDK 6.4): a 1-D array's grid, checked when declared, kept through a checkpoint,
// copied to the realizations' average and written as the attribute axis.
TEST(Output, AnArraysAxisIsTheAttributeNamingItsGrid) {
  std::vector<std::string> summary;
  gdsmc::host::DiagnosticOutput d("curves", &summary);
  d.array("alpha", {0.0, 0.5, 1.0}, {3}, "1", "grid");
  d.array("kappa_vs_alpha", {1.2, 1.1, 1.0}, {3}, "1", "a curve over alpha");
  d.array("short", {1.0, 2.0}, {2}, "1", "two values");
  d.array("matrix", {1, 2, 3, 4, 5, 6}, {2, 3}, "1", "2-D");
  d.scalar("s", 1.0, "1", "a scalar");
  EXPECT_THROW(d.axis("later", "alpha"), std::runtime_error);           // not written
  EXPECT_THROW(d.axis("kappa_vs_alpha", "s"), std::runtime_error);      // the grid is no array
  EXPECT_THROW(d.axis("short", "alpha"), std::runtime_error);           // lengths differ
  EXPECT_THROW(d.axis("matrix", "alpha"), std::runtime_error);          // not 1-D
  EXPECT_THROW(d.axis("alpha", "alpha"), std::runtime_error);           // itself
  d.axis("kappa_vs_alpha", "alpha");
  EXPECT_THROW(d.axis("kappa_vs_alpha", "alpha"), std::runtime_error);  // twice

  gdsmc::BufferStateWriter saved;
  d.save(saved);
  gdsmc::host::DiagnosticOutput resumed("curves", &summary);
  gdsmc::BufferStateReader in(saved.bytes());
  resumed.load(in);
  ASSERT_EQ(resumed.axes.size(), 1u);
  EXPECT_EQ(resumed.axes.at("kappa_vs_alpha"), "alpha");
  const auto averaged = gdsmc::host::average_realizations({{resumed}, {resumed}}, &summary);
  ASSERT_EQ(averaged.size(), 1u);
  EXPECT_EQ(averaged[0].axes, resumed.axes);

  TempDir dir;
  h5::File h(write_one_diagnostic(dir, "axes.h5", resumed));
  EXPECT_EQ(h5::read_string_attribute(h.id(), "/diagnostics/curves/kappa_vs_alpha", "axis"), "alpha");
  for (const char* other : {"alpha", "short", "matrix"})
    EXPECT_FALSE(h5::has_attribute(h.id(), std::string("/diagnostics/curves/") + other, "axis")) << other;
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


// /run/stage_seconds.* say where the steps' wall time went, and the run's summary prints them. Every
// stage is timed from the end of the one before, so the stages together are the time inside the
// steps: never more than wall_seconds (the same clock, over a longer interval), and all of it but
// the run loop's own checks and the end of the run (the last record, finish) here, so at least
// half of it. A slab has every stage but forcings; a homogeneous system without a body
// acceleration has no flight, no sort and no reordering, which stay exactly 0.
TEST(Output, StageSecondsSayWhereTheStepsWent) {
  TempDir dir;
  const std::string slab =
      "run: {seed: 3, particles: 20000, time_step: {value: 0.02, unit: tau0}, stop: {time: {value: 1, unit: tau0}},"
      " sample_every: 5, record_every: 10}\n"
      "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 5}, layers: 20}\n"
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
      "boundaries: {y: {plugin: diffuse_wall, temperature: 1.0}}\ndiagnostics: [temperature]\n"
      "output: {file: slab.h5}\n";
  const ProcessResult r = run_gdsmc({"run", dir.write("slab.yaml", slab).string(), "--threads", "2"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("time in the steps [s]: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("flight "), std::string::npos) << r.out;
  h5::File h(dir / "slab.h5");
  double sum = 0;
  for (const char* stage : {"forcings", "flight", "sort", "reorder", "collisions", "moments", "diagnostics"}) {
    const double s = h5::read_number_attribute(h.id(), "/run", std::string("stage_seconds.") + stage);
    if (std::string(stage) == "forcings") EXPECT_EQ(s, 0.0);
    else EXPECT_GT(s, 0.0) << stage;
    sum += s;
  }
  const double wall = h5::read_number_attribute(h.id(), "/run", "wall_seconds");
  EXPECT_LE(sum, wall);
  EXPECT_GE(sum, 0.5 * wall);

  TempDir dir2;
  const gdsmc::host::Pipeline pipeline = load_yaml(dir2, pipeline_yaml(kDiagnostics));  // the engine keeps a reference
  gdsmc::host::Engine homogeneous(pipeline);
  homogeneous.run();
  using Stage = gdsmc::host::Stage;
  for (Stage s : {Stage::flight, Stage::sort, Stage::reorder, Stage::forcings})
    EXPECT_EQ(homogeneous.stage_seconds(s), 0.0) << gdsmc::host::stage_name(s);
  EXPECT_GT(homogeneous.stage_seconds(Stage::collisions), 0.0);
  EXPECT_LE(homogeneous.stage_seconds(Stage::collisions) + homogeneous.stage_seconds(Stage::moments) +
                homogeneous.stage_seconds(Stage::diagnostics),
            homogeneous.wall_seconds());
}

}  // namespace
