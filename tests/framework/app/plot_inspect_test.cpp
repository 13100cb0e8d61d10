// `gdsmc plot` (the Python plotter run by the host) and `gdsmc inspect` (C++) on small real
// outputs: a homogeneous run (series with realization errors, theory lines, scalars), a slab
// (profiles, histograms), a sweep (/summary against the swept parameter); output.plots: true; the
// plotter installed with `cmake --install`; and the clear one-line errors on a text file and on
// an HDF5 file that is not a gdsmc output. The plot tests need /usr/bin/python3 with the Debian
// packages python3-h5py, python3-numpy and python3-matplotlib (scripts/install-deps installs
// them): without them `gdsmc plot` fails saying which to install, and so do these tests.
#include <gtest/gtest.h>

#include <gdsmc/plugin.hpp>

#include "test_support.hpp"

using namespace gdsmc::test;

namespace {

// Two realizations, so that the series have _stderr companions; a steady window for the means.
const std::string kHomogeneous = R"(run:
  seed: 3
  particles: 400
  time_step: {value: 0.05, unit: tau0}
  stop: {collisions_per_particle: 2}
  realizations: 2
  average_after: {collisions_per_particle: 1}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
diagnostics: [temperature, hcs_theory]
output: {file: out.h5}
)";

// A sheared slab with profiles and the histograms of velocity_marginals (sampled in the window).
const std::string kSlab = R"(run:
  seed: 5
  particles: 600
  time_step: {value: 0.005, unit: tau0}
  stop: {time: 0.2}
  average_after: {time: 0.1}
  record_every: 10
system:
  density: 1.0e-3
  domain: slab
  box: {y: 1.0}
  layers: 5
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
boundaries:
  y: {plugin: lees_edwards, shear_rate: 1}
diagnostics: [profiles, velocity_marginals]
output: {file: slab.h5}
)";

const std::string kSweep = replace_once(kHomogeneous, "output: {file: out.h5}", "output: {file: sweep.h5}\nsweep: {collision.alpha: [0.9, 0.7]}");

// Run a pipeline written into dir; the output file is `file`.
fs::path run_pipeline(const TempDir& dir, const std::string& yaml, const std::string& file) {
  const fs::path p = dir.write("pipeline.yaml", yaml);
  const ProcessResult r = run_gdsmc({"run", p.string(), "-q", "--plugin-path", plugin_dir().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  return dir / file;
}

// A PNG: the signature and more than 1 KB.
void expect_png(const fs::path& p) {
  ASSERT_TRUE(fs::is_regular_file(p)) << p << " was not written";
  EXPECT_GT(fs::file_size(p), 1024u) << p;
  const std::string head = read_text(p).substr(0, 8);
  EXPECT_EQ(head, std::string("\x89PNG\r\n\x1a\n", 8)) << p << " is not a PNG";
}

// `gdsmc plot` exits 0, prints every file it wrote, and every one is a PNG.
std::vector<std::string> plot(const TempDir& dir, const std::vector<std::string>& args) {
  std::vector<std::string> cmd{"plot"};
  cmd.insert(cmd.end(), args.begin(), args.end());
  const ProcessResult r = run_gdsmc(cmd, dir.path(), 300);
  EXPECT_EQ(r.exit_code, 0) << "gdsmc plot needs python3-h5py, python3-numpy and python3-matplotlib "
                               "(apt-get install python3-matplotlib, or scripts/install-deps):\n"
                            << r.describe();
  std::vector<std::string> files;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    files.push_back(fs::path(line).filename().string());
    expect_png(fs::path(line).is_absolute() ? fs::path(line) : dir.path() / line);
  }
  return files;
}

bool has(const std::vector<std::string>& files, const std::string& name) {
  return std::find(files.begin(), files.end(), name) != files.end();
}

// The tag OutputSink::theory wrote on a dataset: "role | theory_of | equation", or "" untagged.
std::string theory_tag(const fs::path& file, const std::string& dataset) {
  const h5::File f(file);
  if (!h5::has_attribute(f.id(), dataset, "role")) return "";
  return h5::read_string_attribute(f.id(), dataset, "role") + " | " + h5::read_string_attribute(f.id(), dataset, "theory_of") +
         " | " + h5::read_string_attribute(f.id(), dataset, "equation");
}

}  // namespace

std::string description(const fs::path& png);

