// `gdsmc conformance` on every plugin of the build, and on deliberately bad test plugins
// (tests/test_plugins/conformance_*), each of which must fail with a message naming the plugin and the
// broken property.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gdsmc/version.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using Outcome = gdsmc::test::ShellResult;

// `gdsmc ARGS` (ARGS quoted by the caller).
Outcome run(const std::string& args) { return gdsmc::test::shell(std::string("'") + GDSMC_EXECUTABLE + "' " + args); }

std::string test_plugin(const std::string& name) {
  return std::string(GDSMC_BINARY_DIR) + "/test-plugins/gdsmc_" + name + ".so";
}

// The line of the output that reports `check`, or "".
std::string line_of(const std::string& out, const std::string& check) {
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string status, name;
    words >> status >> name;
    if (name == check) return line;
  }
  return "";
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("gdsmc-conformance-test-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

}  // namespace

// Run bare, as a plugin author first would: every shipped plugin conforms, those that need more
// than a homogeneous gas (a slab, a shear rate, a heat-flux forcing) in the context they ship
// (GDSMC_CONFORMANCE_CONTEXT), and the runner says which context it used. The old runner had no
// shipped contexts: 9 of them were NOT CONFORMING without --context.
TEST(Conformance, EveryPluginOfTheBuildConformsBareInTheContextItShips) {
  const fs::path dir = GDSMC_TEST_PLUGIN_DIR;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".so") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const char* needed : {"inelastic_hard_spheres", "maxwellian", "temperature"})
    EXPECT_TRUE(fs::exists(dir / ("gdsmc_" + std::string(needed) + ".so"))) << needed;
  const std::set<std::string> shipping = {"delta_shell",       "enskog_hard_spheres", "enskog_shear_viscosity",
                                          "heat_flux",         "mixture_theory",      "poiseuille_channel",  "profiles",
                                          "shear_rheology",    "slab_averages",       "wall_fluxes"};
  std::size_t shipped = 0;
  for (const auto& f : files) {
    std::string name = f.stem().string();
    if (name.rfind("gdsmc_", 0) == 0) name = name.substr(6);
    const Outcome r = run("conformance '" + f.string() + "'");
    EXPECT_EQ(r.status, 0) << "plugin " << name << " does not conform:\n" << r.out;
    EXPECT_NE(r.out.find(": conforming"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("CRASH"), std::string::npos) << r.out;
    const bool ships = r.out.find("context: shipped by the plugin (GDSMC_CONFORMANCE_CONTEXT): {") != std::string::npos;
    EXPECT_EQ(ships, shipping.count(name) == 1) << name << ":\n" << r.out;
    if (!ships) EXPECT_NE(r.out.find("context: the default: a homogeneous system"), std::string::npos) << r.out;
    shipped += ships;
  }
  EXPECT_EQ(shipped, shipping.size());
}

struct BadPlugin {
  const char* plugin;
  const char* check;
  std::vector<const char*> words;  // each must appear in the FAIL line
};

