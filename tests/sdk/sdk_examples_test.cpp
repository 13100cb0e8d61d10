// The SDK as a third party sees it: install this build into a temporary prefix, build each
// project under sdk/examples out of tree against it (find_package(gdsmc) + gdsmc_add_plugin),
// run its YAML pipeline with the installed host, check the datasets it wrote, and run
// `gdsmc conformance` on each of its plugins.
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using Outcome = gdsmc::test::ShellResult;
Outcome sh(const std::string& cmd) { return gdsmc::test::shell(cmd); }

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

std::vector<double> read(const fs::path& file, const std::string& dataset) {
  const gdsmc::host::h5::Handle f = gdsmc::host::h5::open_read_only(file);
  if (!f || !gdsmc::host::h5::exists(f, dataset)) return {};
  return gdsmc::host::h5::read_doubles(f, dataset);
}

bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return !v.empty();
}

// One example project built against a fresh installation.
class SdkExample : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("gdsmc-sdk-examples-" + std::to_string(::getpid()) + "-" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    prefix_ = root_ / "prefix";
    const Outcome r = sh("cmake --install " + q(GDSMC_BINARY_DIR) + " --prefix " + q(prefix_));
    ASSERT_EQ(r.status, 0) << r.out;
    gdsmc_ = prefix_ / "bin" / "gdsmc";
    ASSERT_TRUE(fs::exists(gdsmc_));
    ASSERT_TRUE(fs::exists(prefix_ / "include/gdsmc/gdsmc.hpp"));
    ASSERT_TRUE(fs::exists(prefix_ / "lib/cmake/gdsmc/gdsmcConfig.cmake"));
    // The CMake package carries the release the SDK headers state (project() in the top-level
    // CMakeLists.txt and GDSMC_VERSION_STRING are set by hand: they must agree).
    const std::string version_file = gdsmc::test::read_text(prefix_ / "lib/cmake/gdsmc/gdsmcConfigVersion.cmake");
    EXPECT_NE(version_file.find("set(PACKAGE_VERSION \"" GDSMC_VERSION_STRING "\")"), std::string::npos)
        << "package version differs from GDSMC_VERSION_STRING " GDSMC_VERSION_STRING;
    ASSERT_TRUE(fs::exists(prefix_ / "lib/gdsmc/plugins/gdsmc_maxwellian.so"));
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(root_);
  }
  // Configure and build sdk/examples/<name> out of tree; returns its build directory.
  fs::path build(const std::string& name) {
    const fs::path src = fs::path(GDSMC_SOURCE_DIR) / "sdk/examples" / name;
    const fs::path dir = root_ / ("build-" + name);
    Outcome r = sh("cmake -S " + q(src) + " -B " + q(dir) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + q(prefix_));
    EXPECT_EQ(r.status, 0) << r.out;
    r = sh("cmake --build " + q(dir) + " -j2");
    EXPECT_EQ(r.status, 0) << r.out;
    return dir;
  }
  // Run the example's pipeline with the installed host; returns the output file.
  fs::path run(const std::string& name, const std::string& yaml, const fs::path& dir, const std::string& extra = "") {
    const fs::path file = dir / ("out-" + std::to_string(runs_++) + ".h5");
    const Outcome r = sh(q(gdsmc_) + " run " + q(fs::path(GDSMC_SOURCE_DIR) / "sdk/examples" / name / yaml) +
                         " --plugin-path " + q(dir / "plugins") + " --output " + q(file) + " --quiet " + extra);
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_TRUE(fs::exists(file)) << r.out;
    return file;
  }
  void conforms(const fs::path& plugin, const std::string& extra = "") {
    const Outcome r = sh(q(gdsmc_) + " conformance " + q(plugin) + " " + extra);
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find(": conforming"), std::string::npos) << r.out;
  }

  fs::path root_, prefix_, gdsmc_;
  int runs_ = 0;
};

}  // namespace

