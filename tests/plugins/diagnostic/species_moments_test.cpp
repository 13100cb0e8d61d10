// The species_moments diagnostic driven directly with hand-built two-species states (a SystemInfo
// with two species and a ParticleSpan with a species column, as the host hands them over in a
// mixture), and in a real one-species run against temperature and cumulants. Every tolerance is
// argued beside its check: round-off for values computed by hand, the statistical error of the
// sample for the Maxwellian.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>
#include <vector>

#include "config/system_info.hpp"
#include "engine/particle_store.hpp"
#include "engine/streams.hpp"
#include "output/diagnostic_output.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

const std::string kPipeline =
    "run:\n  seed: 5\n  particles: 6\n  time_step: {value: 0.01, unit: tau0}\n  stop: {collisions_per_particle: 1}\n"
    "system: {density: 1.0e-3, sigma: 1, temperature: 1.0}\n"
    "initial_state: maxwellian\ncollision: {plugin: inelastic_hard_spheres, alpha: 0.8}\n"
    "diagnostics:\n  - species_moments\noutput: {file: unused.h5}\n";

// Species A (mass 1) and B (mass 4): the two-species SystemInfo of a mixture.
const SpeciesInfo kSpecies[2] = {{"A", 1.0, 1.0, 0.5}, {"B", 4.0, 1.5, 0.5}};

struct Bench : t::DiagnosticBench {
  host::ParticleStore store;
  ParticleSpan p;
  std::vector<std::uint32_t> species;
  Bench(const t::TempDir& dir, std::size_t particles, bool slab = false)
      : DiagnosticBench(dir, kPipeline, "species_moments", particles) {
    sys.species_count = 2;
    sys.species = kSpecies;
    if (slab) {
      sys.geometry = Geometry::slab;
      sys.bins = 2;
      out->set_bins(host::bin_centres_lambda0(sys));
    }
    store.allocate(particles, {}, slab);
    p = store.span();
    species.assign(particles, 0u);
    p.species = species.data();
  }
  const std::vector<double>& profile(const std::string& name) const {
    for (const auto& q : out->profiles)
      if (q.name == name) return q.values;
    throw std::runtime_error("no profile " + name);
  }
};

// The brute-force partial temperature of species s over the particles in `members` (all when
// empty): V relative to the barycentric velocity of those particles.
double partial_temperature(const ParticleSpan& p, const SystemInfo& sys, std::uint32_t s,
                           const std::vector<std::size_t>& members, double* barycentric = nullptr) {
  std::vector<std::size_t> all = members;
  if (all.empty())
    for (std::size_t i = 0; i < p.count; ++i) all.push_back(i);
  double M = 0, P[3] = {0, 0, 0};
  for (std::size_t i : all) {
    const double m = sys.species_mass(p.species_of(i));
    M += m;
    P[0] += m * p.vx[i], P[1] += m * p.vy[i], P[2] += m * p.vz[i];
  }
  const double u[3] = {P[0] / M, P[1] / M, P[2] / M};
  if (barycentric)
    for (int a = 0; a < 3; ++a) barycentric[a] = u[a];
  double sum = 0, n = 0;
  for (std::size_t i : all) {
    if (p.species_of(i) != s) continue;
    const double X = p.vx[i] - u[0], Y = p.vy[i] - u[1], Z = p.vz[i] - u[2];
    sum += sys.species_mass(s) * (X * X + Y * Y + Z * Z);
    n += 1;
  }
  return sum / (3 * n);
}

// One sample of the span at `time` with the given collision tallies, the host's barycentric mean.
void sample(Bench& b, double time, const std::vector<CollisionTally>& tallies = {}, double collision_energy = 0,
            const BoundaryTally* species_walls = nullptr) {
  SampledMoments sm;
  double u[3];
  partial_temperature(b.p, b.sys, 0, {}, u);
  for (int a = 0; a < 3; ++a) sm.local.mean[a] = u[a];
  sm.cell_mean_velocity = sm.local.mean;
  sm.number_density = b.sys.number_density;
  StepContext ctx;
  ctx.system = &b.sys;
  ctx.moments = &sm;
  ctx.time = time;
  ctx.collision_tallies = tallies.data();
  ctx.collision_tally_count = tallies.size();
  ctx.collision_energy_change = collision_energy;
  BoundaryTally walls[2];
  if (species_walls) {
    ctx.boundaries = walls;
    ctx.boundary_count = 2;
    ctx.species_boundaries = species_walls;
  }
  b.diag->sample(ctx, b.p);
}
void record(Bench& b, double time) {
  StepContext ctx;
  ctx.system = &b.sys;
  b.out->begin_record(time / b.sys.time_unit0, 0);
  b.diag->record(ctx, *b.out);
  b.out->check_record("species_moments");
}

