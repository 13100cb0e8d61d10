// Bad input through the gdsmc executable: every mistake is refused with exit status 1, a message
// that says where and what (file:line:column, the key, what would be valid), and no output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

// A small valid pipeline (each test breaks one thing). Line numbers are computed from the text.
const std::string kGood = R"(run:
  seed: 7
  particles: 500
  time_step: {value: 0.01, unit: tau0, follow_temperature: true}
  stop: {collisions_per_particle: 2}
system:
  density: 1.0e-3
  temperature: 1.0
initial_state: {plugin: maxwellian}
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
diagnostics:
  - {plugin: temperature}
output: {file: out.h5}
)";

// The reference: the unbroken pipeline runs and writes out.h5 in its directory (so the "no output
// file" checks below are meaningful).
TEST(BadInput, GoodPipelineRunsAndWrites) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", kGood);
  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"out.h5", "pipeline.yaml"}));
}

TEST(BadInput, MalformedYamlGivesFileLineColumn) {
  // An over-indented key inside a block mapping: yaml-cpp stops on that very line.
  const std::string broken = replace_once(kGood, "  temperature: 1.0\n", "   temperature: 1.0\n");
  const Refusal r = refuse(broken);
  const int line = line_of(broken, "   temperature: 1.0");
  ASSERT_GT(line, 0);
  EXPECT_TRUE(contains(r.result.err, r.file + ":" + std::to_string(line) + ":")) << r.result.describe();
  EXPECT_TRUE(contains(r.result.err, "YAML")) << r.result.describe();

  // A second shape of broken line: a scalar followed by another ': '.
  const std::string broken2 = replace_once(kGood, "  density: 1.0e-3\n", "  density: 1.0e-3: 5\n");
  const Refusal r2 = refuse(broken2);
  const int line2 = line_of(broken2, "density: 1.0e-3: 5");
  EXPECT_TRUE(contains(r2.result.err, r2.file + ":" + std::to_string(line2) + ":")) << r2.result.describe();
}

TEST(BadInput, UnknownPluginSuggestsClosestName) {
  const std::string yaml = replace_once(kGood, "{plugin: inelastic_hard_spheres, alpha: 0.9}", "{plugin: inelastic_hard_sphere, alpha: 0.9}");
  const Refusal r = refuse(yaml);
  const std::string& err = r.result.err;
  EXPECT_TRUE(contains(err, "inelastic_hard_sphere'")) << err;          // names what was asked for
  EXPECT_TRUE(contains(err, "did you mean inelastic_hard_spheres")) << err;  // and the closest name
  EXPECT_TRUE(contains(err, r.file + ":" + std::to_string(line_of(yaml, "collision:")) + ":")) << err;
}

// A refused pipeline prints the warnings noticed before its errors: a plugins: directory that does
// not exist is why a plugin it should hold is unknown (not only the error).
TEST(BadInput, AMissingPluginDirectoryIsWarnedBesideTheUnknownPluginItExplains) {
  std::string yaml = replace_once(kGood, "{plugin: inelastic_hard_spheres, alpha: 0.9}", "{plugin: my_rule, alpha: 0.9}");
  yaml = "plugins: [my_plugins_dir]\n" + yaml;
  for (const char* command : {"run", "validate"}) {
    const Refusal r = refuse(yaml, {}, command);
    const std::string& err = r.result.err;
    EXPECT_TRUE(contains(err, "warning: ")) << command << ": " << err;
    EXPECT_TRUE(contains(err, "my_plugins_dir does not exist")) << command << ": " << err;
    EXPECT_TRUE(contains(err, "my_rule")) << command << ": " << err;  // and the error it explains
    EXPECT_LT(err.find("my_plugins_dir does not exist"), err.find("error: ")) << command << ": " << err;
  }
}

TEST(BadInput, UnknownParameterSuggestsAlpha) {
  const std::string yaml = replace_once(kGood, "alpha: 0.9}", "alpah: 0.9}");
  const Refusal r = refuse(yaml);
  const std::string& err = r.result.err;
  EXPECT_TRUE(contains(err, "alpah")) << err;
  EXPECT_TRUE(contains(err, "did you mean alpha")) << err;
  EXPECT_TRUE(contains(err, r.file + ":" + std::to_string(line_of(yaml, "alpah")) + ":")) << err;
}

