// No silent unit: `validate` says what every dimensional value written as a bare number
// was read as, with the dimensionless numbers of the system and those the diagnostics state as
// they begin; `units: explicit` refuses bare dimensional numbers; and the last-mile messages (a
// missing section, a misspelled stop key, --version, the help of validate --resume, inspect's
// run counts).
#include <gtest/gtest.h>

#include <regex>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// Granular Poiseuille flow as paper 004 sets it (W = 1860 sigma), at Kn = lambda0/W = 0.2 and
// a_hat = a W/(2 T_w/m) = 0.5: a = 0.5 * 2/1860 = 5.376e-4 in reduced units.
std::string channel(const std::string& acceleration, const std::string& gap) {
  return R"(run:
  particles: 2000
  time_step: {value: 0.02, unit: tau0}
  stop: {time: {value: 10, unit: tau0}}
system:
  mean_free_path: 372
  domain: slab
  box: {y: )" + gap + R"(}
  layers: 45
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
forcings:
  - {plugin: body_acceleration, acceleration: )" + acceleration + R"(}
boundaries:
  y_min: {plugin: diffuse_wall, temperature: {value: 1, unit: T0}}
  y_max: {plugin: diffuse_wall, temperature: {value: 1, unit: T0}}
diagnostics:
  - {plugin: poiseuille_channel, steady_window: {value: 2, unit: tau0}}
output: {file: out.h5}
)";
}
const std::string kIntendedAcceleration = "{value: 5.376e-4, unit: reduced}";
const std::string kIntendedGap = "{value: 1860, unit: sigma}";

ProcessResult validate(const TempDir& dir, const std::string& yaml) {
  dir.write("p.yaml", yaml);
  return run_gdsmc({"validate", "p.yaml"}, dir.path());
}

// A number as the verdict writes it.
std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// The number after `label` in `text` (NaN if absent).
double number_after(const std::string& text, const std::string& label) {
  const auto at = text.find(label);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(text.c_str() + at + label.size(), nullptr);
}

TEST(UnitsVerdict, TheIntendedChannelShowsItsAhatAndKn) {
  TempDir dir;
  const ProcessResult r = validate(dir, channel(kIntendedAcceleration, kIntendedGap));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NEAR(number_after(r.out, "Kn = lambda0/Ly = "), 0.2, 1e-3) << r.out;
  EXPECT_NEAR(number_after(r.out, "a_hat = "), 0.5, 1e-3) << r.out;
  EXPECT_TRUE(contains(r.out, "units: no dimensional value is written as a bare number")) << r.out;
  EXPECT_TRUE(contains(r.out, "45 layers of 0.1111 lambda0, 44.44 particles per layer")) << r.out;
  EXPECT_TRUE(contains(r.out, "dt = 0.02 tau0 = 0.02257 mean free times")) << r.out;
}

// The issue's first example: the reduced value of a_hat = 0.5 written as a bare number is read in
// 2T0/(m lambda0); the verdict shows the a_hat it gives and the line says what it was read as,
// with the value in 2T0/(m Ly), where a_hat is read off.
TEST(UnitsVerdict, ABareAccelerationMeantInReducedUnitsShowsTheAhatItGives) {
  TempDir dir;
  const ProcessResult r = validate(dir, channel("5.376e-4", kIntendedGap));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const double expected = 5.376e-4 * 1860.0 / 372.0;  // a lambda0-based: a_hat = value * W/lambda0
  EXPECT_NEAR(number_after(r.out, "a_hat = "), expected, 1e-3 * expected) << r.out;
  EXPECT_NEAR(number_after(r.out, "Kn = lambda0/Ly = "), 0.2, 1e-3) << r.out;
  const auto lines = lines_starting(r.out, "  forcings[0].acceleration = 0.0005376 (p.yaml:13:47)");
  ASSERT_EQ(lines.size(), 1u) << r.out;
  EXPECT_TRUE(contains(lines[0], "a bare acceleration: read as 0.0005376 lambda0 tau0^-2 = ")) << lines[0];
  EXPECT_TRUE(contains(lines[0], fmt_g(expected) + " 2T0/(m Ly)")) << lines[0];
  // What the value would have meant in reduced units is on the same line: 5.376e-4 reduced is
  // 0.1 of what was read (lambda0 = 372 sigma: 2T0/(m lambda0) = 2/372 reduced).
  EXPECT_TRUE(contains(lines[0], fmt_g(5.376e-4 * 2 / 372) + " reduced")) << lines[0];
}