// The hand-built state: a flow U shared by all; A (mass 1, 4 particles) drifts by -1 along x and B
// (mass 4, 2 particles) by +1/2, so that the barycentric velocity is U (4 x 1 x (-1) + 2 x 4 x 1/2 = 0).
// Peculiar velocities: A (0,0,0), (-2,0,0), (-1,2,0), (-1,-2,0); B (1/2,0,1), (1/2,0,-1). By hand:
//   T_A = 14/12 = 7/6, T_B = 4 x 2.5/6 = 5/3, T = (4 T_A + 2 T_B)/6 = 4/3 (= sum m V^2 / 3N = 24/18),
//   T_A/T = 7/8, T_B/T = 5/4;  a2_A = 16.5/(15 (7/6)^2) - 1 = -141/735, a2_B = 16 x 1.5625/(15 (5/3)^2) - 1 = -2/5;
//   P_A = (6, 8, 0; 0, 0, 0)/Omega, P_B = 4 (0.5, 0, 2; 0, 0, 0)/Omega;
//   q_A = (1/2)(-18, 0, 0)/Omega, q_B = (4/2)(1.25, 0, 0)/Omega.
const double kU[3] = {0.5, -0.25, 0.125};
void hand_state(Bench& b) {
  const double v[6][3] = {{0, 0, 0}, {-2, 0, 0}, {-1, 2, 0}, {-1, -2, 0}, {0.5, 0, 1}, {0.5, 0, -1}};
  for (std::size_t i = 0; i < 6; ++i) {
    b.species[i] = i < 4 ? 0u : 1u;
    b.p.set_velocity(i, {kU[0] + v[i][0], kU[1] + v[i][1], kU[2] + v[i][2]});
  }
}

}  // namespace

// Every moment of both species equals its value computed by hand (above), to round-off: the values
// are sums of a few numbers of order 1, so 1e-13 relative is a hundred times the rounding.
TEST(SpeciesMoments, TwoSpeciesMomentsMatchTheHandValues) {
  t::TempDir dir;
  Bench b(dir, 6);
  hand_state(b);
  b.diag->begin(b.sys, b.board, *b.out);
  sample(b, 0.0);
  record(b, 0.0);
  const double Omega = b.sys.volume, nT0 = b.sys.number_density, v0 = std::sqrt(2.0);  // T0 = 1, m = 1
  auto near = [&](const std::string& name, double expected) {
    const double got = b.series(name).at(0);
    EXPECT_NEAR(got, expected, 1e-13 * std::max(1.0, std::fabs(expected))) << name;
  };
  near("n[A]", 4.0 / 6.0);
  near("n[B]", 2.0 / 6.0);
  near("u_x[A]", (kU[0] - 1.0) / v0);
  near("u_y[A]", kU[1] / v0);
  near("u_z[B]", kU[2] / v0);
  near("u_x[B]", (kU[0] + 0.5) / v0);
  near("T[A]", 7.0 / 6.0);
  near("T[B]", 5.0 / 3.0);
  near("T", 4.0 / 3.0);
  near("T_ratio[A]", 7.0 / 8.0);
  near("T_ratio[B]", 5.0 / 4.0);
  near("a2[A]", -141.0 / 735.0);
  near("a2[B]", -0.4);
  near("P_xx[A]", 6.0 / Omega / nT0);
  near("P_yy[A]", 8.0 / Omega / nT0);
  near("P_zz[A]", 0.0);
  near("P_xy[A]", 0.0);
  near("P_xx[B]", 4.0 * 0.5 / Omega / nT0);
  near("P_zz[B]", 4.0 * 2.0 / Omega / nT0);
  near("P_xz[B]", 0.0);
  near("q_x[A]", 0.5 * -18.0 / Omega / (nT0 * v0));
  near("q_y[A]", 0.0);
  near("q_x[B]", 2.0 * 1.25 / Omega / (nT0 * v0));
  near("q_z[B]", 0.0);
  // The species' pressures add up to n T (sum_X n_X T_X = n T): (6 + 8 + 2 + 8) / 3 / Omega = 8/Omega = (6/Omega)(4/3).
  const double p = (b.series("P_xx[A]").at(0) + b.series("P_yy[A]").at(0) + b.series("P_zz[A]").at(0) +
                    b.series("P_xx[B]").at(0) + b.series("P_yy[B]").at(0) + b.series("P_zz[B]").at(0)) / 3.0;
  EXPECT_NEAR(p, 1.0 * 4.0 / 3.0, 1e-13);
}