TEST(Plot, HomogeneousSeriesWithErrorsTheoryAndScalars) {
  TempDir dir;
  run_pipeline(dir, kHomogeneous, "out.h5");
  const std::vector<std::string> files = plot(dir, {"out.h5"});
  // Default directory: out_plots/ beside the file.
  EXPECT_TRUE(fs::is_directory(dir / "out_plots"));
  for (const char* name : {"temperature-temperature.png",   // a series with its _stderr band
                           "hcs_theory-temperature.png",    // measured T with Haff's law
                           "hcs_theory-a2.png",             // a2 with a2_sonine
                           "hcs_theory-scalars.png"})       // the scalars
    EXPECT_TRUE(has(files, name)) << name << " not in: " << join(files);
  // The theory series are drawn on the measured quantity's figure, not on their own: paired by
  // the tags the diagnostic wrote (names play no part).
  EXPECT_FALSE(has(files, "hcs_theory-temperature_haff.png")) << join(files);
  EXPECT_FALSE(has(files, "hcs_theory-a2_sonine.png")) << join(files);
  EXPECT_EQ(theory_tag(dir / "out.h5", "/diagnostics/hcs_theory/a2_sonine"), "theory | a2 | 001 Eq. 2.16");
  EXPECT_EQ(theory_tag(dir / "out.h5", "/diagnostics/hcs_theory/temperature_haff"), "theory | temperature | 001 Eqs. 2.14-2.15");
  EXPECT_EQ(theory_tag(dir / "out.h5", "/diagnostics/hcs_theory/a2_sonine.steady_mean"),
            "theory | a2.steady_mean | 001 Eq. 2.16");  // the host's steady mean of a theory series
  EXPECT_EQ(theory_tag(dir / "out.h5", "/diagnostics/hcs_theory/a2"), "");  // measured: no tag
  EXPECT_EQ(theory_tag(dir / "out.h5", "/diagnostics/hcs_theory/a2_sonine_stderr"), "");
  EXPECT_EQ(description(dir / "out_plots" / "hcs_theory-a2.png"),
            "y axis: linear; steady means: none; theory: a2_second_sonine, a2_sonine");
  EXPECT_NE(description(dir / "out_plots" / "hcs_theory-temperature.png").find("; theory: temperature_haff"), std::string::npos);
}

