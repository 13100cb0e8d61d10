// system.species (config/species_section.cpp): a mixture's species as SystemInfo shows them, the
// counts each species gets, and every refusal with its key and what would be valid.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "config/errors.hpp"
#include "config/system_info.hpp"
#include "support/files.hpp"
#include "support/pipelines.hpp"

namespace {

using gdsmc::test::TempDir;

std::string mixture(const std::string& species, int particles = 1000) {
  return "run:\n  seed: 3\n  particles: " + std::to_string(particles) +
         "\n  time_step: {value: 0.01, unit: tau0}\n  stop: {collisions_per_particle: 1}\n"
         "system:\n  density: 1.0e-3\n  species:\n" + species +
         "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 1}\n"
         "diagnostics: [temperature]\noutput: {file: out.h5}\n";
}

// The first error's path and message, or "" if the pipeline loads.
std::pair<std::string, std::string> refusal(const std::string& yaml) {
  TempDir dir;
  try {
    (void)gdsmc::test::load_yaml(dir, yaml);
  } catch (const gdsmc::host::PipelineError& e) {
    if (e.errors().empty()) return {"", e.what()};
    return {e.errors()[0].path, e.errors()[0].message + " | " + e.errors()[0].valid};
  }
  return {"", ""};
}

TEST(SpeciesConfig, TheSpeciesReachSystemInfoWithTheirCounts) {
  TempDir dir;
  const auto p = gdsmc::test::load_yaml(dir, mixture("    - {name: light, fraction: 0.3}\n"
                                                     "    - {name: heavy, mass: 4, diameter: 1.5, fraction: 0.7}\n",
                                                     1001));
  const gdsmc::SystemInfo s = gdsmc::host::system_info(p, p.particles, 0);
  ASSERT_EQ(s.species_count, 2u);
  EXPECT_STREQ(s.species[0].name, "light");
  EXPECT_EQ(s.species_mass(0), 1.0);
  EXPECT_EQ(s.species_mass(1), 4.0);
  EXPECT_EQ(s.species_diameter(1), 1.5);
  EXPECT_EQ(s.pair_diameter(0, 1), 1.25);
  // 0.3 x 1001 = 300.3, 0.7 x 1001 = 700.7: floors 300 + 700, the one left to the larger remainder.
  EXPECT_EQ(gdsmc::host::species_counts(p.species, 1001), (std::vector<std::size_t>{300, 701}));
  // A copy of the pipeline (a sweep case) keeps the names valid.
  const gdsmc::host::Pipeline copy = p;
  EXPECT_STREQ(gdsmc::host::system_info(copy, 10, 0).species[1].name, "heavy");
}

TEST(SpeciesConfig, CountsAreTakenAsGiven) {
  TempDir dir;
  const auto p = gdsmc::test::load_yaml(dir, mixture("    - {name: A, count: 10}\n    - {name: B, count: 990}\n"));
  EXPECT_EQ(gdsmc::host::species_counts(p.species, 1000), (std::vector<std::size_t>{10, 990}));
  EXPECT_DOUBLE_EQ(p.species[0].fraction, 0.01);
  EXPECT_EQ(gdsmc::host::system_info(p, 1000, 0).species_count, 2u);
}

TEST(SpeciesConfig, OneSpeciesHasNoTable) {
  TempDir dir;
  const auto p = gdsmc::test::load_yaml(dir, gdsmc::test::small_pipeline());
  const gdsmc::SystemInfo s = gdsmc::host::system_info(p, p.particles, 0);
  EXPECT_EQ(s.species_count, 1u);
  EXPECT_EQ(s.species, nullptr);
  EXPECT_EQ(s.species_mass(0), 1.0);
}

TEST(SpeciesConfig, RefusalsNameTheKeyAndWhatIsValid) {
  struct Case {
    std::string species, path, says;
  } cases[] = {
      {"    - {name: A, fraction: 1}\n", "system.species", "two or more species"},
      {"    - {name: A, fraction: 0.5}\n    - {name: A, fraction: 0.5}\n", "system.species[1].name", "listed twice"},
      {"    - {name: A, fraction: 0.5}\n    - {name: B, fraction: 0.6}\n", "system.species", "sum to 1"},
      {"    - {name: A, fraction: 0.5}\n    - {name: B, count: 500}\n", "system.species[1]", "not a mix"},
      {"    - {name: A, count: 10}\n    - {name: B, count: 20}\n", "system.species", "run.particles is 1000"},
      {"    - {name: A, mass: -1, fraction: 0.5}\n    - {name: B, fraction: 0.5}\n", "system.species[0].mass", "positive"},
      {"    - {name: A, diameter: 0, fraction: 0.5}\n    - {name: B, fraction: 0.5}\n", "system.species[0].diameter", "positive"},
      {"    - {name: 2A, fraction: 0.5}\n    - {name: B, fraction: 0.5}\n", "system.species[0].name", "letters"},
      {"    - {name: A}\n    - {name: B, fraction: 0.5}\n", "system.species[0]", "missing 'fraction'"},
      {"    - {name: A, fraction: 0.9999}\n    - {name: B, fraction: 0.0001}\n", "system.species[1].fraction", "no particle"},
      {"    - {name: A, fraction: 0.5, colour: red}\n    - {name: B, fraction: 0.5}\n", "system.species[0].colour", ""},
  };
  for (const Case& c : cases) {
    const auto [path, message] = refusal(mixture(c.species));
    EXPECT_EQ(path, c.path) << c.species << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << c.species << message;
  }
}

}  // namespace
