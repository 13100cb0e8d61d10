// The plugin registry's warnings reach `run` and `validate`: a plugin shadowed by a copy that fails
// its ABI check, and a `plugins:` directory that does not exist.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// A user's freshly built inelastic_hard_spheres that fails the ABI check (the wrong_abi test plugin
// under the installed plugin's file name), first on --plugin-path.
fs::path broken_copy(const TempDir& dir) {
  const fs::path plugins = dir.path() / "my-plugins";
  fs::create_directories(plugins);
  const fs::path copy = plugins / "gdsmc_inelastic_hard_spheres.so";
  fs::copy_file(test_plugin("wrong_abi"), copy);
  return copy;
}

TEST(RegistryWarnings, ValidateWarnsAboutAShadowedPluginThatFailsItsAbiCheck) {
  TempDir dir;
  const fs::path copy = broken_copy(dir);
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline);
  const ProcessResult r = run_gdsmc({"validate", file.string(), "--plugin-path", copy.parent_path().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();  // the installed plugin is used, as before
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, copy.string())) << r.describe();
  EXPECT_TRUE(contains(r.err, "rebuild")) << r.describe();
}

TEST(RegistryWarnings, RunWarnsAboutAShadowedPluginThatFailsItsAbiCheck) {
  TempDir dir;
  const fs::path copy = broken_copy(dir);
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline);
  const ProcessResult r =
      run_gdsmc({"run", file.string(), "--quiet", "--plugin-path", copy.parent_path().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, copy.string())) << r.describe();
}

TEST(RegistryWarnings, MissingPluginsDirectoryIsWarnedAbout) {
  TempDir dir;
  const fs::path file = dir.write("pipeline.yaml", kSmallHcsPipeline + "plugins: [no-such-plugin-dir]\n");
  const ProcessResult r = run_gdsmc({"validate", file.string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.err, "warning: ")) << r.describe();
  EXPECT_TRUE(contains(r.err, "no-such-plugin-dir")) << r.describe();
  EXPECT_TRUE(contains(r.err, "does not exist")) << r.describe();
}

}  // namespace
}  // namespace gdsmc::test