TEST(BadInput, OutOfRangeParameterNamesPluginAndRange) {
  const std::string yaml = replace_once(kGood, "alpha: 0.9}", "alpha: 1.2}");
  const Refusal r = refuse(yaml);
  const std::string& err = r.result.err;
  EXPECT_TRUE(contains(err, "alpha")) << err;
  EXPECT_TRUE(contains(err, "inelastic_hard_spheres")) << err;
  EXPECT_TRUE(contains(err, "[0, 1]")) << err;
  EXPECT_TRUE(contains(err, "1.2")) << err;
  EXPECT_TRUE(contains(err, r.file + ":" + std::to_string(line_of(yaml, "alpha: 1.2")) + ":")) << err;
}

TEST(BadInput, ParticleCountMustBeAtLeastTwo) {
  for (const std::string n : {"0", "-5"}) {
    const std::string yaml = replace_once(kGood, "particles: 500", "particles: " + n);
    const Refusal r = refuse(yaml);
    EXPECT_TRUE(contains(r.result.err, "particles")) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, n)) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, r.file + ":" + std::to_string(line_of(yaml, "particles:")) + ":")) << r.result.err;
  }
}

TEST(BadInput, NegativeTimeStep) {
  const std::string yaml = replace_once(kGood, "{value: 0.01, unit: tau0", "{value: -0.01, unit: tau0");
  const Refusal r = refuse(yaml);
  EXPECT_TRUE(contains(r.result.err, "time_step")) << r.result.err;
  EXPECT_TRUE(contains(r.result.err, "> 0")) << r.result.err;
}

TEST(BadInput, MissingRequiredKeyAndSection) {
  {
    const Refusal r = refuse(replace_once(kGood, "  particles: 500\n", ""));
    EXPECT_TRUE(contains(r.result.err, "particles")) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, "missing")) << r.result.err;
  }
  {
    const Refusal r = refuse(replace_once(kGood, "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n", ""));
    EXPECT_TRUE(contains(r.result.err, "collision")) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, "missing")) << r.result.err;
  }
}

