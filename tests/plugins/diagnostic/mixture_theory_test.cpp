// The mixture_theory diagnostic driven directly, with a two-species SystemInfo built by hand: it
// refuses a one-species run, reads the restitution of every species pair from the board (the
// pair's own, else the common one), writes the SDK's theory (gdsmc/physics/mixture_theory.hpp) with
// its theory tags, and measures T0/T1 of a constructed set of particles exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gdsmc/physics.hpp>

#include "config/system_info.hpp"
#include "output/diagnostic_output.hpp"
#include "plugins/loader.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

std::string pipeline_yaml(const std::string& diagnostic) {
  return "run:\n  seed: 5\n  particles: 1000\n  time_step: {value: 0.01, unit: tau0}\n"
         "  stop: {collisions_per_particle: 1}\n"
         "system: {density: 1.0e-3, sigma: 1, temperature: 1.0}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
         "diagnostics:\n  - " + diagnostic + "\noutput: {file: unused.h5}\n";
}

// A light and a heavy species: masses 1 and 4, diameters 1 and 1.5, fractions 0.3 and 0.7.
const SpeciesInfo kSpecies[2] = {{"light", 1.0, 1.0, 0.3}, {"heavy", 4.0, 1.5, 0.7}};

struct Bench : t::DiagnosticBench {
  Bench(const t::TempDir& dir, const std::string& diagnostic, bool mixture = true)
      : DiagnosticBench(dir, pipeline_yaml(diagnostic), "mixture_theory", 1000) {
    if (mixture) {
      sys.species_count = 2;
      sys.species = kSpecies;
    }
  }
};

BinaryMixture mixture(double a00, double a01, double a11) {
  BinaryMixture m;
  for (int i = 0; i < 2; ++i) {
    m.mass[i] = kSpecies[i].mass;
    m.diameter[i] = kSpecies[i].diameter;
    m.fraction[i] = kSpecies[i].fraction;
  }
  m.alpha[0][0] = a00;
  m.alpha[0][1] = m.alpha[1][0] = a01;
  m.alpha[1][1] = a11;
  return m;
}

TEST(MixtureTheoryDiagnostic, RefusesARunThatIsNotATwoSpeciesMixture) {
  t::TempDir dir;
  Bench b(dir, "mixture_theory", false);
  b.board.publish("restitution", 0.8);
  try {
    b.diag->begin(b.sys, b.board, *b.out);
    FAIL() << "a one-species run was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("two-species mixture"), std::string::npos) << e.what();
  }
}

TEST(MixtureTheoryDiagnostic, RefusesARuleWithoutRestitution) {
  t::TempDir dir;
  Bench b(dir, "mixture_theory");
  EXPECT_THROW(b.diag->begin(b.sys, b.board, *b.out), ParameterError);
}

TEST(MixtureTheoryDiagnostic, WritesTheTheoryOfEachStateWithPerPairRestitution) {
  t::TempDir dir;
  for (const char* state : {"cooling", "white_noise"}) {
    Bench b(dir, std::string("{plugin: mixture_theory, state: ") + state + "}");
    b.board.publish("restitution", 0.9);         // the common default: used for [0,0]
    b.board.publish("restitution[0,1]", 0.7);
    b.board.publish("restitution[1,1]", 0.8);
    b.diag->begin(b.sys, b.board, *b.out);
    const MixtureState st = std::string(state) == "cooling" ? MixtureState::cooling : MixtureState::white_noise;
    const BinaryMixture m = mixture(0.9, 0.7, 0.8);
    const MixtureTheory mx = mixture_theory(m, st, MixtureApproximation::maxwellian);
    const MixtureTheory so = mixture_theory(m, st, MixtureApproximation::first_sonine);
    EXPECT_EQ(b.scalar("gamma_maxwellian"), mx.gamma);
    EXPECT_EQ(b.scalar("gamma_sonine"), so.gamma);
    EXPECT_EQ(b.scalar("T0_over_T_sonine"), so.t_over_t[0]);
    EXPECT_EQ(b.scalar("zeta1_star_maxwellian"), mx.zeta_star[1]);
    EXPECT_EQ(b.scalar("c0_sonine"), so.c[0]);
    EXPECT_EQ(b.scalar("c1_sonine"), so.c[1]);
    // the restitution of each pair matters: the common value everywhere gives another gamma
    EXPECT_GT(std::fabs(so.gamma - mixture_theory(mixture(0.9, 0.9, 0.9), st, MixtureApproximation::first_sonine).gamma), 1e-3);
    EXPECT_EQ(b.out->theory_tags.at("gamma_sonine").measured, "temperature_ratio");
    EXPECT_EQ(b.out->theory_tags.at("c0_sonine").measured, "");
    EXPECT_FALSE(b.out->theory_tags.at("gamma_maxwellian").equation.empty());
  }
}

// T0/T1 of a constructed state: species 0 moves with (+-a, 0, 0), species 1 with (0, +-b, 0) plus a
// common drift that the peculiar velocities remove: T0 = m0 a^2 / 3, T1 = m1 b^2 / 3.
TEST(MixtureTheoryDiagnostic, MeasuresTheTemperatureRatioOfTheParticles) {
  t::TempDir dir;
  Bench b(dir, "mixture_theory");
  b.board.publish("restitution", 0.8);
  b.diag->begin(b.sys, b.board, *b.out);
  const double a = 1.3, bb = 0.4, drift = 2.0;
  std::vector<double> y, vx, vy, vz;
  std::vector<std::uint32_t> species;
  for (int k = 0; k < 40; ++k) {
    const bool heavy = k >= 12;  // 12 light, 28 heavy
    const double sign = (k % 2) ? 1.0 : -1.0;
    y.push_back(0);
    vx.push_back(drift + (heavy ? 0.0 : sign * a));
    vy.push_back(heavy ? sign * bb : 0.0);
    vz.push_back(-drift);
    species.push_back(heavy ? 1u : 0u);
  }
  ParticleSpan p;
  p.count = y.size();
  p.y = y.data();
  p.vx = vx.data();
  p.vy = vy.data();
  p.vz = vz.data();
  p.species = species.data();
  StepContext ctx;
  ctx.system = &b.sys;
  b.out->begin_record(0, 0);
  b.diag->sample(ctx, p);
  b.diag->record(ctx, *b.out);
  const double T0 = 1.0 * a * a / 3, T1 = 4.0 * bb * bb / 3, T = (12 * T0 + 28 * T1) / 40;
  EXPECT_NEAR(b.series("temperature_ratio").at(0), T0 / T1, 1e-12);
  EXPECT_NEAR(b.series("T0_over_T").at(0), T0 / T, 1e-12);
  EXPECT_NEAR(b.series("T1_over_T").at(0), T1 / T, 1e-12);
}

}  // namespace