// The issue's second example: a gap meant in sigma, written bare, is read in lambda0.
TEST(UnitsVerdict, ABareGapMeantInSigmaShowsTheKnItGives) {
  TempDir dir;
  const ProcessResult r = validate(dir, channel(kIntendedAcceleration, "1860"));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NEAR(number_after(r.out, "Kn = lambda0/Ly = "), 1 / 1860.0, 1e-3 / 1860) << r.out;
  EXPECT_NEAR(number_after(r.out, "a_hat = "), 5.376e-4 * 1860 * 372 / 2, 0.5) << r.out;  // W = 1860 lambda0
  const auto lines = lines_starting(r.out, "  system.box.y = 1860 (p.yaml:8:12)");
  ASSERT_EQ(lines.size(), 1u) << r.out;
  EXPECT_TRUE(contains(lines[0], "a bare length: read as 1860 lambda0 = " + fmt_g(1860.0 * 372) + " reduced")) << lines[0];
  EXPECT_TRUE(contains(lines[0], fmt_g(1860.0 * 372) + " sigma")) << lines[0];
}

// units: explicit refuses each bare dimensional number at its place and says how to write it; a
// pipeline with every unit written is valid; dimensionless numbers stay plain.
TEST(UnitsVerdict, UnitsExplicitRefusesBareDimensionalNumbers) {
  TempDir dir;
  const std::string bare = "units: explicit\n" + replace_once(channel("5.376e-4", "1860"), "time_step: {value: 0.02, unit: tau0}",
                                                              "time_step: 0.02");
  const ProcessResult r = validate(dir, bare);
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "p.yaml:4:14: run.time_step: 0.02 is a bare time and the pipeline sets units: explicit: "
                              "write {value: 0.02, unit: tau0}"))
      << r.err;
  EXPECT_TRUE(contains(r.err, "p.yaml:9:12: system.box.y: 1860 is a bare length")) << r.err;
  EXPECT_TRUE(contains(r.err, "write {value: 1860, unit: lambda0}")) << r.err;
  EXPECT_TRUE(contains(r.err, "p.yaml:14:47: forcings[0].acceleration: 0.0005376 is a bare acceleration")) << r.err;
  EXPECT_TRUE(contains(r.err, "write {value: 0.0005376, unit: lambda0 tau0^-2}")) << r.err;
  EXPECT_TRUE(contains(r.err, "3 errors")) << r.err;

  const ProcessResult good = validate(dir, "units: explicit\n" + channel(kIntendedAcceleration, kIntendedGap));
  EXPECT_EQ(good.exit_code, 0) << good.describe();
  const ProcessResult wrong = validate(dir, "units: strict\n" + channel(kIntendedAcceleration, kIntendedGap));
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_TRUE(contains(wrong.err, "p.yaml:1:8: units: valid: reference")) << wrong.err;
}

// The unit Ly (a slab's gap) gives a_hat directly: 0.5 2T0/(m Ly) is the intended acceleration.
TEST(UnitsVerdict, TheGapIsAUnit) {
  TempDir dir;
  const ProcessResult r = validate(dir, channel("{value: 0.5, unit: 2T0/(m Ly)}", kIntendedGap));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NEAR(number_after(r.out, "a_hat = "), 0.5, 1e-9) << r.out;
  const ProcessResult homogeneous = validate(dir, replace_once(kSmallHcsPipeline, "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}",
                                                               "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
                                                               "forcings: [{plugin: uniform_shear, shear_rate: {value: 1, unit: 1/Ly}}]"));
  EXPECT_EQ(homogeneous.exit_code, 1);
  EXPECT_TRUE(contains(homogeneous.err, "unit 'Ly' (the gap of a slab) needs system.domain: slab")) << homogeneous.err;
}