TEST(Conformance, BadPluginsFailNamingThePluginAndTheProperty) {
  const std::string host_abi = "host SDK ABI " + std::to_string(gdsmc::sdk_abi_major) + "." + std::to_string(gdsmc::sdk_abi_minor);
  const std::vector<BadPlugin> bad = {
      {"conformance_leaky", "collision.momentum", {"conformance_leaky", "momentum not conserved", "|p' - p|"}},
      {"conformance_nan", "collision.finite", {"conformance_nan", "NaN", "nan"}},
      {"conformance_throwing", "defaults_construct", {"conformance_throwing", "does not construct", "the factory always fails"}},
      {"conformance_wrong_abi", "abi_version", {"conformance_wrong_abi", "wrong ABI version", host_abi.c_str()}},
      {"conformance_fake_thermostat", "forcing.conservation", {"conformance_fake_thermostat", "energy not conserved"}},
      // A forcing that heats the gas but reports no energy to the ledger.
      {"conformance_unreported_work", "forcing.energy", {"conformance_unreported_work"}},
      // A wall that sometimes returns a particle moving outward or beyond its plane.
      {"conformance_leaky_wall", "boundary.containment", {"conformance_leaky_wall", "outside"}},
      // A diffuse wall that emits at 1.5 times its `temperature` parameter.
      {"conformance_hot_wall", "boundary.wall_flux", {"conformance_hot_wall", "wall flux", "temperature", "p = 0"}},
      // Declares the loss with (1 - e) instead of (1 - e^2): right at e = 0 and 1, wrong inside.
      {"conformance_wrong_loss",
       "parameter_interior",
       {"conformance_wrong_loss", "restitution = 0.25", "energy change differs from the declared one",
        "[reproduce: gdsmc conformance", "--seed 1 --only parameter_interior]"}},
      // Declares the inelastic loss for elastic (slow) impacts too: right whenever one parameter
      // is at its default, wrong at a random point of both ranges.
      {"conformance_elastic_loss",
       "parameter_interior",
       {"conformance_elastic_loss", "random point 1 of 3", "alpha = ", "elastic_below = ",
        "energy change differs from the declared one"}},
      // A diagnostic whose running mean is not in its checkpoint (no save_state).
      {"conformance_forgetful",
       "checkpoint",
       {"conformance_forgetful", "resumed differs from the run uninterrupted", "running_mean_temperature",
        "save_state must write every member"}},
      // A diagnostic that declares it reads only the kinetic energy of ctx.moments and reads T too.
      {"conformance_undeclared_moments",
       "diagnostic.moments_read",
       {"conformance_undeclared_moments", "declares that it reads kinetic_energy", "series 'temperature'",
        "declare every part"}},
      // A diagnostic that declares its sample reads no particle and sums their v_x.
      {"conformance_hidden_particles",
       "diagnostic.moments_read",
       {"conformance_hidden_particles", "reads no particle", "on an empty span its output changes", "mean_vx"}},
      // A white-noise thermostat declaring half its heating rate.
      {"conformance_white_noise_half",
       "forcing.expected_energy",
       {"conformance_white_noise_half", "differs from the declared expected_energy_rate()", "standard errors"}},
      // Species-aware, but collides every pair as two unit masses: sum m v changes in a mixture.
      {"conformance_massless_mixture",
       "collision.species",
       {"conformance_massless_mixture", "momentum not conserved", "2-species mixture of light (m = 1, sigma = 1), heavy (m = 3.7, sigma = 2)", "heavy (m = 3.7)",
        "|sum m v' - sum m v|", "species_mass"}},
      // The right masses in the velocities, the loss of two unit masses declared.
      {"conformance_unweighted_energy",
       "collision.species",
       {"conformance_unweighted_energy", "differs from the declared mass-weighted one", "heavy (m = 3.7)"}},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.plugin);
    ASSERT_TRUE(fs::exists(test_plugin(b.plugin)));
    const Outcome r = run("conformance '" + test_plugin(b.plugin) + "'");
    EXPECT_EQ(r.status, 1) << r.out;
    const std::string line = line_of(r.out, b.check);
    ASSERT_EQ(line.rfind("FAIL", 0), 0u) << "expected " << b.check << " to FAIL:\n" << r.out;
    for (const char* w : b.words) EXPECT_NE(line.find(w), std::string::npos) << "'" << w << "' not in: " << line;
    EXPECT_EQ(r.out.find("CRASH"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("NOT CONFORMING"), std::string::npos) << r.out;
  }
}

// collision.species asks a species-aware rule only: the two broken mixture rules pass every
// one-species check and fail the mixture one alone; a rule without gdsmc.species is skipped, saying
// why (conformance_wrong_loss, a one-species rule); inelastic_hard_spheres passes it.
TEST(Conformance, MixtureCheckAsksSpeciesAwareRulesOnly) {
  for (const char* plugin : {"conformance_massless_mixture", "conformance_unweighted_energy"}) {
    SCOPED_TRACE(plugin);
    const Outcome r = run("conformance '" + test_plugin(plugin) + "' --only collision");
    EXPECT_EQ(r.status, 1) << r.out;
    for (const char* c : {"collision.finite", "collision.mass", "collision.momentum", "collision.energy", "collision.rate",
                          "collision.acceptance", "collision.cell"})
      EXPECT_EQ(line_of(r.out, c).rfind("PASS", 0), 0u) << c << ":\n" << r.out;
    EXPECT_EQ(line_of(r.out, "collision.species").rfind("FAIL", 0), 0u) << r.out;
  }
  const std::string dir = GDSMC_TEST_PLUGIN_DIR;
  const Outcome plain = run("conformance '" + test_plugin("conformance_wrong_loss") + "' --only collision.species");
  const std::string skipped = line_of(plain.out, "collision.species");
  EXPECT_EQ(skipped.rfind("SKIP", 0), 0u) << plain.out;
  EXPECT_NE(skipped.find("does not offer the extension gdsmc.species"), std::string::npos) << skipped;
  const Outcome ihs = run("conformance '" + dir + "/gdsmc_inelastic_hard_spheres.so' --only collision.species");
  EXPECT_EQ(ihs.status, 0) << ihs.out;
  EXPECT_EQ(line_of(ihs.out, "collision.species").rfind("PASS", 0), 0u) << ihs.out;
}

