// Granular mixtures run end to end (issue 33): the HCS temperature ratio of a binary mixture beside
// the first-Sonine theory that mixture_theory writes, equal partial cooling rates in the scaled
// state, momentum conserved to round-off with unequal masses, the same bits on one thread and on
// two (a slab with walls, a body force and weighted pairs per species pair), and a plugin written
// for one species refused in a mixture, by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

namespace t = gdsmc::test;

std::string homogeneous(const std::string& run, const std::string& species, const std::string& rest) {
  return "run:\n  seed: 41\n" + run +
         "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: homogeneous\n  species:\n" + species + rest;
}

const std::string kLightHeavy =
    "    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
    "    - {name: heavy, mass: 4, diameter: 1, fraction: 0.5}\n";

TEST(MixtureRuns, HcsTemperatureRatioMatchesTheFirstSonineTheoryAndPartialCoolingRatesAgree) {
  // alpha = 0.8 for every pair, m_1/m_0 = 4, equal sizes and fractions: T0/T1 = 0.7510 (first
  // Sonine), 0.7456 (Maxwellian); a run of 1e5 particles measured 0.7533 +- 0.0011 at dt = 0.02
  // tau(T) (the mixture_theory documentation). Tolerance: 4 standard errors of the steady mean over
  // the 4 realizations, plus 0.5 % for the first-Sonine approximation itself (its largest gap to
  // long runs, 0.3 % at m_1/m_0 = 10, with room for the O(dt) bias).
  const std::string yaml = homogeneous(
      "  particles: 20000\n  realizations: 4\n  time_step: {value: 0.02, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 30}\n  sample_every: 5\n  record_every: 25\n"
      "  average_after: {collisions_per_particle: 8}\n",
      kLightHeavy,
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
      "diagnostics: [mixture_theory, species_moments]\noutput: {file: out.h5}\n");
  t::TempDir dir;
  dir.write("p.yaml", yaml);
  const t::ProcessResult r = t::run_gdsmc({"run", "p.yaml", "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const t::h5::File f(dir.path() / "out.h5");
  const std::string g = "/diagnostics/mixture_theory/";
  const double mean = t::h5::read_scalar(f.id(), g + "temperature_ratio.steady_mean");
  const double error = t::h5::read_scalar(f.id(), g + "temperature_ratio.steady_stderr");
  const double sonine = t::h5::read_scalar(f.id(), g + "gamma_sonine");
  const double maxwellian = t::h5::read_scalar(f.id(), g + "gamma_maxwellian");
  std::printf("  T0/T1 = %.5f +- %.5f; theory %.5f (first Sonine), %.5f (Maxwellian)\n", mean, error, sonine, maxwellian);
  EXPECT_NEAR(sonine, 0.7510, 5e-4);
  ASSERT_TRUE(std::isfinite(error));
  EXPECT_LT(error, 0.004);
  EXPECT_NEAR(mean, sonine, 4 * error + 0.005 * sonine);
  // In the scaled HCS every species cools at the mixture's rate: zeta_i / zeta = 1.
  for (const char* s : {"light", "heavy"}) {
    const std::string k = std::string("/diagnostics/species_moments/zeta_ratio[") + s + "]";
    const double z = t::h5::read_scalar(f.id(), k + ".steady_mean"), ze = t::h5::read_scalar(f.id(), k + ".steady_stderr");
    std::printf("  zeta_%s / zeta = %.5f +- %.5f\n", s, z, ze);
    ASSERT_TRUE(std::isfinite(ze));
    EXPECT_NEAR(z, 1.0, 4 * ze + 1e-3) << s;
  }
}

TEST(MixtureRuns, MomentumIsConservedToRoundOffWithUnequalMasses) {
  // Masses 1 and 7.3, diameters 1 and 2.5, alpha_ab per pair: the initial state has sum m v = 0
  // exactly (exact moments) and only collisions act, so the barycentric velocity stays at round-off
  // of the momentum scale sum m |v|.
  const std::string yaml = homogeneous(
      "  particles: 4000\n  time_step: {value: 0.02, unit: tau0, follow_temperature: true}\n"
      "  stop: {collisions_per_particle: 20}\n",
      "    - {name: A, mass: 1, diameter: 1, fraction: 0.3}\n    - {name: B, mass: 7.3, diameter: 2.5, fraction: 0.7}\n",
      "initial_state: maxwellian\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 0.9, restitution_pairs: \"A-B: 0.6, B-B: 0.75\"}\n"
      "diagnostics: [temperature]\noutput: {file: out.h5, particles: true}\n");
  t::TempDir dir;
  dir.write("p.yaml", yaml);
  const t::ProcessResult r = t::run_gdsmc({"run", "p.yaml", "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const t::h5::File f(dir.path() / "out.h5");
  const std::vector<double> species = t::h5::read_doubles(f.id(), "/particles/species");
  const double mass[2] = {1.0, 7.3};
  double p[3] = {0, 0, 0}, scale = 0;
  const char* axes[3] = {"/particles/vx", "/particles/vy", "/particles/vz"};
  for (int a = 0; a < 3; ++a) {
    const std::vector<double> v = t::h5::read_doubles(f.id(), axes[a]);
    ASSERT_EQ(v.size(), species.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      const double m = mass[static_cast<int>(species[i])];
      p[a] += m * v[i];
      scale += m * std::fabs(v[i]);
    }
  }
  const double collisions = t::h5::read_number_attribute(f.id(), "/run", "collisions");
  EXPECT_GT(collisions, 30000);
  // Each collision's round-off is a few ulps of its pair's momentum; 1e-12 of the scale is far above
  // their random-walk sum (sqrt(4e4) x 1e-16) and far below a missed mass (1 %).
  for (int a = 0; a < 3; ++a) EXPECT_LT(std::fabs(p[a]), 1e-12 * scale) << "axis " << a;
}

const std::string kSlabMixture =
    "run:\n  seed: 12\n  particles: 40000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {time: 6}\n"
    "  record_every: 20\n"
    "system:\n  mean_free_path: 186\n  temperature: 1.0\n  domain: slab\n"
    "  box: {y: {value: 1860, unit: sigma}}\n  layers: 40\n  species:\n"
    "    - {name: light, mass: 1, diameter: 1, fraction: 0.6}\n"
    "    - {name: heavy, mass: 4, diameter: 1.5, fraction: 0.4}\n"
    "initial_state: maxwellian\n"
    "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
    "forcings:\n  - {plugin: body_acceleration, acceleration: {value: 5.0e-4, unit: reduced}}\n"
    "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n"
    "  y_max: {plugin: maxwell_wall, temperature: 1.0, accommodation: 0.5}\n"
    "diagnostics: [energy_balance, species_moments, wall_fluxes]\n"
    "output: {file: out.h5, particles: true}\n";

TEST(MixtureRuns, ASlabMixtureIsTheSameBitsOnOneThreadAndOnTwo) {
  t::TempDir dir;
  dir.write("p.yaml", kSlabMixture);
  for (const char* n : {"1", "2"}) {
    const t::ProcessResult r =
        t::run_gdsmc({"run", "p.yaml", "--quiet", "--threads", n, "-o", std::string("out") + n + ".h5"}, dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }
  const auto one = t::h5::contents(dir.path() / "out1.h5"), two = t::h5::contents(dir.path() / "out2.h5");
  EXPECT_GE(one.size(), 100u);
  ASSERT_EQ(one.size(), two.size());
  for (const auto& [key, bytes] : one) {
    const auto it = two.find(key);
    ASSERT_NE(it, two.end()) << key;
    EXPECT_TRUE(it->second == bytes) << key << " differs between 1 and 2 threads";
  }
  const t::h5::File f(dir.path() / "out1.h5");
  // The per-species wall tallies add up to the wall's (the host keeps both).
  for (const char* side : {"y_min", "y_max"}) {
    const std::string b = std::string("boundary.") + side + ".";
    const double all = t::h5::read_number_attribute(f.id(), "/run", b + "energy");
    const double parts = t::h5::read_number_attribute(f.id(), "/run", b + "light.energy") +
                         t::h5::read_number_attribute(f.id(), "/run", b + "heavy.energy");
    EXPECT_NEAR(parts, all, 1e-9 * std::fabs(all) + 1e-12) << side;
    EXPECT_GT(t::h5::read_number_attribute(f.id(), "/run", b + "heavy.hits"), 100) << side;
  }
  EXPECT_EQ(t::h5::read_number_attribute(f.id(), "/system", "species.heavy.mass"), 4.0);
  EXPECT_EQ(t::h5::read_number_attribute(f.id(), "/system", "species.heavy.count"), 16000.0);
}

TEST(MixtureRuns, APluginWrittenForOneSpeciesIsRefusedByName) {
  const t::Refusal r = t::refuse(homogeneous(
      "  particles: 1000\n  time_step: {value: 0.02, unit: tau0}\n  stop: {collisions_per_particle: 1}\n", kLightHeavy,
      "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
      "diagnostics: [temperature, hcs_theory]\noutput: {file: out.h5}\n"));
  const std::string said = r.result.out + r.result.err;
  EXPECT_NE(said.find("hcs_theory"), std::string::npos) << said;
  EXPECT_NE(said.find("gdsmc.species"), std::string::npos) << said;
  EXPECT_EQ(said.find("'temperature'"), std::string::npos) << said;  // a species-aware one is not named
}

}  // namespace