// Partial cooling rates from the tallies species_energy_change[X] between two samples: zeta_X =
// -dE_X / ((3/2) N_X dt sqrt(T_X(a) T_X(b))) and zeta the same for the mixture, both in 1/tau0; T_X
// of each state by brute force (partial_temperature). Round-off again.
TEST(SpeciesMoments, PartialCoolingRatesFromTheTallies) {
  t::TempDir dir;
  Bench b(dir, 6);
  hand_state(b);
  b.diag->begin(b.sys, b.board, *b.out);
  const double TA1 = partial_temperature(b.p, b.sys, 0, {}), TB1 = partial_temperature(b.p, b.sys, 1, {});
  std::vector<CollisionTally> tallies = {{"species_energy_change[A]", 0.0}, {"species_energy_change[B]", 0.0}};
  sample(b, 0.0, tallies, 0.0);
  record(b, 0.0);
  EXPECT_TRUE(std::isnan(b.series("zeta[A]").at(0)));  // no interval yet
  // Cool A by 0.8 and B by 0.6 in energy (the state: A's velocities scaled about U by 0.9, B's by 0.8).
  for (std::size_t i = 0; i < 6; ++i) {
    const double f = i < 4 ? 0.9 : 0.8;
    b.p.set_velocity(i, {kU[0] + f * (b.p.vx[i] - kU[0]), kU[1] + f * (b.p.vy[i] - kU[1]), kU[2] + f * (b.p.vz[i] - kU[2])});
  }
  const double TA2 = partial_temperature(b.p, b.sys, 0, {}), TB2 = partial_temperature(b.p, b.sys, 1, {});
  const double dt = 0.7 * b.sys.time_unit0;
  tallies[0].value = -0.8;
  tallies[1].value = -0.6;
  sample(b, dt, tallies, -1.4);
  record(b, dt);
  const double tau0 = b.sys.time_unit0;
  const double zA = 0.8 / (1.5 * 4 * dt * std::sqrt(TA1 * TA2)) * tau0, zB = 0.6 / (1.5 * 2 * dt * std::sqrt(TB1 * TB2)) * tau0;
  const double T1 = (4 * TA1 + 2 * TB1) / 6, T2 = (4 * TA2 + 2 * TB2) / 6;
  const double z = 1.4 / (1.5 * 6 * dt * std::sqrt(T1 * T2)) * tau0;
  EXPECT_NEAR(b.series("zeta[A]").at(1), zA, 1e-13 * zA);
  EXPECT_NEAR(b.series("zeta[B]").at(1), zB, 1e-13 * zB);
  EXPECT_NEAR(b.series("zeta").at(1), z, 1e-13 * z);
  EXPECT_NEAR(b.series("zeta_ratio[A]").at(1), zA / z, 1e-13);
  // The mixture temperature of the second record (its one sample, the second state) is the brute-force one.
  EXPECT_NEAR(b.series("T").at(1), T2, 1e-13);
  b.diag->finish(StepContext{}, *b.out);
  EXPECT_TRUE(b.summary.empty()) << b.summary.at(0);  // the tallies were there: no note
}

// A rule without the tallies: zeta[X] is NaN and the summary says why; zeta is still measured.
TEST(SpeciesMoments, WithoutTalliesThePartialRatesAreNaNAndSaidSo) {
  t::TempDir dir;
  Bench b(dir, 6);
  hand_state(b);
  b.diag->begin(b.sys, b.board, *b.out);
  sample(b, 0.0, {}, 0.0);
  sample(b, 1.0, {}, -1.0);
  record(b, 1.0);
  EXPECT_TRUE(std::isnan(b.series("zeta[A]").at(0)));
  EXPECT_GT(b.series("zeta").at(0), 0.0);
  b.diag->finish(StepContext{}, *b.out);
  ASSERT_EQ(b.summary.size(), 1u);
  EXPECT_NE(b.summary[0].find("species_energy_change"), std::string::npos);
}

