// Host behaviour fixed with the framework layout: registry warnings reach run and validate,
// validate does not allocate particles, sweep cases share one plugin registry, and the
// conformance runner refuses plugin files with the loader's own checks.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "study/cases.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// The first line of `text` that contains `part` ("" if none).
std::string line_with(const std::string& text, const std::string& part) {
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (contains(line, part)) return line;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return "";
}

// A user's freshly built inelastic_hard_spheres that fails the ABI check (the wrong_abi test plugin
// under the installed plugin's file name), first on --plugin-path.
fs::path broken_copy(const TempDir& dir) {
  const fs::path plugins = dir.path() / "my-plugins";
  fs::create_directories(plugins);
  const fs::path copy = plugins / "gdsmc_inelastic_hard_spheres.so";
  fs::copy_file(test_plugin("wrong_abi"), copy);
  return copy;
}

TEST(HostFixes, ValidateWarnsAboutAShadowedPluginThatFailsItsAbiCheck) {
  TempDir dir;
  const fs::path copy = broken_copy(dir);
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline);
  const ProcessResult r = run_gdsmc({"validate", file.string(), "--plugin-path", copy.parent_path().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();  // the installed plugin is used, as before
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, copy.string())) << r.describe();
  EXPECT_TRUE(contains(r.err, "rebuild")) << r.describe();
}

TEST(HostFixes, RunWarnsAboutAShadowedPluginThatFailsItsAbiCheck) {
  TempDir dir;
  const fs::path copy = broken_copy(dir);
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline);
  const ProcessResult r =
      run_gdsmc({"run", file.string(), "--quiet", "--plugin-path", copy.parent_path().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, copy.string())) << r.describe();
}

TEST(HostFixes, MissingPluginsDirectoryIsWarnedAbout) {
  TempDir dir;
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline + "plugins: [no-such-plugin-dir]\n");
  const ProcessResult r = run_gdsmc({"validate", file.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, "no-such-plugin-dir")) << r.describe();
  EXPECT_TRUE(contains(r.err, "does not exist")) << r.describe();
}

// 1e7 particles (about 570 MiB, which fits) under a 1 GB address-space limit: validate passes,
// because it only builds the plugin objects. (4e9 would not fit and is refused with the estimate:
// memory_and_sweep_test.cpp, which also checks that validate never holds the particles.)
TEST(HostFixes, ValidateDoesNotAllocateParticles) {
  TempDir dir;
  std::string yaml = kSmallHcsPipeline;
  yaml.replace(yaml.find("particles: 400"), 14, "particles: 10000000");
  const fs::path file = dir.write("pipeline.yaml", yaml);
  const ShellResult r = shell("bash -c 'ulimit -v 1000000 && exec \"" + executable().string() + "\" validate \"" +
                              file.string() + "\"'");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "10000000 particles")) << r.out;
}

TEST(HostFixes, SweepCasesShareTheBasePipelinesRegistry) {
  TempDir dir;
  const host::Pipeline base = load_yaml(dir, kSmallHcsPipeline + "sweep:\n  collision.alpha: [0.5, 0.7, 0.9]\n");
  const auto cases = host::expand_cases(base);
  ASSERT_EQ(cases.size(), 3u);
  for (const auto& c : cases) {
    EXPECT_EQ(c.pipeline.registry.get(), base.registry.get()) << c.label;
    EXPECT_EQ(c.pipeline.collision.plugin, base.collision.plugin) << c.label;  // the same loaded library
  }
}

// The conformance runner's abi_version check and the loader refuse a file for the same reason,
// in the same words (one implementation of the check).
TEST(HostFixes, ConformanceAbiCheckIsTheLoaders) {
  const fs::path file = test_plugin("conformance_wrong_abi");
  std::string loader_message;
  try {
    (void)host::load_plugin(file);
  } catch (const host::PluginLoadError& e) {
    loader_message = e.what();
  }
  ASSERT_FALSE(loader_message.empty());
  const std::string reason = loader_message.substr(file.string().size() + 2);  // after "<file>: "
  const ShellResult r = shell("'" + executable().string() + "' conformance '" + file.string() + "' --only abi_version");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(contains(line_with(r.out, "abi_version"), reason)) << "'" << reason << "' not in:\n" << r.out;
}

}  // namespace
}  // namespace gdsmc::test