TEST(Plot, SlabProfilesAndHistograms) {
  TempDir dir;
  run_pipeline(dir, kSlab, "slab.h5");
  const std::vector<std::string> files = plot(dir, {"slab.h5", "--out", "figs"});
  EXPECT_TRUE(fs::is_directory(dir / "figs"));
  EXPECT_FALSE(fs::exists(dir / "slab_plots"));
  for (const char* name : {"profiles-T.png", "profiles-u_x.png",                // profiles against y
                           "velocity_marginals-F.png",                          // histograms (F_local_equilibrium on it)
                           "velocity_marginals-g_x_plus.png"})
    EXPECT_TRUE(has(files, name)) << name << " not in: " << join(files);
  EXPECT_FALSE(has(files, "velocity_marginals-F_local_equilibrium.png")) << join(files);
  // Histograms are paired by the tags on their groups.
  EXPECT_EQ(theory_tag(dir / "slab.h5", "/diagnostics/velocity_marginals/F_local_equilibrium"),
            "theory | F | 000 Eq. 3.20 of a Maxwellian");
  EXPECT_EQ(description(dir / "figs" / "velocity_marginals-F.png"), "theory: F_local_equilibrium");
  EXPECT_EQ(description(dir / "figs" / "velocity_marginals-g_y_minus.png"), "theory: g_local_equilibrium");
  // `gdsmc inspect` shows a histogram's group tag beside its edges and values, none beside the measured F's.
  const ProcessResult r = run_gdsmc({"inspect", "slab.h5"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* part : {"edges", "values"}) {
    const auto theory = lines_starting(r.out, std::string("  /diagnostics/velocity_marginals/F_local_equilibrium/") + part + " ");
    ASSERT_EQ(theory.size(), 1u) << r.out;
    EXPECT_TRUE(theory[0].ends_with("  theory of F (000 Eq. 3.20 of a Maxwellian)")) << theory[0];
    const auto measured = lines_starting(r.out, std::string("  /diagnostics/velocity_marginals/F/") + part + " ");
    ASSERT_EQ(measured.size(), 1u) << r.out;
    EXPECT_FALSE(contains(measured[0], "theory")) << measured[0];
  }
}

// What a figure shows, from the Description text the plotter writes into its PNG.
std::string description(const fs::path& png) {
  const std::string bytes = read_text(png);
  const std::string key = std::string("tEXtDescription") + '\0';
  const std::size_t at = bytes.find(key);
  if (at == std::string::npos || at < 4) return "";
  std::size_t length = 0;  // the chunk's data length, big-endian, before its type
  for (std::size_t k = at - 4; k < at; ++k) length = length * 256 + static_cast<unsigned char>(bytes[k]);
  const std::size_t text = key.size() - 4;  // "Description" and its NUL
  return length >= text ? bytes.substr(at + 4 + text, length - text) : "";
}

// A freely cooling gas: Haff's law takes T down more than two decades, so its figure has a
// logarithmic y axis, and no steady-mean line is drawn for it although the run has an averaging
// window (the temperature diagnostic declares none of its series stationary); a sheared gas's rheology,
// declared stationary by shear_rheology, keeps its steady means. The old plotter drew every
// series on a linear axis and a steady mean for every series with a window.
TEST(Plot, LogAxesForSeriesSpanningDecadesAndSteadyMeansOnlyWhereDeclared) {
  TempDir dir;
  const std::string hcs = R"(run:
  seed: 3
  particles: 400
  time_step: {value: 0.05, unit: tau0, follow_temperature: true}
  stop: {collisions_per_particle: 40}
  average_after: {collisions_per_particle: 20}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.3}
diagnostics: [temperature]
output: {file: hcs.h5}
)";
  run_pipeline(dir, hcs, "hcs.h5");
  plot(dir, {"hcs.h5", "--out", "hcs"});
  EXPECT_EQ(description(dir / "hcs" / "temperature-temperature.png"), "y axis: log; steady means: none; theory: none");

  const std::string usf = R"(run:
  seed: 3
  particles: 400
  time_step: {value: 0.01, unit: tau0, follow_temperature: true}
  stop: {collisions_per_particle: 6}
  average_after: {collisions_per_particle: 3}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
forcings: [{plugin: uniform_shear, shear_rate: 0.1}]
diagnostics: [temperature, shear_rheology]
output: {file: usf.h5}
)";
  run_pipeline(dir, usf, "usf.h5");
  const std::vector<std::string> files = plot(dir, {"usf.h5", "--out", "usf"});
  std::size_t with_means = 0;
  for (const auto& f : files)
    if (f.rfind("shear_rheology-", 0) == 0 && f != "shear_rheology-scalars.png") {
      const std::string d = description(dir / "usf" / f);
      with_means += d.find("steady means: ") != std::string::npos && d.find("steady means: none") == std::string::npos;
    }
  EXPECT_GT(with_means, 0u) << join(files);
  EXPECT_NE(description(dir / "usf" / "temperature-temperature.png").find("steady means: none"), std::string::npos);
  // The temperature diagnostic declares it, with an empty list, rather than leaving it out: T is
  // steady in this USF but grows in the modified shear flow with the same shear_rate published, so
  // nothing it reads tells it; shear_rheology, which measures a steady state, declares "all".
  for (const char* file : {"hcs.h5", "usf.h5"}) {
    const h5::File f(dir / file);
    ASSERT_TRUE(h5::has_attribute(f.id(), "/diagnostics/temperature", "stationary")) << file;
    EXPECT_EQ(h5::read_string_attribute(f.id(), "/diagnostics/temperature", "stationary"), "") << file;
  }
  const h5::File usf_file(dir / "usf.h5");
  EXPECT_EQ(h5::read_string_attribute(usf_file.id(), "/diagnostics/shear_rheology", "stationary"), "all");
}

