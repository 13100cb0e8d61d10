// The plugin loader: ABI checks, non-plugins, object lifetime, the registry, failing factories.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <memory>
#include <string>
#include <vector>

#include "conformance/internal.hpp"
#include "engine/streams.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;
using gdsmc::host::LoadedPlugin;
using gdsmc::host::PluginLoadError;
using gdsmc::host::PluginRegistry;

// The message of the PluginLoadError that loading `file` throws ("" if it loads).
std::string load_error(const fs::path& file) {
  try {
    (void)gdsmc::host::load_plugin(file);
  } catch (const PluginLoadError& e) {
    return e.what();
  }
  return "";
}

TEST(Loader, TestPluginsWereBuilt) {
  for (const char* name : {"wrong_abi", "not_a_plugin", "throwing_factory", "failing_finish"})
    EXPECT_TRUE(fs::is_regular_file(test_plugin(name))) << test_plugin(name);
}

// A plugin whose entry declares another ABI major (the test plugin claims 1.0: built against the
// old SDK 1.x) is refused before its descriptor is read (the test plugin's describe() aborts),
// with the file, both versions and what to do.
TEST(Loader, WrongAbiMajorIsRefused) {
  static_assert(GDSMC_SDK_ABI_MAJOR != 1, "the wrong_abi test plugin claims ABI 1.0");
  const fs::path file = test_plugin("wrong_abi");
  const std::string message = load_error(file);
  ASSERT_FALSE(message.empty()) << "a plugin with ABI major 1 was loaded by a host with ABI major "
                                << GDSMC_SDK_ABI_MAJOR;
  EXPECT_TRUE(contains(message, file.string())) << message;
  const std::string plugin_version = "1.0";
  const std::string host_version = std::to_string(GDSMC_SDK_ABI_MAJOR) + "." + std::to_string(GDSMC_SDK_ABI_MINOR);
  EXPECT_TRUE(contains(message, plugin_version)) << message;
  EXPECT_TRUE(contains(message, host_version)) << message;
  EXPECT_TRUE(contains(message, "rebuild")) << message;
  // An older major (every 5.x plugin since SDK 6.0) is pointed at the porting guide.
  EXPECT_TRUE(contains(message, "Porting to SDK 6.0")) << message;
  // Named explicitly on the search path: an error; found by scanning a directory: a warning.
  PluginRegistry explicit_file;
  EXPECT_THROW(explicit_file.add(file), PluginLoadError);
  // (Scanned in a directory of its own: test-plugins also holds other deliberately broken plugins.)
  TempDir dir;
  const fs::path copy = dir.path() / file.filename();
  fs::copy_file(file, copy);
  PluginRegistry scanned;
  scanned.add(dir.path());
  EXPECT_EQ(scanned.find("wrong_abi"), nullptr);
  EXPECT_TRUE(scanned.plugins().empty());
  bool warned = false;
  for (const auto& w : scanned.warnings()) warned = warned || (contains(w, copy.string()) && contains(w, "rebuild"));
  EXPECT_TRUE(warned) << join(scanned.warnings(), "\n");
}

TEST(Loader, SharedLibraryThatIsNotAPluginIsRefused) {
  const fs::path file = test_plugin("not_a_plugin");
  const std::string message = load_error(file);
  EXPECT_TRUE(contains(message, "not a gdsmc plugin")) << message;
  EXPECT_TRUE(contains(message, file.string())) << message;
  // A file that is not a shared library at all.
  TempDir dir;
  const fs::path junk = dir.write("gdsmc_junk.so", "this is not an ELF file\n");
  const std::string junk_message = load_error(junk);
  EXPECT_TRUE(contains(junk_message, junk.string())) << junk_message;
  EXPECT_FALSE(junk_message.empty());
}