// Maxwellian velocities at one temperature T = 1.3 for both species (components N(0, T/m_X)), N_X =
// 100000 each: T_A / T_B = 1 within 4 of its standard errors. m_X V^2 / T is chi-squared with 3
// degrees of freedom, so T_X has relative variance 2/(3 N_X) and the ratio sqrt(2/(3 N_A) + 2/(3 N_B))
// = 0.37 % (the barycentric velocity subtracted removes 3 of 6 N degrees of freedom: 5e-6 relative).
// a2_X vanishes for a Maxwellian; by the delta method on a2 = 9 <x^2> / (15 <x>^2) - 1 (x = m V^2 / T,
// Var x = 6, Var x^2 = 720, Cov(x, x^2) = 60) its variance is 0.533 / N_X: 4 sigma = 0.0092.
TEST(SpeciesMoments, MaxwellianAtEqualTemperaturesIsInEquipartition) {
  const std::size_t NX = 100000, N = 2 * NX;
  t::TempDir dir;
  Bench b(dir, N);
  Rng rng = host::StreamFactory::standalone(33, 0);
  const double T = 1.3;
  for (std::size_t i = 0; i < N; ++i) {
    b.species[i] = i < NX ? 0u : 1u;
    const double sd = std::sqrt(T / kSpecies[b.species[i]].mass);
    b.p.set_velocity(i, {sd * rng.normal(), sd * rng.normal(), sd * rng.normal()});
  }
  b.diag->begin(b.sys, b.board, *b.out);
  sample(b, 0.0);
  record(b, 0.0);
  const double ratio = b.series("T[A]").at(0) / b.series("T[B]").at(0);
  const double sigma = std::sqrt(2.0 / (3.0 * NX) + 2.0 / (3.0 * NX));
  std::printf("  T_A/T_B = %.5f (sigma %.5f), T_A/T = %.5f, a2_A = %.5f, a2_B = %.5f\n", ratio, sigma,
              b.series("T_ratio[A]").at(0), b.series("a2[A]").at(0), b.series("a2[B]").at(0));
  EXPECT_NEAR(ratio, 1.0, 4 * sigma);
  EXPECT_NEAR(b.series("T[A]").at(0), T, 4 * T * std::sqrt(2.0 / (3.0 * NX)));
  // T = (T_A + T_B)/2 here, so T_A/T - 1 = (T_A/T_B - 1)/2 to first order: its error is sigma/2, and 4 of them 2 sigma.
  EXPECT_NEAR(b.series("T_ratio[A]").at(0), 1.0, 2 * sigma);
  for (const char* a2 : {"a2[A]", "a2[B]"}) EXPECT_NEAR(b.series(a2).at(0), 0.0, 4 * std::sqrt(0.533 / NX)) << a2;
}

// A slab of two sampling bins: the profiles per species take V about the bin's own barycentric
// flow; each value against the brute force over that bin's particles (round-off). Bin 0 holds A's
// particles 0, 1 and B's 4; bin 1 the others. One sample, so the window sums are that sample's.
TEST(SpeciesMoments, SlabProfilesPerSpeciesInEachBin) {
  t::TempDir dir;
  Bench b(dir, 6, true);
  hand_state(b);
  const std::vector<std::size_t> bin[2] = {{0, 1, 4}, {2, 3, 5}};
  for (int k = 0; k < 2; ++k)
    for (std::size_t i : bin[k]) b.p.y[i] = (k == 0 ? -0.25 : 0.25) * b.sys.box[1];
  b.diag->begin(b.sys, b.board, *b.out);
  // No per-species wall tallies in this hand-made slab: hand the diagnostic zeros.
  const BoundaryTally walls[4] = {};
  sample(b, 0.0, {}, 0.0, walls);
  record(b, 0.0);
  const double Vbin = b.sys.bin_width() * b.sys.cross_section(), n0 = b.sys.number_density, v0 = std::sqrt(2.0);
  for (std::size_t k = 0; k < 2; ++k) {
    double u[3];
    const double TA = partial_temperature(b.p, b.sys, 0, bin[k], u), TB = partial_temperature(b.p, b.sys, 1, bin[k]);
    const double T = (2 * TA + 1 * TB) / 3;
    EXPECT_NEAR(b.profile("n_profile[A]").at(k), 2 / Vbin / n0, 1e-12);
    EXPECT_NEAR(b.profile("n_profile[B]").at(k), 1 / Vbin / n0, 1e-12);
    EXPECT_NEAR(b.profile("n_profile").at(k), 3 / Vbin / n0, 1e-12);
    EXPECT_NEAR(b.profile("T_profile[A]").at(k), TA, 1e-13) << k;
    EXPECT_NEAR(b.profile("T_profile[B]").at(k), TB, 1e-13) << k;
    EXPECT_NEAR(b.profile("T_profile").at(k), T, 1e-13) << k;
    EXPECT_NEAR(b.profile("T_ratio_profile[A]").at(k), TA / T, 1e-13) << k;
    EXPECT_NEAR(b.profile("u_x_profile").at(k), u[0] / v0, 1e-13) << k;
    const double uxA = (b.p.vx[bin[k][0]] + b.p.vx[bin[k][1]]) / 2;
    EXPECT_NEAR(b.profile("u_x_profile[A]").at(k), uxA / v0, 1e-13) << k;
  }
}

