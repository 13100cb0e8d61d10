// The initial states in a two-species mixture (SDK 6.5), on a hand-built span: light (m = 1) and
// heavy (m = 4) particles. Each species is Maxwellian at its own T_s with the thermal scale
// sqrt(T_s/m_s); exact_moments makes every species' temperature exact and the total momentum
// sum m_i v_i zero; species_temperatures starts a run out of equipartition; the delta shell gives
// species s the speed sqrt(3 T_s/m_s); unknown species names and malformed entries are refused
// naming the parameter. Tolerances are argued next to each check.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <gdsmc/physics.hpp>

#include "plugins/two_species_span.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::test;

std::string homogeneous_yaml(const std::string& initial) {
  return "run: {seed: 1, particles: 1000, time_step: {value: 0.01, unit: tau0}, stop: {collisions_per_particle: 1}}\n"
         "system: {density: 1.0e-3, temperature: 1.0}\n"
         "initial_state: " + initial + "\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
         "diagnostics: [temperature]\noutput: {file: out.h5}\n";
}
std::string slab_yaml(const std::string& initial) {
  return "run: {seed: 1, particles: 1000, time_step: {value: 0.01, unit: tau0}, stop: {collisions_per_particle: 1}}\n"
         "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
         "initial_state: " + initial + "\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
         "boundaries: {y: {plugin: lees_edwards, shear_rate: 0.5}}\n"
         "diagnostics: [temperature]\noutput: {file: out.h5}\n";
}

void generate(PluginFromPipeline& made, TwoSpecies& gas) {
  QuantityBoard board;
  made.object->publish(board);
  made.as<InitialState>().generate(gas.sys, board, gas.span, streams_at(StreamPurpose::initial_state, 0));
}

// Without exact moments each species is a sample of its Maxwellian: T_s = m_s <V^2>/3 has the
// relative standard error sqrt(2 / (3 N_s)) (m_s V^2 / T_s is a chi^2 with 3 N_s degrees of
// freedom, less 3 for the mean): 0.0058 for N_s = 2e4; 4 standard errors, 0.023, cannot pass a
// thermal scale sqrt(T) instead of sqrt(T/m_s), which would give the heavy species T = 4.
TEST(MixtureInitialStates, MaxwellianGivesEachSpeciesTheTemperatureWithItsOwnThermalScale) {
  TempDir dir;
  for (const char* text : {"", "heavy: 2.0"}) {
    PluginFromPipeline with(dir, homogeneous_yaml(std::string("{plugin: maxwellian, exact_moments: false, "
                                                              "species_temperatures: \"") + text + "\"}"),
                            "initial_state", 40000);
    TwoSpecies gas(with.sys, 20000, 20000, 4.0);
    generate(with, gas);
    const double T_heavy = std::string(text).empty() ? 1.0 : 2.0;
    const double tolerance = 4.0 * std::sqrt(2.0 / (3.0 * 20000.0));
    EXPECT_NEAR(gas.temperature(0) / 1.0, 1.0, tolerance) << text;
    EXPECT_NEAR(gas.temperature(1) / T_heavy, 1.0, tolerance) << text;
    std::printf("maxwellian [%s]: T_light = %.4f, T_heavy = %.4f (expected 1, %.1f; tolerance %.3f)\n", text,
                gas.temperature(0), gas.temperature(1), T_heavy, tolerance);
  }
}

// With exact moments every species is shifted to zero mean velocity and rescaled: T_s is exact and
// sum m_i v_i = 0, to round-off. Round-off: sums of 4e4 terms of O(1), relative 1e-16 sqrt(N) ~
// 2e-14; 1e-12 leaves room and fails for any statistical residue (~ 1e-2).
TEST(MixtureInitialStates, ExactMomentsMakeEverySpeciesTemperatureExactAndTheMomentumZero) {
  TempDir dir;
  for (const std::string initial : {"{plugin: maxwellian, species_temperatures: \"heavy: 2.5\"}",
                                    "{plugin: local_equilibrium, species_temperatures: \"heavy: 2.5, light: 0.5\"}",
                                    "{plugin: maxwellian, temperature: 1.5}"}) {
    PluginFromPipeline made(dir, homogeneous_yaml(initial), "initial_state", 30000);
    TwoSpecies gas(made.sys, 10000, 20000, 4.0);
    generate(made, gas);
    const bool lagrangian = initial.find("local_equilibrium") != std::string::npos;
    const double T_light = lagrangian ? 0.5 : initial.find("1.5") != std::string::npos ? 1.5 : 1.0;
    const double T_heavy = initial.find("2.5") != std::string::npos ? 2.5 : 1.5;
    EXPECT_NEAR(gas.temperature(0) / T_light, 1.0, 1e-12) << initial;
    EXPECT_NEAR(gas.temperature(1) / T_heavy, 1.0, 1e-12) << initial;
    const double scale = gas.total_mass() * std::sqrt(T_heavy);  // M times a thermal speed
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(gas.momentum(c)) / scale, 1e-12) << initial;
    // The mixture temperature sum m_i V_i^2 / 3N = sum_s x_s T_s (SDK 6.5 mass-weighted moments).
    EXPECT_NEAR(2.0 * gas.kinetic_energy() / (3.0 * 30000.0), (T_light + 2.0 * T_heavy) / 3.0, 1e-12) << initial;
  }
}