TEST(Conformance, CrashingPluginGivesCrashLinesAndTheRunnerCarriesOn) {
  const Outcome r = run("conformance '" + test_plugin("conformance_crash") + "'");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(line_of(r.out, "parameter_schema").rfind("PASS", 0), 0u) << r.out;
  EXPECT_EQ(line_of(r.out, "defaults_construct").rfind("CRASH", 0), 0u) << r.out;
  const std::string line = line_of(r.out, "collision.momentum");
  EXPECT_EQ(line.rfind("CRASH", 0), 0u) << r.out;
  EXPECT_NE(line.find("conformance_crash"), std::string::npos) << line;
  EXPECT_NE(line.find("signal"), std::string::npos) << line;
  // later checks still ran and the summary was printed
  EXPECT_FALSE(line_of(r.out, "collision.cell").empty()) << r.out;
  EXPECT_NE(r.out.find("NOT CONFORMING"), std::string::npos) << r.out;
}

TEST(Conformance, BoundaryChecksRunOnATestBoundary) {
  const Outcome r = run("conformance '" + test_plugin("conformance_periodic") + "'");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(line_of(r.out, "boundary.containment").rfind("PASS", 0), 0u) << r.out;
  EXPECT_EQ(line_of(r.out, "boundary.transfer").rfind("PASS", 0), 0u) << r.out;
  EXPECT_EQ(line_of(r.out, "boundary.wall_flux").rfind("SKIP", 0), 0u) << r.out;  // not a wall
}

// Every in-tree boundary plugin, check by check: what must PASS and what must SKIP (with the word
// that says why). Each line also carries the measured quantities (tallies, chi-square, p).
TEST(Conformance, InTreeBoundariesPassTheirBoundaryChecks) {
  struct Expect {
    const char* plugin;
    std::vector<const char*> pass, skip;
  };
  const std::vector<Expect> expected = {
      {"periodic", {"boundary.containment", "boundary.elastic", "boundary.transfer"}, {"boundary.wall_flux"}},
      {"lees_edwards", {"boundary.containment", "boundary.transfer"}, {"boundary.elastic", "boundary.wall_flux"}},
      {"specular_wall", {"boundary.containment", "boundary.elastic"}, {"boundary.wall_flux", "boundary.transfer"}},
      {"diffuse_wall", {"boundary.containment", "boundary.wall_flux"}, {"boundary.elastic", "boundary.accommodation"}},
      {"maxwell_wall", {"boundary.containment", "boundary.wall_flux", "boundary.accommodation"}, {"boundary.transfer"}},
  };
  for (const auto& e : expected) {
    SCOPED_TRACE(e.plugin);
    const std::string file = std::string(GDSMC_TEST_PLUGIN_DIR) + "/gdsmc_" + e.plugin + ".so";
    ASSERT_TRUE(fs::exists(file));
    const Outcome r = run("conformance '" + file + "' --only boundary,determinism");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(line_of(r.out, "determinism").rfind("PASS", 0), 0u) << r.out;
    for (const char* c : e.pass) EXPECT_EQ(line_of(r.out, c).rfind("PASS", 0), 0u) << c << ":\n" << r.out;
    for (const char* c : e.skip) EXPECT_EQ(line_of(r.out, c).rfind("SKIP", 0), 0u) << c << ":\n" << r.out;
  }
  // The Lees-Edwards line states the sheared-frame balance; the diffuse wall's the chi-square test.
  const Outcome le = run("conformance '" + std::string(GDSMC_TEST_PLUGIN_DIR) + "/gdsmc_lees_edwards.so' --only boundary.transfer");
  EXPECT_NE(line_of(le.out, "boundary.transfer").find("-(a L)(N_up - N_down)"), std::string::npos) << le.out;
  EXPECT_NE(line_of(le.out, "boundary.transfer").find("published 'shear_rate'"), std::string::npos) << le.out;
  const Outcome dw = run("conformance '" + std::string(GDSMC_TEST_PLUGIN_DIR) + "/gdsmc_diffuse_wall.so' --only boundary.wall_flux");
  EXPECT_NE(line_of(dw.out, "boundary.wall_flux").find("chi2"), std::string::npos) << dw.out;
}