// Per-species wall fluxes: the change of each species' tally between records over A dt, in the
// units of wall_fluxes.
TEST(SpeciesMoments, PerSpeciesWallFluxes) {
  t::TempDir dir;
  Bench b(dir, 6, true);
  hand_state(b);
  b.diag->begin(b.sys, b.board, *b.out);
  BoundaryTally walls[4] = {};  // [b * 2 + s]: y_min A, y_min B, y_max A, y_max B
  sample(b, 0.0, {}, 0.0, walls);
  record(b, 0.0);
  walls[1].hits = 10;
  walls[1].momentum[0] = 0.3;
  walls[1].energy = -0.7;
  walls[2].momentum[1] = -1.1;
  const double dt = 2.0;
  sample(b, dt, {}, 0.0, walls);
  record(b, dt);
  const double A = b.sys.cross_section(), nT0 = b.sys.number_density;
  const double rate_unit = 1.0 / (b.sys.mean_free_path0 * b.sys.mean_free_path0 * b.sys.time_unit0);
  EXPECT_NEAR(b.series("y_min_hit_rate[B]").at(1), 10 / (A * dt) / rate_unit, 1e-12 * 10 / (A * dt) / rate_unit);
  EXPECT_NEAR(b.series("y_min_momentum_flux_x[B]").at(1), 0.3 / (A * dt) / nT0, 1e-13);
  EXPECT_NEAR(b.series("y_min_energy_flux[B]").at(1), -0.7 / (A * dt) / (nT0 * std::sqrt(2.0)), 1e-13);
  EXPECT_NEAR(b.series("y_max_momentum_flux_y[A]").at(1), -1.1 / (A * dt) / nT0, 1e-13);
  EXPECT_EQ(b.series("y_min_energy_flux[A]").at(1), 0.0);
  EXPECT_TRUE(std::isnan(b.series("y_min_energy_flux[A]").at(0)));  // the first record: no interval
}

// A slab mixture whose context hands no per-species tallies (a harness driving the diagnostic by
// hand): the wall series are NaN and the summary says so, rather than an error.
TEST(SpeciesMoments, WithoutPerSpeciesWallTalliesTheWallSeriesAreNaN) {
  t::TempDir dir;
  Bench b(dir, 6, true);
  hand_state(b);
  b.diag->begin(b.sys, b.board, *b.out);
  sample(b, 0.0);
  record(b, 0.0);
  sample(b, 1.0);
  record(b, 1.0);
  EXPECT_TRUE(std::isnan(b.series("y_max_hit_rate[A]").at(1)));
  EXPECT_TRUE(std::isnan(b.series("y_min_momentum_flux_x[B]").at(1)));
  b.diag->finish(StepContext{}, *b.out);
  bool said = false;
  for (const auto& line : b.summary) said = said || line.find("per-species boundary tallies") != std::string::npos;
  EXPECT_TRUE(said);
}