TEST_F(SdkExample, ViscoelasticRestitution) {
  const fs::path dir = build("viscoelastic_restitution");
  const fs::path plugin = dir / "plugins/gdsmc_viscoelastic_restitution.so";
  ASSERT_TRUE(fs::exists(plugin));
  const fs::path h5 = run("viscoelastic_restitution", "viscoelastic.yaml", dir);
  const auto T = read(h5, "/diagnostics/temperature/temperature");
  ASSERT_TRUE(all_finite(T));
  EXPECT_DOUBLE_EQ(T.front(), 1.0);
  EXPECT_LT(T.back(), 0.99);  // it cools
  EXPECT_GT(T.back(), 0.05);
  for (std::size_t k = 1; k < T.size(); ++k) EXPECT_LE(T[k], T[k - 1] * (1 + 1e-3)) << k;  // cools monotonically (to noise)
  conforms(plugin);
  // the installed host finds the plugin by name once it is installed into the same prefix
  const Outcome r = sh("cmake --install " + q(dir) + " --prefix " + q(prefix_));
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(fs::exists(prefix_ / "lib/gdsmc/plugins/gdsmc_viscoelastic_restitution.so"));
  const Outcome p = sh(q(gdsmc_) + " plugins viscoelastic_restitution");
  EXPECT_EQ(p.status, 0) << p.out;
  EXPECT_NE(p.out.find("Brilliantov"), std::string::npos) << p.out;
}

// A mixture rule (SDK 6.5): restitution per pair of species and impact speed. It passes
// collision.species (sum m v and the mass-weighted energy in a two-species system), and the binary
// mixture of its pipeline (small: m = 1, sigma = 1; large: m = 8, sigma = 2) cools.
TEST_F(SdkExample, ViscoelasticMixture) {
  const fs::path dir = build("viscoelastic_mixture");
  const fs::path plugin = dir / "plugins/gdsmc_viscoelastic_mixture.so";
  ASSERT_TRUE(fs::exists(plugin));
  const Outcome c = sh(q(gdsmc_) + " conformance " + q(plugin) + " --only collision.species");
  EXPECT_EQ(c.status, 0) << c.out;
  EXPECT_NE(c.out.find("PASS   collision.species"), std::string::npos) << c.out;
  conforms(plugin);
  const fs::path h5 = run("viscoelastic_mixture", "viscoelastic_mixture.yaml", dir);
  const auto T = read(h5, "/diagnostics/temperature/temperature");
  ASSERT_TRUE(all_finite(T));
  EXPECT_NEAR(T.front(), 1.0, 0.05);  // the mass-weighted temperature of the initial Maxwellians
  EXPECT_LT(T.back(), 0.95 * T.front());  // it cools
  EXPECT_GT(T.back(), 0.05);
}

TEST_F(SdkExample, RoughSpheres) {
  const fs::path dir = build("rough_spheres");
  const fs::path rule = dir / "plugins/gdsmc_rough_spheres.so";
  const fs::path diag = dir / "plugins/gdsmc_rotational_temperature.so";
  ASSERT_TRUE(fs::exists(rule));
  ASSERT_TRUE(fs::exists(diag));
  const fs::path h5 = run("rough_spheres", "rough_spheres.yaml", dir);
  const auto t_rot = read(h5, "/diagnostics/rotational_temperature/rotational_temperature");
  const auto ratio = read(h5, "/diagnostics/rotational_temperature/temperature_ratio");
  ASSERT_TRUE(all_finite(t_rot));
  ASSERT_TRUE(all_finite(ratio));
  EXPECT_EQ(t_rot.front(), 0.0);  // spins start at rest
  EXPECT_GT(t_rot.back(), 0.05);  // and are spun up by the rough collisions
  const auto omega = read(h5, "/particles/angular_velocity");
  EXPECT_EQ(omega.size(), 3u * 5000u);
  EXPECT_TRUE(all_finite(omega));
  // alpha = beta = 1: the total energy (3/2)(T_tr + T_rot) is conserved to round-off
  const fs::path elastic = run("rough_spheres", "rough_spheres.yaml", dir, "--set collision.alpha=1 --set collision.beta=1");
  const auto e = read(elastic, "/diagnostics/rotational_temperature/energy_per_particle");
  const auto t_rot_e = read(elastic, "/diagnostics/rotational_temperature/rotational_temperature");
  ASSERT_TRUE(all_finite(e));
  for (double x : e) EXPECT_NEAR(x, 1.5, 1e-9);
  EXPECT_GT(t_rot_e.back(), 0.05);
  conforms(rule);
  conforms(diag, "--context " + q(fs::path(GDSMC_SOURCE_DIR) / "sdk/examples/rough_spheres/rough_spheres.yaml") +
                     " --plugin-path " + q(dir / "plugins"));
  // The project's own CTest runs the same conformance checks (gdsmc_add_plugin registers them).
  const Outcome c = sh("ctest --test-dir " + q(dir));
  EXPECT_EQ(c.status, 0) << c.out;
}

