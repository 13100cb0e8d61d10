// The forcings in a two-species mixture (SDK 6.5), on a hand-built span: the white-noise thermostat
// kicks every species with the same velocity variance xi0^2 dt per component, so species s gains
// (3/2) m_s xi0^2 per particle and unit time (Barrat & Trizac 2002), returns the mass-weighted
// energy it added and keeps the total momentum; body_acceleration's apply() returns the
// mass-weighted energy. Tolerances are argued next to each check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "plugins/two_species_span.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::test;

std::string homogeneous_yaml(const std::string& forcing) {
  return "run: {seed: 1, particles: 1000, time_step: {value: 0.01, unit: tau0}, stop: {collisions_per_particle: 1}}\n"
         "system: {density: 1.0e-3, temperature: 1.0}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
         "forcings: [" + forcing + "]\n"
         "diagnostics: [temperature]\noutput: {file: out.h5}\n";
}

struct Driven {
  TempDir dir;
  PluginFromPipeline made;
  TwoSpecies gas;
  StepContext ctx;
  Streams streams;
  Driven(const std::string& forcing, std::size_t light, std::size_t heavy, double m_heavy)
      : made(dir, homogeneous_yaml(forcing), "forcings[0]", light + heavy), gas(made.sys, light, heavy, m_heavy) {
    ctx.system = &gas.sys;
    ctx.dt = 0.01 * gas.sys.time_unit0;
  }
  Forcing& forcing() { return made.as<Forcing>(); }
  double step(std::uint64_t k) {
    streams = streams_at(StreamPurpose::forcing, k);
    ctx.streams = &streams;
    ctx.step = k;
    return forcing().apply(ctx, gas.span);
  }
};

// xi0^2 = 0.5 T0/(m tau0). From rest at every step, particle i gains (m_i/2)|d_i - Delta|^2 with
// d_i Gaussian of variance xi0^2 dt per component: per particle of species s the mean rate is
// (3/2) m_s xi0^2 (1 - 2 m_s/M + sum m^2/M^2) (the net-momentum removal, O(1/N)). m_i |d|^2/2 is
// (m_s xi0^2 dt / 2) chi^2_3, relative standard deviation sqrt(2/3) per sample; 1000 particles x 400
// steps per species give 0.0013 on the mean; 5 of them, 0.0065, separate the heavy species'
// factor m_s = 4 from any other. The returned energy is the particles' energy change to round-off
// (1e-12 relative: sums of 2000 terms) and the total momentum stays zero to round-off.
TEST(MixtureForcings, WhiteNoiseHeatsEverySpeciesAtThreeHalvesItsMassTimesXi0Squared) {
  Driven d("{plugin: white_noise_thermostat, xi0_squared: 0.5}", 1000, 1000, 4.0);
  QuantityBoard board;
  d.forcing().publish(board);
  const double xi2 = 0.5 * d.gas.sys.initial_temperature / d.gas.sys.time_unit0;  // T0/(m tau0), m = 1
  ASSERT_NE(board.find("white_noise_strength"), nullptr);
  EXPECT_NEAR(*board.find("white_noise_strength") / xi2, 1.0, 1e-12);
  EXPECT_EQ(d.forcing().stage(), Forcing::Stage::after_collisions);
  EXPECT_TRUE(d.forcing().conserves().momentum);
  const std::size_t steps = 400;
  double gained[2] = {0, 0}, returned = 0, declared = 0;
  for (std::size_t k = 0; k < steps; ++k) {
    std::fill(d.gas.vx.begin(), d.gas.vx.end(), 0.0);
    std::fill(d.gas.vy.begin(), d.gas.vy.end(), 0.0);
    std::fill(d.gas.vz.begin(), d.gas.vz.end(), 0.0);
    double rate = 0;
    ASSERT_TRUE(d.forcing().expected_energy_rate(d.ctx, d.gas.span, rate));
    declared += rate * d.ctx.dt;
    const double added = d.step(k);
    const double change = d.gas.kinetic_energy();
    ASSERT_NEAR(added / change, 1.0, 1e-12) << "step " << k;
    for (int c = 0; c < 3; ++c) ASSERT_LT(std::abs(d.gas.momentum(c)) / (d.gas.total_mass() * std::sqrt(xi2 * d.ctx.dt)), 1e-12);
    returned += added;
    for (std::size_t i = 0; i < d.gas.span.count; ++i)
      gained[d.gas.kind[i]] += 0.5 * d.gas.mass(i) *
                               (d.gas.vx[i] * d.gas.vx[i] + d.gas.vy[i] * d.gas.vy[i] + d.gas.vz[i] * d.gas.vz[i]);
  }
  const double M = 1000 * 1.0 + 1000 * 4.0, m2 = 1000 * 1.0 + 1000 * 16.0;
  const double time = static_cast<double>(steps) * d.ctx.dt;
  const double tolerance = 5.0 * std::sqrt(2.0 / 3.0) / std::sqrt(1000.0 * steps);
  for (std::uint32_t s : {0u, 1u}) {
    const double m = d.gas.sys.species_mass(s);
    const double expected = 1.5 * m * xi2 * (1.0 - 2.0 * m / M + m2 / (M * M));
    const double measured = gained[s] / (1000.0 * time);
    EXPECT_NEAR(measured / expected, 1.0, tolerance) << "species " << s;
    std::printf("white noise, species %u (m = %g): dE/dt per particle = %.5f x (3/2) m xi0^2 (1 - 2m/M + sum m^2/M^2)"
                " (tolerance %.4f)\n", s, m, measured / expected, tolerance);
  }
  // The declared rate is the mean of what apply() returns (relative standard error 0.0011 for the
  // mixture; 5 of them).
  EXPECT_NEAR(returned / declared, 1.0, tolerance);
}