// One species (no system.species): the diagnostic works and reproduces temperature's T and
// cumulants' a2 from the same moments, with T_ratio = 1 and zeta_ratio = 1 (the one species' tally
// is the host's collision_energy_change). A real run of the small HCS.
TEST(SpeciesMoments, OneSpeciesRunReproducesTemperatureAndCumulants) {
  t::TempDir dir;
  std::string yaml = t::kSmallHcsPipeline;
  yaml.replace(yaml.find("diagnostics: [temperature]"), 26, "diagnostics: [temperature, cumulants, species_moments]");
  host::Pipeline p = t::load_yaml(dir, yaml);
  host::Engine e(p);
  e.run();
  const auto& T = t::series(e, "temperature", "temperature");
  const auto& a2 = t::series(e, "cumulants", "a2");
  const auto& T0 = t::series(e, "species_moments", "T[0]");
  const auto& Tmix = t::series(e, "species_moments", "T");
  const auto& a20 = t::series(e, "species_moments", "a2[0]");
  const auto& ratio = t::series(e, "species_moments", "T_ratio[0]");
  const auto& zratio = t::series(e, "species_moments", "zeta_ratio[0]");
  ASSERT_EQ(T.size(), T0.size());
  ASSERT_GT(T.size(), 3u);
  // The same sums in another order: a few ulps of T, of a2 + 1.
  for (std::size_t k = 0; k < T.size(); ++k) {
    EXPECT_NEAR(T0[k], T[k], 1e-12 * T[k]) << k;
    EXPECT_NEAR(Tmix[k], T0[k], 1e-14 * T[k]) << k;  // N T / N: an ulp or two
    EXPECT_NEAR(a20[k], a2[k], 1e-12) << k;
    EXPECT_NEAR(ratio[k], 1.0, 1e-14) << k;
    if (k > 0) EXPECT_NEAR(zratio[k], 1.0, 1e-12) << k;
  }
}

// A real two-species run: elastic hard spheres (light: m = 1, sigma = 1; heavy: m = 4, sigma = 1.5;
// half and half) started out of equipartition, T_light = 0.5 T0, T_heavy = 1.5 T0, relax to T_X/T = 1.
// The steady mean of T_ratio[light] over s = 10 ... 25 is 1 within 4 of the host's errors over 8
// realizations (their scatter / sqrt 8: z follows Student's t with 7 degrees of freedom, P(|t| > 4)
// = 0.5 %; one realization's batch means were NaN here, the records' autocorrelation time being 6.5
// records), and that error is below 0.002 so that the check means something. T is the host's
// temperature to round-off. Needs the species-aware inelastic_hard_spheres and maxwellian
// (species_temperatures): skipped, saying so, while the build's plugins are refused.
TEST(SpeciesMoments, ElasticMixtureRelaxesToEquipartition) {
  const std::string yaml =
      "run:\n  seed: 33\n  particles: 10000\n  realizations: 8\n  time_step: {value: 0.02, unit: tau0}\n"
      "  stop: {collisions_per_particle: 25}\n  sample_every: 5\n  record_every: 25\n"
      "  average_after: {collisions_per_particle: 10}\n"
      "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: homogeneous\n  species:\n"
      "    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
      "    - {name: heavy, mass: 4, diameter: 1.5, fraction: 0.5}\n"
      "initial_state: {plugin: maxwellian, species_temperatures: \"light: 0.5, heavy: 1.5\"}\n"
      "collision: {plugin: inelastic_hard_spheres, alpha: 1.0}\n"
      "diagnostics: [temperature, species_moments]\noutput: {file: out.h5}\n";
  t::TempDir dir;
  dir.write("mixture.yaml", yaml);
  const t::ProcessResult r = t::run_gdsmc({"run", "mixture.yaml", "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const t::h5::File f(dir.path() / "out.h5");
  const std::string g = "/diagnostics/species_moments/";
  const std::vector<double> ratio = t::h5::read_doubles(f.id(), g + "T_ratio[light]");
  EXPECT_NEAR(ratio.at(0), 0.5, 1e-12);  // the initial state at exactly T_light/T = 0.5
  const double mean = t::h5::read_scalar(f.id(), g + "T_ratio[light].steady_mean");
  const double error = t::h5::read_scalar(f.id(), g + "T_ratio[light].steady_stderr");
  std::printf("  T_light/T = %.5f +- %.5f over s = 10 ... 25, 8 realizations (from 0.5 at s = 0)\n", mean, error);
  ASSERT_TRUE(std::isfinite(error));
  EXPECT_LT(error, 0.002);
  EXPECT_NEAR(mean, 1.0, 4 * error);
  const std::vector<double> T = t::h5::read_doubles(f.id(), "/diagnostics/temperature/temperature");
  const std::vector<double> Tmix = t::h5::read_doubles(f.id(), g + "T");
  ASSERT_EQ(T.size(), Tmix.size());
  for (std::size_t k = 0; k < T.size(); ++k) EXPECT_NEAR(Tmix[k], T[k], 1e-12 * T[k]) << k;
}