TEST(Conformance, CommandLineOptions) {
  const std::string ihs = std::string(GDSMC_TEST_PLUGIN_DIR) + "/gdsmc_inelastic_hard_spheres.so";
  {
    const Outcome r = run("conformance '" + ihs + "' --only collision.momentum --seed 7");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("seed 7"), std::string::npos) << r.out;
    EXPECT_EQ(line_of(r.out, "collision.momentum").rfind("PASS", 0), 0u) << r.out;
    EXPECT_TRUE(line_of(r.out, "collision.energy").empty()) << r.out;
  }
  {
    const Outcome r = run("conformance '" + ihs + "' --list");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("collision.cell"), std::string::npos) << r.out;
  }
  const fs::path tmp = temp_dir();
  {
    const fs::path params = tmp / "params.yaml";
    std::ofstream(params) << "alpha: 0.5\n";
    const Outcome r = run("conformance '" + ihs + "' --params '" + params.string() + "' --only defaults_construct");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(line_of(r.out, "defaults_construct").find("alpha = 0.5"), std::string::npos) << r.out;
  }
  {
    const fs::path params = tmp / "bad.yaml";
    std::ofstream(params) << "alpha: 1.5\n";
    const Outcome r = run("conformance '" + ihs + "' --params '" + params.string() + "' --only defaults_construct");
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(line_of(r.out, "defaults_construct").find("out of range"), std::string::npos) << r.out;
  }
  EXPECT_EQ(run("conformance '" + ihs + "' --no-such-option").status, 2);
  EXPECT_EQ(run("conformance /no/such/plugin.so").status, 2);
  EXPECT_EQ(run("conformance '" + ihs + "' --only no_such_check").status, 2);
  EXPECT_EQ(run("conformance --help").status, 0);
  fs::remove_all(tmp);
}

// A rule that computes what collide() uses in begin() (its factor is NaN before): the parameter
// sweeps must begin every rule they build, as a run does. The old sweeps called collide() on rules
// whose begin() never ran and failed this sound rule with NaN velocities.
TEST(Conformance, ParameterSweepsBeginEveryRuleTheyCollide) {
  const Outcome r = run("conformance '" + test_plugin("conformance_begin_rule") +
                        "' --only parameter_bounds,parameter_interior,collision.finite");
  EXPECT_EQ(r.status, 0) << r.out;
  for (const char* check : {"parameter_bounds", "parameter_interior", "collision.finite"})
    EXPECT_EQ(line_of(r.out, check).rfind("PASS", 0), 0u) << check << ":\n" << r.out;
}

// The two wrong-loss rules are exactly the bugs a defaults-and-bounds check cannot see: every
// check of the previous suite passes, only parameter_interior fails, the same way for the same seed.
TEST(Conformance, WrongLossRulesPassDefaultsAndBoundsAndFailInside) {
  for (const char* plugin : {"conformance_wrong_loss", "conformance_elastic_loss"}) {
    SCOPED_TRACE(plugin);
    const Outcome r = run("conformance '" + test_plugin(plugin) + "'");
    EXPECT_EQ(r.status, 1) << r.out;
    for (const char* c : {"defaults_construct", "parameter_bounds", "determinism", "collision.finite", "collision.mass",
                          "collision.momentum", "collision.energy", "collision.rate", "collision.acceptance", "collision.cell"})
      EXPECT_EQ(line_of(r.out, c).rfind("PASS", 0), 0u) << c << ":\n" << r.out;
    EXPECT_EQ(line_of(r.out, "parameter_interior").rfind("FAIL", 0), 0u) << r.out;
    const Outcome again = run("conformance '" + test_plugin(plugin) + "' --only parameter_interior");
    EXPECT_EQ(line_of(again.out, "parameter_interior"), line_of(r.out, "parameter_interior"));
  }
  // Another seed draws other random points, and says so.
  const Outcome r = run("conformance '" + test_plugin("conformance_elastic_loss") + "' --seed 5 --only parameter_interior");
  const std::string line = line_of(r.out, "parameter_interior");
  EXPECT_EQ(line.rfind("FAIL", 0), 0u) << r.out;
  EXPECT_NE(line.find("--seed 5 --only parameter_interior"), std::string::npos) << line;
}