// The kicks come from each particle's own stream: without the momentum removal (a sum over all
// particles) a particle's kick is the same whatever the storage order, to the last bit.
TEST(MixtureForcings, WhiteNoiseKicksDoNotDependOnStorageOrder) {
  Driven a("{plugin: white_noise_thermostat, xi0_squared: 0.5, remove_net_momentum: false}", 300, 200, 4.0);
  Driven b("{plugin: white_noise_thermostat, xi0_squared: 0.5, remove_net_momentum: false}", 300, 200, 4.0);
  EXPECT_FALSE(a.forcing().conserves().momentum);
  std::reverse(b.gas.id.begin(), b.gas.id.end());  // particle id[i] now sits at 499 - i
  std::reverse(b.gas.kind.begin(), b.gas.kind.end());
  a.step(3);
  b.step(3);
  for (std::size_t i = 0; i < 500; ++i) {
    ASSERT_EQ(a.gas.vx[i], b.gas.vx[499 - i]);
    ASSERT_EQ(a.gas.vy[i], b.gas.vy[499 - i]);
    ASSERT_EQ(a.gas.vz[i], b.gas.vz[499 - i]);
  }
  // Without the removal the kicks carry a net momentum, O(sqrt(sum m^2 xi0^2 dt)): not zero.
  EXPECT_GT(std::abs(a.gas.momentum(0)), 0.0);
}

// body_acceleration's apply() (a homogeneous system): v += g dt for every species, and it returns
// sum m_i [(v_i + g dt)^2 - v_i^2] / 2, the particles' energy change to round-off.
TEST(MixtureForcings, BodyAccelerationReturnsTheMassWeightedEnergy) {
  Driven d("{plugin: body_acceleration, acceleration: 0.3}", 400, 600, 4.0);
  EXPECT_NE(d.forcing().extension(species_id), nullptr);
  Rng rng = host::StreamFactory::standalone(5, 0);
  for (std::size_t i = 0; i < d.gas.span.count; ++i) {
    d.gas.vx[i] = rng.normal() + 0.2;
    d.gas.vy[i] = rng.normal();
    d.gas.vz[i] = rng.normal();
  }
  const double before = d.gas.kinetic_energy(), vx0 = d.gas.vx[7];
  const double added = d.step(0);
  const double g = d.made.pipeline.forcings.at(0).params.real("acceleration");
  EXPECT_NEAR(d.gas.vx[7] - vx0, g * d.ctx.dt, 1e-15);
  EXPECT_NEAR(added / (d.gas.kinetic_energy() - before), 1.0, 1e-9);  // a difference of two sums ~ 1e3
}

}  // namespace