// 1-D arrays against the grid they declare (OutputSink::axis): poiseuille_channel's steady profiles
// against its bin centres y, the errors too; an array that declares none (energy_balance's energy
// by stage) against its index. The old plotter drew every array against its index.
TEST(Plot, ArraysAgainstTheGridTheyDeclare) {
  TempDir dir;
  run_pipeline(dir, R"(run: {seed: 7, particles: 600, time_step: {value: 0.02, unit: tau0}, stop: {time: 2}}
system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 12}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
forcings: [{plugin: body_acceleration, acceleration: 0.5}]
boundaries: {y: diffuse_wall}
diagnostics: [{plugin: poiseuille_channel, steady_window: 0.5}, energy_balance]
output: {file: channel.h5}
)",
               "channel.h5");
  const auto files = plot(dir, {"channel.h5", "--out", "figs"});
  for (const char* profile : {"steady_u_x", "steady_T", "steady_u_x_error"}) {
    ASSERT_TRUE(has(files, std::string("poiseuille_channel-") + profile + ".png")) << join(files);
    EXPECT_EQ(description(dir / "figs" / (std::string("poiseuille_channel-") + profile + ".png")), "x axis: y") << profile;
  }
  EXPECT_EQ(description(dir / "figs" / "energy_balance-added_by_stage.png"), "x axis: index");
  const h5::File f(dir / "channel.h5");
  EXPECT_EQ(h5::read_string_attribute(f.id(), "/diagnostics/poiseuille_channel/steady_u_x", "axis"), "y");
}

TEST(Plot, SweepSummaryAgainstTheSweptParameter) {
  TempDir dir;
  run_pipeline(dir, kSweep, "sweep.h5");
  const std::vector<std::string> files = plot(dir, {"sweep.h5"});
  for (const char* name : {"summary-hcs_theory-a2.png",          // steady a2 +- error with a2_sonine, vs alpha
                           "summary-temperature-temperature.png",
                           "case0-temperature-temperature.png",  // each case's own figures
                           "case1-hcs_theory-a2.png"})
    EXPECT_TRUE(has(files, name)) << name << " not in: " << join(files);
  // A theory scalar's /summary column names the measured columns it is theory for.
  EXPECT_EQ(theory_tag(dir / "sweep.h5", "/summary/hcs_theory.a2_sonine.steady_mean"),
            "theory | hcs_theory.a2.steady_mean | 001 Eq. 2.16");
  EXPECT_EQ(description(dir / "sweep_plots" / "summary-hcs_theory-a2.png"), "theory: a2_second_sonine.steady_mean, a2_sonine.steady_mean");
  EXPECT_FALSE(has(files, "summary-hcs_theory-a2_sonine.png")) << join(files);
}

TEST(Plot, OutputPlotsTrueDrawsAfterTheRun) {
  TempDir dir;
  run_pipeline(dir, replace_once(kHomogeneous, "output: {file: out.h5}", "output: {file: out.h5, plots: true}"), "out.h5");
  expect_png(dir / "out_plots" / "temperature-temperature.png");
  // And the key is checked.
  const fs::path bad = dir.write("bad.yaml", replace_once(kHomogeneous, "output: {file: out.h5}", "output: {file: b.h5, plots: 2}"));
  const ProcessResult r = run_gdsmc({"validate", bad.string(), "--plugin-path", plugin_dir().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "output.plots")) << r.describe();
}