// Through the executable: `gdsmc plugins FILE.so` on each broken file fails cleanly (exit 1,
// no crash) with the same messages.
TEST(Loader, ExecutableRefusesBrokenPluginFiles) {
  TempDir dir;
  const ProcessResult abi = run_gdsmc({"plugins", test_plugin("wrong_abi").string()}, dir.path());
  EXPECT_EQ(abi.exit_code, 1) << abi.describe();
  EXPECT_TRUE(contains(abi.err, "rebuild")) << abi.describe();
  const ProcessResult other = run_gdsmc({"plugins", test_plugin("not_a_plugin").string()}, dir.path());
  EXPECT_EQ(other.exit_code, 1) << other.describe();
  EXPECT_TRUE(contains(other.err, "not a gdsmc plugin")) << other.describe();
  // On the search path of a run: refused with the file named, nothing run.
  const ProcessResult run = run_gdsmc({"validate", (source_dir() / "configs" / "hcs.yaml").string(), "--plugin-path",
                                       test_plugin("wrong_abi").string()},
                                      dir.path());
  EXPECT_EQ(run.exit_code, 1) << run.describe();
  EXPECT_TRUE(contains(run.err, test_plugin("wrong_abi").string())) << run.describe();
}

// The layout fingerprint names no compiler (SDK 2.0): a tiny program printing abi_fingerprint(),
// compiled with g++ and with clang++ against the same SDK headers and standard library, prints
// the same value, and the value this test (built like the host) computes. Skipped when clang++
// is not installed.
TEST(Loader, FingerprintDoesNotDependOnTheCompiler) {
  if (shell("command -v clang++").status != 0) GTEST_SKIP() << "clang++ is not installed";
  if (shell("command -v g++").status != 0) GTEST_SKIP() << "g++ is not installed";
  TempDir dir;
  const fs::path src = dir.write("fingerprint.cpp",
                                 "#include <cstdio>\n"
                                 "#include <gdsmc/plugin.hpp>\n"
                                 "int main() {\n"
                                 "  std::printf(\"%llu\\n\", static_cast<unsigned long long>(gdsmc::abi_fingerprint()));\n"
                                 "}\n");
  const std::string include = "-I'" + (source_dir() / "sdk" / "include").string() + "'";
  auto fingerprint_with = [&](const std::string& compiler) -> std::string {
    const fs::path exe = dir / ("fingerprint_" + compiler);
    const ShellResult build =
        shell(compiler + " -std=c++20 " + include + " '" + src.string() + "' -o '" + exe.string() + "'");
    if (build.status != 0) {
      ADD_FAILURE() << compiler << " could not build the fingerprint program:\n" << build.out;
      return "";
    }
    const ShellResult run = shell("'" + exe.string() + "'");
    EXPECT_EQ(run.status, 0) << run.out;
    return run.out;
  };
  const std::string gcc = fingerprint_with("g++");
  const std::string clang = fingerprint_with("clang++");
  const std::string here = std::to_string(gdsmc::abi_fingerprint()) + "\n";
  EXPECT_EQ(gcc, here) << "g++ and the host's compiler disagree";
  EXPECT_EQ(clang, gcc) << "g++ and clang++ disagree on the fingerprint";
}

// A plugin class with a wrong base (here PluginObject alone) does not compile: GDSMC_PLUGIN names
// the problem, where SDK 1.x registered it as a collision rule and cast it (undefined behaviour).
// The same file with the right base compiles, so the failure is the base and nothing else.
TEST(Loader, PluginClassWithAWrongBaseIsACompileError) {
  if (shell("command -v g++").status != 0) GTEST_SKIP() << "g++ is not installed";
  TempDir dir;
  auto source = [](const std::string& base) {
    return "#include <gdsmc/gdsmc.hpp>\n"
           "struct Probe final : " + base + " {\n"
           "  static constexpr const char* name = \"probe\";\n"
           "  static constexpr const char* version = \"1.0.0\";\n"
           "  static constexpr const char* summary = \"probe\";\n"
           "  static constexpr const char* documentation = \"probe\";\n"
           "  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }\n"
           "  explicit Probe(const gdsmc::Params&) {}\n"
           "  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink&) {}\n"
           "  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) {}\n"
           "  void record(const gdsmc::StepContext&, gdsmc::OutputSink&) {}\n"
           "};\n"
           "GDSMC_PLUGIN(Probe)\n";
  };
  const std::string flags = "g++ -std=c++20 -fsyntax-only -DBOOST_DLL_USE_STD_FS -I'" +
                            (source_dir() / "sdk" / "include").string() + "' ";
  const fs::path wrong = dir.write("wrong.cpp", source("gdsmc::PluginObject"));
  const fs::path right = dir.write("right.cpp", source("gdsmc::Diagnostic"));
  const ShellResult bad = shell(flags + "'" + wrong.string() + "' 2>&1");
  EXPECT_NE(bad.status, 0) << bad.out;
  EXPECT_NE(bad.out.find("must derive from exactly one of"), std::string::npos) << bad.out;
  const ShellResult good = shell(flags + "'" + right.string() + "' 2>&1");
  EXPECT_EQ(good.status, 0) << good.out;
}