// A misspelled key inside run.stop says so, and nothing else: no step count from an empty stop.
TEST(UnitsVerdict, AMisspelledStopKeyIsNamedAndNothingElse) {
  TempDir dir;
  const ProcessResult r = validate(dir, replace_once(kSmallHcsPipeline, "stop: {collisions_per_particle: 1}",
                                                     "stop: {colisions_per_particle: 1}"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "unknown key 'colisions_per_particle'; did you mean collisions_per_particle?")) << r.err;
  EXPECT_FALSE(contains(r.err, "steps")) << r.err;
  EXPECT_TRUE(contains(r.err, "1 error;")) << r.err;
}

// A missing section's error shows a minimal one, which (put back) makes the pipeline valid.
TEST(UnitsVerdict, AMissingSectionShowsAMinimalValidOne) {
  const std::vector<std::pair<std::string, std::string>> sections = {
      {"run", "run:\n  seed: 3\n  particles: 400\n  time_step: {value: 0.02, unit: tau0}\n  stop: {collisions_per_particle: 1}\n"},
      {"system", "system: {density: 1.0e-3}\n"},
      {"initial_state", "initial_state: maxwellian\n"},
      {"collision", "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"}};
  for (const auto& [name, text] : sections) {
    SCOPED_TRACE(name);
    TempDir dir;
    const ProcessResult r = validate(dir, replace_once(kSmallHcsPipeline, text, ""));
    EXPECT_EQ(r.exit_code, 1);
    const std::string marker = "missing required section '" + name + "'; a minimal one: ";
    const auto at = r.err.find(marker);
    ASSERT_NE(at, std::string::npos) << r.err;
    std::string example = r.err.substr(at + marker.size());
    example = example.substr(0, example.find(" ("));  // the example ends before its comment
    const ProcessResult fixed = validate(dir, replace_once(kSmallHcsPipeline, text, "") + example + "\n");
    EXPECT_EQ(fixed.exit_code, 0) << example << "\n" << fixed.describe();
  }
}

TEST(UnitsVerdict, VersionNamesTheBuild) {
  TempDir dir;
  const ProcessResult r = run_gdsmc({"--version"}, dir.path());
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind(std::string("gdsmc ") + version_string + "\n", 0), 0u) << r.out;
  EXPECT_TRUE(contains(r.out, "SDK ABI " + std::to_string(sdk_abi_major) + "." + std::to_string(sdk_abi_minor))) << r.out;
  EXPECT_EQ(lines_starting(r.out, "MPI: ").size(), 1u) << r.out;
  EXPECT_EQ(lines_starting(r.out, "build: ").size(), 1u) << r.out;
  EXPECT_EQ(lines_starting(r.out, "HDF5: ").size(), 1u) << r.out;
  // CITATION.cff cites this version.
  EXPECT_EQ(lines_starting(read_text(source_dir() / "CITATION.cff"), std::string("version: ") + version_string).size(), 1u);
}

// The top-level help says what validate --resume does, as `gdsmc help validate` does.
TEST(UnitsVerdict, ValidateResumeIsDescribedAlike) {
  TempDir dir;
  const ProcessResult top = run_gdsmc({"--help"}, dir.path());
  const std::string validate_section = top.out.substr(top.out.find("gdsmc validate"), top.out.find("gdsmc plugins") - top.out.find("gdsmc validate"));
  EXPECT_TRUE(contains(validate_section, "--resume               also check that the checkpoint")) << validate_section;
  EXPECT_FALSE(contains(validate_section, "ignored")) << validate_section;
}

// inspect says that the counts are realization 0's and the wall time every realization's.
TEST(UnitsVerdict, InspectSeparatesRunCountsFromTheWallTime) {
  TempDir dir;
  dir.write("p.yaml", replace_once(kSmallHcsPipeline, "  seed: 3\n", "  seed: 3\n  realizations: 3\n"));
  ASSERT_EQ(run_gdsmc({"run", "p.yaml", "--quiet"}, dir.path()).exit_code, 0);
  const ProcessResult r = run_gdsmc({"inspect", "out.h5"}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(lines_starting(r.out, "  run (realization 0) ").size(), 1u) << r.out;
  EXPECT_EQ(lines_starting(r.out, "  wall time (all 3 realizations) ").size(), 1u) << r.out;
}

}  // namespace
}  // namespace gdsmc::test