TEST_F(SdkExample, SpeedDistributionWritesItsOwnDatasets) {
  const fs::path dir = build("speed_distribution");
  const fs::path plugin = dir / "plugins/gdsmc_speed_distribution.so";
  ASSERT_TRUE(fs::exists(plugin));
  const fs::path h5 = run("speed_distribution", "speed_distribution.yaml", dir);
  const std::string g = "/diagnostics/speed_distribution/";
  const auto mean = read(h5, g + "mean_speed");
  const auto time = read(h5, g + "time");
  ASSERT_TRUE(all_finite(mean));
  EXPECT_EQ(mean.size(), time.size());
  EXPECT_NEAR(mean.front(), 2.0 / std::sqrt(M_PI), 0.02);  // Maxwellian <c>
  const auto edges = read(h5, g + "speed_pdf/edges");
  const auto values = read(h5, g + "speed_pdf/values");
  ASSERT_EQ(values.size(), 32u);
  ASSERT_EQ(edges.size(), 33u);
  EXPECT_DOUBLE_EQ(edges.back(), 4.0);
  double integral = 0;
  for (std::size_t b = 0; b < values.size(); ++b) integral += values[b] * (edges[b + 1] - edges[b]);
  const auto overflow = read(h5, g + "overflow_fraction");
  ASSERT_EQ(overflow.size(), 1u);
  EXPECT_NEAR(integral + overflow[0], 1.0, 1e-9);
  EXPECT_EQ(read(h5, g + "maxwellian_pdf").size(), 32u);
  const auto samples = read(h5, g + "samples");
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_GT(samples[0], 1.0);
  conforms(plugin);
}