// Whether the shared library `file` is mapped in this process (dlopen with RTLD_NOLOAD never
// loads; it only finds a library already loaded).
bool is_loaded(const fs::path& file) {
  void* h = ::dlopen(file.c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (!h) return false;
  ::dlclose(h);
  return true;
}

// An object made by a plugin holds its library: with the registry (and every LoadedPlugin)
// gone, the library stays mapped and the object's code still runs.
TEST(Loader, ObjectKeepsItsLibraryAlive) {
  const fs::path file = plugin_dir() / "gdsmc_inelastic_hard_spheres.so";
  ASSERT_TRUE(fs::is_regular_file(file));
  std::shared_ptr<gdsmc::PluginObject> object;
  {
    auto registry = std::make_unique<PluginRegistry>();
    registry->add(file);
    const LoadedPlugin* lp = registry->find("inelastic_hard_spheres");
    ASSERT_NE(lp, nullptr);
    gdsmc::Params params;
    params.set("alpha", 0.5);
    params.set("restitution_pairs", std::string(""));  // every declared parameter (the loader fills no defaults)
    object = gdsmc::host::create_object(*lp, params);
    ASSERT_TRUE(is_loaded(file));
  }  // registry destroyed
  EXPECT_TRUE(is_loaded(file)) << "the library was unloaded while an object made by it is alive";
  auto* rule = dynamic_cast<gdsmc::CollisionRule*>(object.get());
  ASSERT_NE(rule, nullptr);
  // Call into the library: pair_rate of the hard-sphere kernel is g.s for g.s > 0 (exact here).
  EXPECT_EQ(rule->pair_rate({2.0, 0.0, 0.0}, {1.0, 0.0, 0.0}), 2.0);
  EXPECT_EQ(rule->pair_rate({-2.0, 0.0, 0.0}, {1.0, 0.0, 0.0}), 0.0);
  // And a collision: v1 = (1,0,0), v2 = 0, s = x: v1' = (1 - 0.75, 0, 0), v2' = (0.75, 0, 0) for
  // alpha = 0.5 (000 Eq. 2.8); energy change -(1 - alpha^2)/4 (g.s)^2 = -0.1875. All exact in binary.
  std::vector<double> vx = {1.0, 0.0}, vy = {0.0, 0.0}, vz = {0.0, 0.0}, x(2), y(2), z(2);
  const std::vector<std::uint32_t> ids = {0, 1};
  const std::vector<std::uint32_t> cells = {0, 0};
  gdsmc::ParticleSpan span;
  span.count = 2;
  span.id = ids.data();
  span.cell = cells.data();
  span.x = x.data(); span.y = y.data(); span.z = z.data();
  span.vx = vx.data(); span.vy = vy.data(); span.vz = vz.data();
  rule->bind(span);
  gdsmc::Rng rng = gdsmc::host::StreamFactory::standalone(1, 0);
  // The pair kernel on a batch of one pair with its impact direction given (as conformance calls it).
  std::vector<double> no_tally;
  const double energy_change =
      gdsmc::host::conformance::collide_with_direction(*rule, span, 0, 1, {1.0, 0.0, 0.0}, 1.0, rng, no_tally);
  EXPECT_EQ(vx[0], 0.25) << "the pair collided and its velocities were written back";
  EXPECT_EQ(vx[1], 0.75);
  EXPECT_EQ(energy_change, -0.1875);
  object.reset();  // the library may now be unloaded; nothing of it is used again
}

// The registry scans the in-tree plugin directory and lists the plugins by kind.
TEST(Loader, RegistryListsInTreePluginsByKind) {
  PluginRegistry reg;
  reg.add(plugin_dir());
  EXPECT_EQ(reg.warnings(), std::vector<std::string>{}) << "in-tree plugins should all load";
  using gdsmc::PluginKind;
  auto has = [&](PluginKind kind, const std::string& name) {
    const auto names = reg.names_of_kind(kind);
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  EXPECT_TRUE(has(PluginKind::collision_rule, "inelastic_hard_spheres"));
  EXPECT_TRUE(has(PluginKind::initial_state, "maxwellian"));
  for (const char* d : {"temperature", "cumulants", "pressure_tensor", "collision_count", "hcs_theory"})
    EXPECT_TRUE(has(PluginKind::diagnostic, d)) << d;
  // Every plugin is listed under exactly its own kind.
  for (const auto& lp : reg.plugins()) {
    for (auto kind : {PluginKind::collision_rule, PluginKind::forcing, PluginKind::boundary, PluginKind::initial_state,
                      PluginKind::diagnostic})
      EXPECT_EQ(has(kind, lp.descriptor->name), kind == lp.descriptor->kind) << lp.descriptor->name;
    EXPECT_EQ(lp.abi_major, gdsmc::sdk_abi_major);
    EXPECT_FALSE(lp.descriptor->version.empty());
    EXPECT_EQ(reg.find(lp.descriptor->name), &lp);
  }
  EXPECT_FALSE(has(PluginKind::diagnostic, "inelastic_hard_spheres"));
  EXPECT_EQ(reg.find("no_such_plugin"), nullptr);
}

// A factory that throws: create_object passes the exception on (it does not crash or leak a
// half-made object), and a pipeline using the plugin is refused with a message that names the
// plugin, where it is used, and what it said.
TEST(Loader, ThrowingFactoryGivesClearError) {
  PluginRegistry reg;
  reg.add(test_plugin("throwing_factory"));
  const LoadedPlugin* lp = reg.find("throwing_factory");
  ASSERT_NE(lp, nullptr);
  gdsmc::Params params;
  params.set("mode", std::string("runtime_error"));
  params.set("limit", 0.5);
  try {
    (void)gdsmc::host::create_object(*lp, params);
    ADD_FAILURE() << "the factory did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "deliberate failure")) << e.what();
  }

  TempDir dir;
  const std::string yaml = R"(run:
  particles: 100
  time_step: 0.01
  stop: {collisions_per_particle: 1}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: inelastic_hard_spheres
diagnostics:
  - {plugin: throwing_factory}
)";
  const fs::path file = dir.write("pipeline.yaml", yaml);
  auto refused = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      (void)gdsmc::host::load_pipeline(file, overrides, {plugin_dir(), test_plugin("throwing_factory")});
    } catch (const gdsmc::host::PipelineError& e) {
      return e.what();
    }
    return "";
  };
  const std::string runtime = refused({});
  EXPECT_TRUE(contains(runtime, "throwing_factory")) << runtime;
  EXPECT_TRUE(contains(runtime, "deliberate failure in the throwing_factory constructor")) << runtime;
  EXPECT_TRUE(contains(runtime, "diagnostics[0]")) << runtime;
  EXPECT_TRUE(contains(runtime, file.string() + ":" + std::to_string(line_of(yaml, "throwing_factory")) + ":"))
      << runtime;
  // A ParameterError names the parameter and where its value came from.
  const std::string parameter = refused({"diagnostics[0].mode=none", "diagnostics[0].limit=3"});
  EXPECT_TRUE(contains(parameter, "limit")) << parameter;
  EXPECT_TRUE(contains(parameter, "deliberate ParameterError")) << parameter;
  EXPECT_TRUE(contains(parameter, "--set diagnostics[0].limit=3")) << parameter;
  // With a value it accepts, the same pipeline loads.
  EXPECT_EQ(refused({"diagnostics[0].mode=none"}), "");

  // The executable says the same and exits 1.
  const ProcessResult r = run_gdsmc({"run", file.string(), "--plugin-path", test_plugin("throwing_factory").string()},
                                    dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_TRUE(contains(r.err, "deliberate failure")) << r.describe();
  EXPECT_EQ(dir.files(), std::vector<std::string>{"pipeline.yaml"});
}

}  // namespace