TEST(BadInput, NonexistentOrUnreadablePipelineFile) {
  TempDir dir;
  {
    const std::string missing = (dir / "no-such-pipeline.yaml").string();
    const ProcessResult r = run_gdsmc({"run", missing}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_TRUE(contains(r.err, missing)) << r.err;
    EXPECT_TRUE(contains(r.err, "cannot read")) << r.err;
  }
  {
    // A directory where the file should be: refused, naming the path.
    const ProcessResult r = run_gdsmc({"run", dir.path().string()}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_TRUE(contains(r.err, dir.path().string())) << r.err;
  }
  EXPECT_EQ(dir.entries_except({}), std::vector<std::string>{});
  if (::geteuid() != 0) {  // root reads a mode-000 file anyway
    const auto file = dir.write("locked.yaml", kGood);
    ::chmod(file.c_str(), 0);
    const ProcessResult r = run_gdsmc({"run", file.string()}, dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_TRUE(contains(r.err, "cannot read")) << r.err;
    EXPECT_EQ(dir.files(), std::vector<std::string>{"locked.yaml"});
  }
}

TEST(BadInput, OutOfRangeSetOverrideNamesTheSet) {
  const Refusal r = refuse(kGood, {"--set", "collision.alpha=1.5"});
  const std::string& err = r.result.err;
  EXPECT_TRUE(contains(err, "--set collision.alpha=1.5")) << err;
  EXPECT_TRUE(contains(err, "[0, 1]")) << err;
  EXPECT_TRUE(contains(err, "inelastic_hard_spheres")) << err;
  // An override of a value that is not in the file (here a run key) is checked the same way.
  const Refusal r2 = refuse(kGood, {"--set", "run.particles=1"});
  EXPECT_TRUE(contains(r2.result.err, "--set run.particles=1")) << r2.result.err;
}

// Known defects, disabled until framework/pipeline.cpp is fixed (run with
// --gtest_also_run_disabled_tests to see them fail):
// - `--set a.0.b=v` (the dot form of a list index, which apply_override accepts) is reported at
//   "<file>:1:1" instead of at the --set, because Checker::where compares the raw override key
//   with the canonical path "a[0].b".
TEST(BadInput, SetOverrideWithDotIndexNamesTheSet) {
  const Refusal r = refuse(kGood, {"--set", "diagnostics.0.record_every=0"});
  EXPECT_TRUE(contains(r.result.err, "--set diagnostics.0.record_every=0")) << r.result.err;
}
// - A directory given as the pipeline file is reported as "a pipeline is a YAML mapping ..." at
//   "<dir>:1:1" (std::ifstream opens a directory; the read then fails silently).
TEST(BadInput, DirectoryAsPipelineFileCannotBeRead) {
  TempDir dir;
  const ProcessResult r = run_gdsmc({"run", dir.path().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "cannot read")) << r.err;
}

TEST(BadInput, DuplicateKey) {
  {
    const std::string yaml = replace_once(kGood, "  seed: 7\n", "  seed: 7\n  seed: 8\n");
    const Refusal r = refuse(yaml);
    EXPECT_TRUE(contains(r.result.err, "duplicate key 'seed'")) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, r.file + ":" + std::to_string(line_of(yaml, "seed: 8")) + ":")) << r.result.err;
  }
  {
    const std::string yaml = replace_once(kGood, "alpha: 0.9}", "alpha: 0.9, alpha: 0.5}");
    const Refusal r = refuse(yaml);
    EXPECT_TRUE(contains(r.result.err, "duplicate key 'alpha'")) << r.result.err;
  }
}

// Every error in a named sweep variant carries the file:line:column of its entry. A misspelt first
// key ("colision.alpha"), a key below a value ("collision.alpha.x") or a section the variant adds
// that the system cannot have ("boundaries.y" in a homogeneous system) made a node the file does
// not hold, and was reported with the file name alone.
TEST(BadInput, EveryErrorInASweepVariantCarriesFileLineColumn) {
  const std::vector<std::pair<std::string, std::string>> variants = {
      {"{colision.alpha: 0.5}", "colision: unknown key 'colision'; did you mean collision?"},
      {"{collision.alpha.x: 0.5}", "collision.alpha: parameter 'alpha' of plugin 'inelastic_hard_spheres'"},
      {"{boundaries.y: diffuse}", "boundaries: boundaries need a slab"},
      {"{collision.alpah: 0.5}", "collision.alpah: plugin 'inelastic_hard_spheres' ("},
      {"{collision.alpah: 0.5}", ") has no parameter 'alpah'"},
  };
  for (const auto& [variant, message] : variants) {
    SCOPED_TRACE(variant);
    const std::string entry = "    typo: " + variant + "\n";
    const std::string yaml = replace_once(kGood, "output: {file: out.h5}\n",
                                          "sweep:\n  model:\n    fine: {collision.alpha: 0.8}\n" + entry +
                                              "output: {file: out.h5}\n");
    const Refusal r = refuse(yaml);
    const std::string located = r.file + ":" + std::to_string(line_of(yaml, entry.substr(0, entry.size() - 1))) + ":";
    EXPECT_TRUE(contains(r.result.err, "error: " + located)) << r.result.err;
    EXPECT_TRUE(contains(r.result.err, message)) << r.result.err;
    EXPECT_FALSE(contains(r.result.err, "error: " + r.file + ": ")) << "an error without line and column\n" << r.result.err;
  }
}

// Keys a sweep case cannot vary (output.*, sweep.*, plugins) were silently ignored inside a sweep
// variant or as a value axis: every case wrote the study's one output file with the study's plugins.
// They are refused at their file:line:column, saying why and what a sweep may vary.
TEST(BadInput, KeysASweepCaseCannotVaryAreRefusedWhereTheyAre) {
  const std::vector<std::pair<std::string, std::string>> sweeps = {
      {"  model:\n    fine: {collision.alpha: 0.8}\n    typo: {output.file: other.h5}\n", "    typo: {output.file"},
      {"  model:\n    fine: {collision.alpha: 0.8}\n    typo: {sweep.x: [1, 2]}\n", "    typo: {sweep.x"},
      {"  model:\n    fine: {collision.alpha: 0.8}\n    typo: {plugins: [elsewhere]}\n", "    typo: {plugins"},
      {"  output.file: [a.h5, b.h5]\n", "  output.file:"},
  };
  for (const auto& [sweep, at] : sweeps) {
    SCOPED_TRACE(sweep);
    const std::string yaml = replace_once(kGood, "output: {file: out.h5}\n", "sweep:\n" + sweep + "output: {file: out.h5}\n");
    for (const char* command : {"run", "validate"}) {
      const Refusal r = refuse(yaml, {}, command);
      const std::string located = r.file + ":" + std::to_string(line_of(yaml, at)) + ":";
      EXPECT_TRUE(contains(r.result.err, "error: " + located)) << r.result.err;
      EXPECT_TRUE(contains(r.result.err, "cannot vary between sweep cases")) << r.result.err;
    }
  }
}

// Every unknown-plugin and parameter error names the library file it is about (a plugin shadowed
// by another file of the same name shows at once), and an unknown plugin names the search path.
TEST(BadInput, UnknownPluginAndParameterErrorsNameTheLibraryFile) {
  const std::string ihs = "gdsmc_inelastic_hard_spheres.so)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {replace_once(kGood, "alpha: 0.9}", "alpah: 0.9}"), ihs + " has no parameter 'alpah'"},
      {replace_once(kGood, "alpha: 0.9}", "alpha: 1.2}"), ihs + "; valid: [0, 1]"},
      {replace_once(kGood, "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}", "collision: temperature"),
       "gdsmc_temperature.so) is a diagnostic plugin, but a collision plugin is needed here"},
      {replace_once(kGood, "  - {plugin: temperature}", "  - {plugin: shear_rheology}"),
       "plugin 'shear_rheology' (diagnostics[0], "},
      {replace_once(kGood, "{plugin: inelastic_hard_spheres, alpha: 0.9}", "{plugin: no_such_rule}"),
       "; searched: "},
  };
  for (const auto& [yaml, expected] : cases) {
    SCOPED_TRACE(expected);
    const Refusal r = refuse(yaml, {}, "validate");
    EXPECT_TRUE(contains(r.result.err, expected)) << r.result.err;
  }
  // The begin() refusal of shear_rheology (no shear rate) names its library too.
  const Refusal r = refuse(replace_once(kGood, "  - {plugin: temperature}", "  - {plugin: shear_rheology}"), {}, "validate");
  EXPECT_TRUE(contains(r.result.err, ", library ")) << r.result.err;
  EXPECT_TRUE(contains(r.result.err, "gdsmc_shear_rheology.so): ")) << r.result.err;
  // The unknown plugin's message names the plugin directory it searched.
  const Refusal u = refuse(replace_once(kGood, "{plugin: inelastic_hard_spheres, alpha: 0.9}", "{plugin: no_such_rule}"),
                           {}, "validate");
  const std::string dir = std::filesystem::path(GDSMC_TEST_PLUGIN_DIR).filename().string();
  EXPECT_TRUE(contains(u.result.err, "; searched: ")) << u.result.err;
  EXPECT_TRUE(contains(u.result.err.substr(u.result.err.find("; searched: ")), dir)) << u.result.err;
}