// Several --params sets: each set is checked in turn, the bounds sweep is kept (it varies the
// parameters the set gives too), and a failure's reproduce line carries the set's --params.
TEST(Conformance, SeveralParameterSets) {
  const fs::path tmp = temp_dir();
  const std::string ihs = std::string(GDSMC_TEST_PLUGIN_DIR) + "/gdsmc_inelastic_hard_spheres.so";
  const fs::path a = tmp / "a.yaml", b = tmp / "b.yaml";
  std::ofstream(a) << "alpha: 0.5\n";
  std::ofstream(b) << "alpha: 0.9\n";
  {
    const Outcome r = run("conformance '" + ihs + "' --params '" + a.string() + "' --params '" + b.string() +
                          "' --only defaults_construct,parameter_bounds,parameter_interior");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("parameter set 1 of 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("parameter set 2 of 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("alpha = 0.5"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("alpha = 0.9"), std::string::npos) << r.out;
    // the bounds sweep still varies alpha, which the sets fix
    const std::string bounds = line_of(r.out, "parameter_bounds");
    EXPECT_EQ(bounds.rfind("PASS", 0), 0u) << r.out;
    EXPECT_EQ(bounds.find("no parameter with bounds"), std::string::npos) << bounds;
    EXPECT_EQ(line_of(r.out, "parameter_interior").rfind("PASS", 0), 0u) << r.out;
  }
  {
    const fs::path e = tmp / "e.yaml";
    std::ofstream(e) << "restitution: 1\n";
    const fs::path ctx = tmp / "ctx.yaml";
    std::ofstream(ctx) << "initial_state: {plugin: maxwellian}\n";
    const Outcome r2 = run("conformance '" + test_plugin("conformance_wrong_loss") + "' --params '" + e.string() +
                           "' --context '" + ctx.string() + "' --seed 3 --only parameter_interior");
    const std::string line = line_of(r2.out, "parameter_interior");
    EXPECT_EQ(line.rfind("FAIL", 0), 0u) << r2.out;
    for (const std::string& w : std::vector<std::string>{"--params " + e.string(), "--context " + ctx.string(),
                                                          "--seed 3", "--only parameter_interior"})
      EXPECT_NE(line.find(w), std::string::npos) << "'" << w << "' not in: " << line;
  }
  fs::remove_all(tmp);
}

// A stochastic forcing that declares its mean energy input is held to it; one that does not is
// skipped with the reason.
TEST(Conformance, ForcingExpectedEnergy) {
  const Outcome r = run("conformance '" + test_plugin("conformance_white_noise") + "'");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find(": conforming"), std::string::npos) << r.out;
  const std::string line = line_of(r.out, "forcing.expected_energy");
  EXPECT_EQ(line.rfind("PASS", 0), 0u) << r.out;
  EXPECT_NE(line.find("standard errors"), std::string::npos) << line;
  EXPECT_EQ(line_of(r.out, "forcing.order").rfind("SKIP", 0), 0u) << r.out;         // stochastic
  EXPECT_EQ(line_of(r.out, "forcing.conservation").rfind("SKIP", 0), 0u) << r.out;  // declares neither
  const Outcome drag = run("conformance '" + std::string(GDSMC_TEST_PLUGIN_DIR) +
                           "/gdsmc_drag.so' --only forcing.expected_energy");
  EXPECT_EQ(drag.status, 0) << drag.out;
  EXPECT_EQ(line_of(drag.out, "forcing.expected_energy").rfind("SKIP", 0), 0u) << drag.out;
}

// The runner's abi_version check and the loader refuse a file for the same reason, in the same
// words (one implementation of the check).
TEST(Conformance, AbiCheckIsTheLoaders) {
  const fs::path file = test_plugin("conformance_wrong_abi");
  std::string loader_message;
  try {
    (void)gdsmc::host::load_plugin(file);
  } catch (const gdsmc::host::PluginLoadError& e) {
    loader_message = e.what();
  }
  ASSERT_FALSE(loader_message.empty());
  const std::string reason = loader_message.substr(file.string().size() + 2);  // after "<file>: "
  const Outcome r = run("conformance '" + file.string() + "' --only abi_version");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(gdsmc::test::contains(line_of(r.out, "abi_version"), reason)) << "'" << reason << "' not in:\n" << r.out;
}
