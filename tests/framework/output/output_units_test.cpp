// The units of outputs: one vocabulary (gdsmc/physics/units.hpp), one spelling
// per unit, and every unit attribute that the shipped pipelines write spelled as it spells it.
#include <gtest/gtest.h>

#include <gdsmc/physics/units.hpp>

#include <set>

#include "test_support.hpp"

using namespace gdsmc::test;
using namespace gdsmc::test::h5;

namespace {
// A unit with its spaces taken out: two entries that differ only in spaces are one unit spelled
// twice ("sqrt(2 T0/m)" and "sqrt(2T0/m)").
std::string without_spaces(std::string u) {
  u.erase(std::remove(u.begin(), u.end(), ' '), u.end());
  return u;
}
}  // namespace

TEST(OutputUnits, TheVocabularySpellsEachUnitOnceAndTheOutputFormatGuideExplainsEveryOne) {
  std::set<std::string> seen;
  for (const char* u : gdsmc::units::all) EXPECT_TRUE(seen.insert(without_spaces(u)).second) << "'" << u << "' twice";
  const std::string guide = read_text(source_dir() / "docs" / "output-format.md");
  for (const char* u : gdsmc::units::all)
    if (*u) EXPECT_TRUE(contains(guide, "`" + std::string(u) + "`")) << "docs/output-format.md does not explain `" << u << "`";
}

// Every diagnostic plugin of the build writes in at least one of these runs (a channel with the
// slab diagnostics and the particles, a sheared gas with the USF set, the HCS, Enskog, the heat
// flux, an inhomogeneous shear flow, a sweep with its summary table, a cooling mixture and a
// two-species channel); the host writes its own
// datasets (time, bins, particles, layers, the summary) in them too.
TEST(OutputUnits, EveryUnitTheShippedPipelinesWriteIsSpelledAsTheVocabularySpellsIt) {
  TempDir dir;
  const std::vector<std::vector<std::string>> runs = {
      {"configs/poiseuille.yaml", "chan.h5", "--set", "run.particles=4000", "--set", "run.stop.time=6", "--set",
       "diagnostics=[{plugin: poiseuille_channel, steady_window: 1}, energy_balance, wall_fluxes, profiles, "
       "temperature, collision_count]",
       "--set", "output.particles=true", "--set", "system.layers={mean_free_paths: 0.5, after: 2}"},
      {"configs/usf_ehs_alpha0.5_shear0.1.yaml", "usf.h5", "--set", "run.particles=2000", "--set",
       "run.stop={collisions_per_particle: 2}", "--set", "run.average_after={collisions_per_particle: 1}"},
      {"configs/hcs.yaml", "hcs.h5", "--set", "run.particles=2000", "--set", "run.stop={collisions_per_particle: 2}",
       "--set", "run.average_after={collisions_per_particle: 1}"},
      {"configs/enskog_viscosity.yaml", "enskog.h5", "--set", "run.particles=2000", "--set",
       "run.stop={collisions_per_particle: 2}", "--set", "run.average_after={collisions_per_particle: 1}"},
      {"configs/heat_flux.yaml", "heat.h5", "--set", "run.particles=2000", "--set", "run.stop.time=0.6", "--set",
       "run.average_after.time=0.2"},
      {"configs/usf_inhomogeneous_transient.yaml", "usfi.h5", "--set", "run.particles=2000", "--set",
       "run.stop={collisions_per_particle: 2}"},
      {"configs/hcs_cumulants_sweep.yaml", "sweep.h5", "--set", "run.particles=2000", "--set",
       "run.stop={collisions_per_particle: 1}", "--set", "run.average_after={collisions_per_particle: 0.5}"},
      {"configs/mixture_hcs_sweep.yaml", "mixture.h5", "--set", "run.particles=2000", "--set", "run.realizations=2",
       "--set", "run.stop={collisions_per_particle: 1}", "--set", "run.average_after={collisions_per_particle: 0.5}"},
      {"configs/mixture_poiseuille.yaml", "mixture_channel.h5", "--set", "run.particles=4000", "--set",
       "run.stop.time=6", "--set", "run.average_after.time=2"}};
  std::set<std::string> plugins_seen;
  std::size_t units_read = 0;
  for (auto args : runs) {
    const std::string output = args[1];
    args[0] = (source_dir() / args[0]).string();
    args[1] = "-o";
    args.insert(args.begin() + 2, output);
    args.insert(args.begin(), "run");
    args.push_back("--quiet");
    const ProcessResult r = run_gdsmc(args, dir.path());
    ASSERT_EQ(r.exit_code, 0) << join(args, " ") << "\n" << r.describe();
    const File f(dir / output);
    for (const auto& [path, type] : objects(f.id())) {
      for (const char* key : {"unit", "edge_unit", "value_unit"}) {
        if (!has_attribute(f.id(), path, key)) continue;
        const std::string unit = read_string_attribute(f.id(), path, key);
        ++units_read;
        EXPECT_TRUE(gdsmc::units::is_output_unit(unit))
            << output << ":" << path << "@" << key << " = '" << unit << "' is not in gdsmc/physics/units.hpp";
      }
      if (has_attribute(f.id(), path, "plugin")) plugins_seen.insert(read_string_attribute(f.id(), path, "plugin"));
    }
  }
  EXPECT_GT(units_read, 1000u);
  // Every diagnostic plugin of the tree wrote in one of the runs.
  for (const auto& e : fs::directory_iterator(source_dir() / "plugins" / "diagnostic"))
    EXPECT_TRUE(plugins_seen.count(e.path().filename().string())) << e.path().filename() << " was not in the runs";
}