// A species of one particle cannot be shifted to rest and rescaled: it is left as drawn and the
// barycentric velocity of all is removed instead, so the total momentum is still zero.
TEST(MixtureInitialStates, ALoneParticleOfASpeciesStillLeavesZeroTotalMomentum) {
  TempDir dir;
  PluginFromPipeline made(dir, homogeneous_yaml("maxwellian"), "initial_state", 1001);
  TwoSpecies gas(made.sys, 1000, 1, 4.0);
  generate(made, gas);
  for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(gas.momentum(c)) / gas.total_mass(), 1e-12);
  EXPECT_NEAR(gas.temperature(0), 1.0, 0.1);  // exact before the shift; the shift is ~ 1/N
}

// The delta shell (000 Eq. 3.6) per species: |v - u0(y)| = sqrt(3 T_s/m_s) for every particle, to
// round-off (a unit vector times the speed, |e| = 1 to 1e-16).
TEST(MixtureInitialStates, DeltaShellGivesEachSpeciesItsOwnSpeed) {
  TempDir dir;
  PluginFromPipeline made(dir, slab_yaml("{plugin: delta_shell, shear_rate: 0.5, species_temperatures: \"heavy: 2\"}"),
                          "initial_state", 2000);
  TwoSpecies gas(made.sys, 1000, 1000, 4.0);
  generate(made, gas);
  const double L = gas.sys.box[1];
  const double a = made.pipeline.initial_state.params.real("shear_rate");  // reduced units
  for (std::size_t i = 0; i < gas.span.count; ++i) {
    const double T = gas.kind[i] == 0 ? 1.0 : 2.0;
    const double speed = std::sqrt(3.0 * T / gas.mass(i));
    // u0(y) = a L (cos(pi y/L) - 2/pi) x_hat (Eq. 3.8)
    const double u0 = a * L * (std::cos(M_PI * gas.y[i] / L) - 2.0 / M_PI);
    const double V = std::hypot(gas.vx[i] - u0, gas.vy[i], gas.vz[i]);
    ASSERT_NEAR(V / speed, 1.0, 1e-12) << "particle " << i;
  }
}

// Names are checked against the run's species (the error names the parameter and lists them);
// the syntax and the range when the plugin is built.
TEST(MixtureInitialStates, UnknownSpeciesAndMalformedEntriesAreRefused) {
  TempDir dir;
  for (const char* plugin : {"maxwellian", "local_equilibrium"}) {
    PluginFromPipeline made(dir, homogeneous_yaml(std::string("{plugin: ") + plugin +
                                                  ", species_temperatures: \"heavy: 2, medium: 3\"}"),
                            "initial_state", 100);
    TwoSpecies gas(made.sys, 50, 50, 4.0);
    try {
      generate(made, gas);
      ADD_FAILURE() << plugin << ": species 'medium' accepted";
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.parameter(), "species_temperatures");
      EXPECT_TRUE(contains(e.what(), "'medium'")) << e.what();
      EXPECT_TRUE(contains(e.what(), "light, heavy")) << e.what();
    }
    // In a one-species run there are no names to give.
    PluginFromPipeline one(dir, homogeneous_yaml(std::string("{plugin: ") + plugin + ", species_temperatures: \"heavy: 2\"}"),
                           "initial_state", 100);
    TwoSpecies gas1(one.sys, 100, 0, 1.0);
    gas1.sys.species_count = 1;
    gas1.sys.species = nullptr;
    gas1.span.species = nullptr;
    EXPECT_THROW(generate(one, gas1), ParameterError) << plugin;
  }
  for (const char* text : {"heavy 2", "heavy: two", "heavy: -1", "heavy: 0", "heavy: 1, heavy: 2", ": 1", "heavy: 1,, light: 1"}) {
    bool refused = false;
    try {
      PluginFromPipeline made(dir, homogeneous_yaml(std::string("{plugin: maxwellian, species_temperatures: \"") + text + "\"}"),
                              "initial_state", 100);
    } catch (const std::exception& e) {
      refused = true;
      EXPECT_TRUE(contains(e.what(), "species_temperatures")) << text << ": " << e.what();
    }
    EXPECT_TRUE(refused) << text;
  }
}

// A one-species run (no species list) takes the one-species path: the state is the one the SDK's
// sample_maxwellian and impose_exact_moments give, to the last bit.
TEST(MixtureInitialStates, OneSpeciesRunIsUnchanged) {
  TempDir dir;
  PluginFromPipeline made(dir, homogeneous_yaml("maxwellian"), "initial_state", 500);
  TwoSpecies gas(made.sys, 500, 0, 1.0);
  gas.sys.species_count = 1;
  gas.sys.species = nullptr;
  gas.span.species = nullptr;
  generate(made, gas);
  TwoSpecies ref(made.sys, 500, 0, 1.0);
  ref.sys.species_count = 1;
  ref.sys.species = nullptr;
  ref.span.species = nullptr;
  sample_maxwellian(ref.sys, ref.span, 1.0, streams_at(StreamPurpose::initial_state, 0));
  impose_exact_moments(ref.span, 1.0);
  for (std::size_t i = 0; i < 500; ++i) {
    ASSERT_EQ(gas.vx[i], ref.vx[i]);
    ASSERT_EQ(gas.vy[i], ref.vy[i]);
    ASSERT_EQ(gas.vz[i], ref.vz[i]);
  }
}

}  // namespace