// The documented configure line (section 1 of the plugin author guide) sets no build type: the
// plugin must still be compiled with the in-tree Release optimisation (-O3 -DNDEBUG), because the
// SDK compiles the whole per-cell collision loop into it. The author's own build type wins, and
// GDSMC_PLUGIN_DEFAULT_OPTIMIZATION=OFF turns the default off. Checked on the compile commands,
// not on timings. CONFORMANCE_PARAMS registers one conformance test per parameter set.
TEST_F(SdkExample, DocumentedBuildIsOptimised) {
  const std::string name = "viscoelastic_restitution";
  const fs::path src = fs::path(GDSMC_SOURCE_DIR) / "sdk/examples" / name;
  // The plugin's compile command in <dir>/compile_commands.json after configuring with `extra`.
  auto compile_command = [&](const std::string& tag, const std::string& extra, bool build_it) {
    const fs::path dir = root_ / ("build-" + tag);
    Outcome r = sh("cmake -S " + q(src) + " -B " + q(dir) + " -DCMAKE_PREFIX_PATH=" + q(prefix_) +
                   " -DCMAKE_EXPORT_COMPILE_COMMANDS=ON " + extra);
    EXPECT_EQ(r.status, 0) << r.out;
    if (build_it) {
      r = sh("cmake --build " + q(dir) + " -j2");
      EXPECT_EQ(r.status, 0) << r.out;
      EXPECT_TRUE(fs::exists(dir / ("plugins/gdsmc_" + name + ".so")));
    }
    const std::string json = gdsmc::test::read_text(dir / "compile_commands.json");
    const auto at = json.find(name + ".cpp\"");
    EXPECT_NE(at, std::string::npos) << json;
    const auto begin = json.rfind("\"command\"", at);
    return begin == std::string::npos ? json : json.substr(begin, json.find('\n', begin) - begin);
  };
  // The documented way: no build type at all.
  const std::string documented = compile_command("documented", "", true);
  EXPECT_NE(documented.find(" -O3"), std::string::npos) << documented;
  EXPECT_NE(documented.find("-DNDEBUG"), std::string::npos) << documented;
  // The author's build type wins.
  const std::string debug = compile_command("debug", "-DCMAKE_BUILD_TYPE=Debug", false);
  EXPECT_EQ(debug.find(" -O3"), std::string::npos) << debug;
  EXPECT_NE(debug.find(" -g"), std::string::npos) << debug;
  const std::string own_flags = compile_command("own-flags", "'-DCMAKE_CXX_FLAGS=-O1'", false);
  EXPECT_EQ(own_flags.find(" -O3"), std::string::npos) << own_flags;
  EXPECT_NE(own_flags.find(" -O1"), std::string::npos) << own_flags;
  const std::string off = compile_command("off", "-DGDSMC_PLUGIN_DEFAULT_OPTIMIZATION=OFF", false);
  EXPECT_EQ(off.find(" -O"), std::string::npos) << off;

  // CONFORMANCE_PARAMS: one CTest test per parameter set, each with --params <file>.
  const fs::path project = root_ / "params-project";
  fs::create_directories(project);
  fs::copy_file(src / (name + ".cpp"), project / (name + ".cpp"));
  {
    std::ofstream(project / "soft.yaml") << "delta: 0.4\n";
    std::ofstream(project / "hard.yaml") << "delta: 0.05\nepsilon_min: 0.5\n";
    std::ofstream(project / "CMakeLists.txt")
        << "cmake_minimum_required(VERSION 3.20)\nproject(params_project LANGUAGES CXX)\n"
           "find_package(gdsmc CONFIG REQUIRED)\nenable_testing()\n"
           "gdsmc_add_plugin(" << name << " SOURCES " << name << ".cpp CONFORMANCE_PARAMS soft.yaml hard.yaml)\n";
  }
  const fs::path pdir = root_ / "build-params";
  Outcome r = sh("cmake -S " + q(project) + " -B " + q(pdir) + " -DCMAKE_PREFIX_PATH=" + q(prefix_));
  ASSERT_EQ(r.status, 0) << r.out;
  r = sh("ctest --test-dir " + q(pdir) + " -N -V");
  EXPECT_EQ(r.status, 0) << r.out;
  for (const std::string& t : std::vector<std::string>{"gdsmc_conformance_" + name, "gdsmc_conformance_" + name + "_soft",
                                                        "gdsmc_conformance_" + name + "_hard"})
    EXPECT_NE(r.out.find(": " + t + "\n"), std::string::npos) << t << ":\n" << r.out;
  EXPECT_NE(r.out.find("--params\" \"" + (project / "soft.yaml").string()), std::string::npos) << r.out;
}

// A forcing: white noise heats an inelastic gas to the steady state where the heating h T0/tau0
// balances the collisional cooling; Maxwellian estimate (2/3)(1 - alpha^2) T_s^(3/2) / sqrt(pi) = h
// gives T_s = 2.39 T0 for h = 0.5, alpha = 0.8.
TEST_F(SdkExample, WhiteNoiseThermostat) {
  const fs::path dir = build("white_noise_heating");
  const fs::path plugin = dir / "plugins/gdsmc_white_noise_heating.so";
  ASSERT_TRUE(fs::exists(plugin));
  const fs::path h5 = run("white_noise_heating", "white_noise_heating.yaml", dir);
  const auto T = read(h5, "/diagnostics/temperature/temperature");
  ASSERT_TRUE(all_finite(T));
  ASSERT_GT(T.size(), 30u);
  EXPECT_NEAR(T.front(), 1.0, 1e-12);
  double late = 0;
  for (std::size_t k = T.size() - 30; k < T.size(); ++k) late += T[k] / 30;
  EXPECT_NEAR(late, 2.39, 0.15);  // heated to the steady state
  conforms(plugin);                // forcing.energy and forcing.expected_energy pass
}