// Several mistakes at once are all reported (the user fixes them in one go).
TEST(BadInput, EveryErrorIsReported) {
  std::string yaml = replace_once(kGood, "alpha: 0.9}", "alpha: 1.2}");
  yaml = replace_once(yaml, "particles: 500", "particles: 0");
  const Refusal r = refuse(yaml);
  EXPECT_TRUE(contains(r.result.err, "alpha")) << r.result.err;
  EXPECT_TRUE(contains(r.result.err, "particles")) << r.result.err;
}

TEST(Validate, GoodAndBadPipelines) {
  TempDir dir;
  const std::string hcs = (gdsmc::test::source_dir() / "configs" / "hcs.yaml").string();
  const ProcessResult ok = run_gdsmc({"validate", hcs}, dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.describe();
  const auto bad = dir.write("bad.yaml", replace_once(kGood, "alpha: 0.9}", "alpha: 1.2}"));
  const ProcessResult no = run_gdsmc({"validate", bad.string()}, dir.path());
  EXPECT_EQ(no.exit_code, 1) << no.describe();
  EXPECT_TRUE(contains(no.err, "alpha")) << no.err;
  // validate writes nothing.
  EXPECT_EQ(dir.files(), std::vector<std::string>{"bad.yaml"});
}

TEST(Cli, HelpAndPluginDocumentation) {
  TempDir dir;
  const ProcessResult help = run_gdsmc({"--help"}, dir.path());
  EXPECT_EQ(help.exit_code, 0) << help.describe();
  for (const char* word : {"run", "validate", "plugins", "--set"}) EXPECT_TRUE(contains(help.out, word)) << word;

  const ProcessResult run_help = run_gdsmc({"run", "--help"}, dir.path());
  EXPECT_EQ(run_help.exit_code, 0) << run_help.describe();
  EXPECT_TRUE(contains(run_help.out, "--set")) << run_help.out;
  EXPECT_TRUE(contains(run_help.out, "--output")) << run_help.out;

  const ProcessResult list = run_gdsmc({"plugins"}, dir.path());
  EXPECT_EQ(list.exit_code, 0) << list.describe();
  for (const char* name : {"inelastic_hard_spheres", "maxwellian", "temperature", "hcs_theory"})
    EXPECT_TRUE(contains(list.out, name)) << name << "\n" << list.out;
  // Listed by kind: the collision rule comes under "collision:", before "initial:".
  const auto collision = list.out.find("collision:");
  const auto ihs = list.out.find("inelastic_hard_spheres");
  const auto initial = list.out.find("initial:");
  EXPECT_TRUE(collision != std::string::npos && initial != std::string::npos && collision < ihs && ihs < initial)
      << list.out;

  const ProcessResult doc = run_gdsmc({"plugins", "inelastic_hard_spheres"}, dir.path());
  EXPECT_EQ(doc.exit_code, 0) << doc.describe();
  EXPECT_TRUE(contains(doc.out, "alpha")) << doc.out;
  EXPECT_TRUE(contains(doc.out, "[0, 1]")) << doc.out;
  const int alpha_line = line_of(doc.out, "alpha (");
  EXPECT_GT(alpha_line, 0) << doc.out;
  EXPECT_EQ(alpha_line, line_of(doc.out, "[0, 1]")) << "the range is on the parameter's line\n" << doc.out;

  const ProcessResult unknown = run_gdsmc({"plugins", "inelastic_hard_sphere"}, dir.path());
  EXPECT_EQ(unknown.exit_code, 1) << unknown.describe();
  EXPECT_TRUE(contains(unknown.err, "inelastic_hard_spheres")) << unknown.err;

  EXPECT_EQ(dir.files(), std::vector<std::string>{});
}

}  // namespace