TEST(Plot, InstalledPlotterIsFound) {
  TempDir dir;
  run_pipeline(dir, kHomogeneous, "out.h5");
  const fs::path prefix = dir.path() / "prefix";
  const ShellResult install = shell("cmake --install '" + std::string(GDSMC_BINARY_DIR) + "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(install.status, 0) << install.out;
  ASSERT_TRUE(fs::is_regular_file(prefix / "share/gdsmc/gdsmc_plot.py"));
  const ShellResult r = shell("cd '" + dir.path().string() + "' && '" + (prefix / "bin/gdsmc").string() + "' plot out.h5 --out installed");
  EXPECT_EQ(r.status, 0) << r.out;
  expect_png(dir / "installed" / "temperature-temperature.png");
}

TEST(Plot, RefusesFilesThatAreNotGdsmcOutputs) {
  TempDir dir;
  dir.write("notes.txt", "not HDF5\n");
  {
    const hid_t f = H5Fcreate((dir / "other.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Fclose(f);
  }
  for (const char* command : {"plot", "inspect"}) {
    const ProcessResult text = run_gdsmc({command, "notes.txt"}, dir.path());
    EXPECT_EQ(text.exit_code, 1) << text.describe();
    EXPECT_EQ(text.err, std::string("gdsmc ") + command +
                            ": notes.txt: not an HDF5 file (expected a gdsmc output file, OUTPUT.h5 written by `gdsmc run`)\n")
        << text.describe();
    const ProcessResult other = run_gdsmc({command, "other.h5"}, dir.path());
    EXPECT_EQ(other.exit_code, 1) << other.describe();
    EXPECT_TRUE(contains(other.err, "other.h5: an HDF5 file but not a gdsmc output")) << other.describe();
    EXPECT_EQ(std::count(other.err.begin(), other.err.end(), '\n'), 1) << "one line:\n" << other.describe();
    const ProcessResult missing = run_gdsmc({command, "missing.h5"}, dir.path());
    EXPECT_EQ(missing.exit_code, 1) << missing.describe();
    EXPECT_TRUE(contains(missing.err, "missing.h5: no such file")) << missing.describe();
    EXPECT_TRUE(dir.entries_except({"notes.txt", "other.h5"}).empty()) << "nothing is written";
  }
}

TEST(Inspect, PrintsProvenanceAndDatasetsWithUnits) {
  TempDir dir;
  run_pipeline(dir, kHomogeneous, "out.h5");
  const ProcessResult r = run_gdsmc({"inspect", "out.h5"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(lines_starting(r.out, "  seed").size(), 1u) << r.out;
  EXPECT_TRUE(contains(lines_starting(r.out, "  seed").at(0), " 3")) << r.out;
  EXPECT_TRUE(contains(r.out, std::string("gdsmc version   ") + gdsmc::version_string)) << r.out;
  EXPECT_TRUE(contains(r.out, "pipeline.yaml")) << r.out;
  EXPECT_TRUE(contains(r.out, "inelastic_hard_spheres")) << r.out;
  EXPECT_TRUE(contains(r.out, "params  alpha=0.9")) << r.out;
  // A known dataset with its shape and unit, and a scalar.
  const auto temperature = lines_starting(r.out, "  /diagnostics/temperature/temperature ");
  ASSERT_EQ(temperature.size(), 1u) << r.out;
  EXPECT_TRUE(temperature[0].find("[") != std::string::npos && temperature[0].substr(temperature[0].size() - 2) == "T0")
      << temperature[0];
  const auto time = lines_starting(r.out, "  /diagnostics/temperature/time ");
  ASSERT_EQ(time.size(), 1u) << r.out;
  EXPECT_EQ(time[0].substr(time[0].size() - 4), "tau0") << time[0];
  EXPECT_EQ(lines_starting(r.out, "  /diagnostics/hcs_theory/a2.steady_mean ").size(), 1u) << r.out;
  // Theory beside its measurement: the tag of OutputSink::theory after the unit, none on the measured.
  const auto a2_sonine = lines_starting(r.out, "  /diagnostics/hcs_theory/a2_sonine ");
  ASSERT_EQ(a2_sonine.size(), 1u) << r.out;
  EXPECT_TRUE(a2_sonine[0].ends_with("  theory of a2 (001 Eq. 2.16)")) << a2_sonine[0];
  const auto zeta = lines_starting(r.out, "  /diagnostics/hcs_theory/zeta_ratio_second_sonine ");
  ASSERT_EQ(zeta.size(), 1u) << r.out;
  EXPECT_TRUE(contains(zeta[0], "theory of zeta_ratio_from_cumulants, zeta_ratio_from_cumulants_bilinear (000 Eq. 2.10")) << zeta[0];
  const auto a2 = lines_starting(r.out, "  /diagnostics/hcs_theory/a2 ");
  ASSERT_EQ(a2.size(), 1u) << r.out;
  EXPECT_TRUE(a2[0].ends_with(" 1")) << "the measured a2 ends with its unit: " << a2[0];
  EXPECT_TRUE(contains(r.out, "datasets (") && contains(r.out, "; path, shape, unit, theory tag):")) << r.out;
  // Where the steps' time went, from /run/stage_seconds.*: a homogeneous run has collisions.
  const auto stages = lines_starting(r.out, "  steps' time [s] ");
  ASSERT_EQ(stages.size(), 1u) << r.out;
  EXPECT_TRUE(contains(stages[0], " = ") && contains(stages[0], "collisions ")) << stages[0];
  EXPECT_FALSE(contains(stages[0], "flight")) << "no flight in a homogeneous run without forcing: " << stages[0];
  // --long: the descriptions too.
  const ProcessResult l = run_gdsmc({"inspect", "--long", "out.h5"}, dir.path());
  ASSERT_EQ(l.exit_code, 0) << l.describe();
  EXPECT_TRUE(contains(l.out, "time t / tau0")) << l.out;
}