// A wall: Cercignani-Lampis walls at T_w = 1 and 2 on the planes of an elastic slab. Heat flows
// from y_max to y_min, the profile rises monotonically between the walls with temperature jumps
// at both, and partial accommodation (a_n = 0.5, a_t = 0.3) passes less heat than the fully
// diffuse limit a_n = a_t = 1.
TEST_F(SdkExample, CercignaniLampisWall) {
  const fs::path dir = build("cercignani_lampis_wall");
  const fs::path plugin = dir / "plugins/gdsmc_cercignani_lampis_wall.so";
  ASSERT_TRUE(fs::exists(plugin));
  const std::string yaml = "cercignani_lampis_wall.yaml";
  const fs::path h5 = run("cercignani_lampis_wall", yaml, dir);
  const auto T = read(h5, "/diagnostics/profiles/T.steady_mean");
  const auto q = read(h5, "/diagnostics/profiles/q_y.steady_mean");
  ASSERT_EQ(T.size(), 10u);
  ASSERT_TRUE(all_finite(T));
  ASSERT_TRUE(all_finite(q));
  EXPECT_GT(T.front(), 1.05);  // jump at the cold wall (T_w = 1)
  EXPECT_LT(T.back(), 1.95);   // and at the hot one (T_w = 2)
  EXPECT_GT(T.back(), T.front() + 0.1);
  double q_mean = 0;
  for (double x : q) q_mean += x / static_cast<double>(q.size());
  EXPECT_LT(q_mean, 0);  // heat flows towards y_min
  const fs::path diffuse = run("cercignani_lampis_wall", yaml, dir,
                               "--set boundaries.y_min.normal_accommodation=1 --set boundaries.y_min.tangential_accommodation=1 "
                               "--set boundaries.y_max.normal_accommodation=1 --set boundaries.y_max.tangential_accommodation=1");
  const auto qd = read(diffuse, "/diagnostics/profiles/q_y.steady_mean");
  ASSERT_TRUE(all_finite(qd));
  double qd_mean = 0;
  for (double x : qd) qd_mean += x / static_cast<double>(qd.size());
  EXPECT_LT(qd_mean, 1.5 * q_mean);  // the diffuse walls pass more heat (about twice as much)
  conforms(plugin);
}

// An initial state: the two-temperature Maxwellian starts at T = T0 with the fourth cumulant
// a2 = (f T_hot^2 + (1 - f) T_cold^2)/T0^2 - 1 = 0.64 (f = 1/2, r = 9), which the collisions erase.
TEST_F(SdkExample, BimodalMaxwellian) {
  const fs::path dir = build("bimodal_maxwellian");
  const fs::path plugin = dir / "plugins/gdsmc_bimodal_maxwellian.so";
  ASSERT_TRUE(fs::exists(plugin));
  const fs::path h5 = run("bimodal_maxwellian", "bimodal_maxwellian.yaml", dir);
  const auto T = read(h5, "/diagnostics/temperature/temperature");
  const auto a2 = read(h5, "/diagnostics/cumulants/a2");
  ASSERT_TRUE(all_finite(T));
  ASSERT_TRUE(all_finite(a2));
  EXPECT_NEAR(T.front(), 1.0, 1e-12);
  EXPECT_NEAR(a2.front(), 0.64, 0.12);  // sampling error of a2 on 5000 particles is about 0.05
  EXPECT_LT(std::fabs(a2.back()), 0.05);
  conforms(plugin);
}