// The same refusals in-process: each error carries its fields (where, which key, plugin,
// parameter, what is valid, who found it), which `gdsmc conformance` matches instead of the text.
namespace {
const gdsmc::host::ConfigError* error_at(const gdsmc::host::PipelineError& e, const std::string& path) {
  for (const auto& error : e.errors())
    if (error.path == path) return &error;
  return nullptr;
}
}  // namespace

TEST(ConfigErrors, EachErrorCarriesItsLocationPluginParameterAndWhatIsValid) {
  using gdsmc::host::ErrorOrigin;
  TempDir dir;
  std::string yaml = replace_once(kGood, "alpha: 0.9}", "alpha: 1.2, alpah: 1}");
  yaml = replace_once(yaml, "particles: 500", "particles: 1");
  try {
    (void)gdsmc::test::load_yaml(dir, yaml);
    FAIL() << "expected a PipelineError";
  } catch (const gdsmc::host::PipelineError& e) {
    ASSERT_EQ(e.errors().size(), e.messages().size());
    const auto* range = error_at(e, "collision.alpha");
    ASSERT_NE(range, nullptr) << e.what();
    EXPECT_EQ(range->plugin, "inelastic_hard_spheres");
    EXPECT_EQ(range->parameter, "alpha");
    EXPECT_EQ(range->valid, "[0, 1]");
    EXPECT_EQ(range->origin, ErrorOrigin::host_check);
    const std::string file = (dir.path() / "pipeline.yaml").string();
    const std::string line = "collision: {plugin: inelastic_hard_spheres, alpha: ";  // the value's column follows it
    EXPECT_EQ(range->location, file + ":" + std::to_string(line_of(yaml, "alpha: 1.2")) + ":" +
                                   std::to_string(line.size() + 1));
    EXPECT_TRUE(contains(range->text(), "; valid: [0, 1]")) << range->text();
    const auto* unknown = error_at(e, "collision.alpah");
    ASSERT_NE(unknown, nullptr) << e.what();
    EXPECT_EQ(unknown->plugin, "inelastic_hard_spheres");
    EXPECT_EQ(unknown->parameter, "alpah");
    const auto* particles = error_at(e, "run.particles");
    ASSERT_NE(particles, nullptr) << e.what();
    EXPECT_EQ(particles->plugin, "");  // a host key: no plugin, no parameter
    EXPECT_EQ(particles->parameter, "");
  }
}

// A value inside the schema that the plugin's constructor refuses is marked as the plugin's refusal.
TEST(ConfigErrors, APluginsOwnRefusalIsMarkedAsSuch) {
  TempDir dir;
  const std::string yaml = replace_once(kGood, "{plugin: inelastic_hard_spheres, alpha: 0.9}",
                                        "{plugin: enskog_hard_spheres, alpha: 0.9, contact_value: -2}");
  try {
    (void)gdsmc::test::load_yaml(dir, yaml);
    FAIL() << "expected a PipelineError";
  } catch (const gdsmc::host::PipelineError& e) {
    const auto* refused = error_at(e, "collision.contact_value");
    ASSERT_NE(refused, nullptr) << e.what();
    EXPECT_EQ(refused->origin, gdsmc::host::ErrorOrigin::refused_by_plugin);
    EXPECT_EQ(refused->plugin, "enskog_hard_spheres");
    EXPECT_EQ(refused->parameter, "contact_value");
  }
}
