// The host's DSMC scheme for a mixture (engine/collision_species.cpp): candidates per pair of
// species, each class with its own majorant. With an elastic hard-sphere rule that weighs the pair
// by its masses, a two-species gas (masses 1 and 4, diameters 1 and 2) must collide at the
// equilibrium rates of every pair class, Z_ab = n_a n_b pi sigma_ab^2 <g_ab> (halved for a = b),
// conserve momentum and energy to round-off, relax two unequal temperatures to one (equipartition),
// and give the same bits on one thread and on two.
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include <gdsmc/collision.hpp>

#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/streams.hpp"
#include "engine/work_pool.hpp"

namespace {

using namespace gdsmc;

constexpr double kMass[2] = {1.0, 4.0};
constexpr double kDiameter[2] = {1.0, 2.0};

// Elastic hard spheres of unequal masses (Garzó & Dufty 1999 Eq. 2.3 at alpha = 1), tallying the
// collisions of each class: (0,0) -> 0, (0,1) -> 1, (1,1) -> 2.
struct MixtureElastic {
  static constexpr bool species_aware = true;
  std::vector<std::string> tallies() const { return {"c00", "c01", "c11"}; }
  double collide(Vec3& v1, Vec3& v2, const Vec3& s, PairContext& pair) const {
    const std::uint32_t a = pair.particles.species_of(pair.i), b = pair.particles.species_of(pair.j);
    const double ma = kMass[a], mb = kMass[b];
    const double gs = dot(v1 - v2, s);
    v1 -= (2.0 * mb / (ma + mb) * gs) * s;
    v2 += (2.0 * ma / (ma + mb) * gs) * s;
    pair.tally[a + b] += 1;
    return 0.0;
  }
};

struct Mixture {
  std::vector<std::uint32_t> id, species;
  std::vector<double> vx, vy, vz;
  double volume;
  // n particles, the first half species 0 at temperature t0, the rest species 1 at t1, total
  // momentum removed.
  Mixture(std::size_t n, double volume_, double t0, double t1)
      : id(n), species(n), vx(n), vy(n), vz(n), volume(volume_) {
    Rng rng = host::StreamFactory::standalone(17, 0);
    double p[3] = {0, 0, 0}, m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      id[i] = static_cast<std::uint32_t>(i);
      species[i] = i < n / 2 ? 0 : 1;
      const double scale = std::sqrt((species[i] ? t1 : t0) / kMass[species[i]]);
      vx[i] = scale * rng.normal(), vy[i] = scale * rng.normal(), vz[i] = scale * rng.normal();
      p[0] += kMass[species[i]] * vx[i], p[1] += kMass[species[i]] * vy[i], p[2] += kMass[species[i]] * vz[i];
      m += kMass[species[i]];
    }
    for (std::size_t i = 0; i < n; ++i) vx[i] -= p[0] / m, vy[i] -= p[1] / m, vz[i] -= p[2] / m;
  }
  ParticleSpan span() {
    ParticleSpan s;
    s.count = id.size();
    s.id = id.data();
    s.species = species.data();
    s.vx = vx.data(); s.vy = vy.data(); s.vz = vz.data();
    return s;
  }
  // T_s = m_s <V^2> / 3 of species s (the mean momentum is zero), and sum m v, sum m v^2 / 2.
  double temperature(std::uint32_t s) const {
    double sum = 0, count = 0;
    for (std::size_t i = 0; i < id.size(); ++i)
      if (species[i] == s) sum += kMass[s] * (vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]), count += 1;
    return sum / (3.0 * count);
  }
  Vec3 momentum() const {
    Vec3 p{0, 0, 0};
    for (std::size_t i = 0; i < id.size(); ++i) p += kMass[species[i]] * Vec3{vx[i], vy[i], vz[i]};
    return p;
  }
  double energy() const {
    double e = 0;
    for (std::size_t i = 0; i < id.size(); ++i) e += 0.5 * kMass[species[i]] * (vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]);
    return e;
  }
};

// `steps` collision stages of dt, moments every 4 as the engine updates them; the per-class tallies summed.
struct Totals {
  double tallies[3] = {0, 0, 0};
  std::uint64_t exceeded = 0, accepted = 0, candidates = 0;
};
Totals collide(Mixture& gas, std::size_t steps, double dt, unsigned threads, std::size_t subpopulation,
               host::PairSelection selection = host::PairSelection::uniform) {
  host::WorkPool pool(threads);
  host::CellGrid grid;
  grid.homogeneous(gas.id.size(), gas.volume);
  grid.set_species(kMass, 2);
  host::CollisionStage stage;
  stage.set_species(kMass, kDiameter, 2);
  stage.set_subpopulation(subpopulation);
  stage.set_pair_selection(selection);
  stage.set_pool(&pool);
  stage.set_tally_count(3);
  const CollisionRuleAdapter<MixtureElastic> rule{MixtureElastic{}};
  host::StreamFactory streams(23, 0);
  std::vector<CellMoments> cells;
  CellMoments global;
  Totals out;
  for (std::size_t k = 0; k < steps; ++k) {
    streams.set_step(k);
    if (k % 4 == 0) {
      grid.cell_moments(gas.span(), gas.id.size() / gas.volume, cells, global, &pool);
      if (k > 0) stage.reset_majorants();
    }
    const auto t = stage.run(rule, gas.span(), grid, &global, global.temperature, 1.0, 1.0, dt, streams);
    for (int c = 0; c < 3; ++c) out.tallies[c] += t.tallies[c];
    out.exceeded += t.majorant_exceeded;
    out.accepted += t.accepted;
    out.candidates += t.candidates;
  }
  return out;
}

// 2 x 3000 particles at T = 1, n = 6000 / 2e5: Z_ab V dt per step for each class, against the
// tallies over 300 steps (3e4 to 1.4e5 collisions in each class: Poisson errors below 0.6 %): in one
// group of all particles, uniform candidates against each class's majorant and weighted pairs from
// the species' speed envelopes (a slab layer's draw), and in four sub-populations of 1500 (their
// volume V (N_c - 1)/(N - 1) gives every class its rate too: the expected pairs of a random
// sub-population are the whole system's times N_c (N_c - 1) / (N (N - 1)), like or unlike species).
class CollisionSpeciesRates : public ::testing::TestWithParam<std::pair<std::size_t, host::PairSelection>> {};

TEST_P(CollisionSpeciesRates, EveryPairClassCollidesAtItsEquilibriumRate) {
  Mixture gas(6000, 2.0e5, 1.0, 1.0);
  const double dt = 0.8, steps = 300;
  const Vec3 p0 = gas.momentum();
  const double e0 = gas.energy();
  const Totals run = collide(gas, static_cast<std::size_t>(steps), dt, 1, GetParam().first, GetParam().second);
  // The temperature the energy fixes (the momentum is zero): the sample's, not T = 1 (1 % apart at N = 6000).
  const double n_s = 3000, T = 2.0 * e0 / (3.0 * 6000);
  for (int a = 0; a < 2; ++a)
    for (int b = a; b < 2; ++b) {
      const double mu = kMass[a] * kMass[b] / (kMass[a] + kMass[b]);   // reduced mass
      const double mean_g = std::sqrt(8.0 * T / (M_PI * mu));          // <g_ab> of two Maxwellians
      const double sigma = 0.5 * (kDiameter[a] + kDiameter[b]);
      const double pairs = a == b ? 0.5 * n_s * (n_s - 1) : n_s * n_s;
      const double expected = pairs / gas.volume * M_PI * sigma * sigma * mean_g * dt * steps;
      const double got = run.tallies[a + b];
      EXPECT_NEAR(got, expected, 4.0 * std::sqrt(expected)) << "class (" << a << "," << b << "), T = " << T;
    }
  // Momentum and energy to round-off (sum m |v| ~ 6000 x 2, sum m v^2 / 2 ~ 9000).
  const Vec3 p1 = gas.momentum();
  EXPECT_NEAR(p1.x, p0.x, 1e-9);
  EXPECT_NEAR(p1.y, p0.y, 1e-9);
  EXPECT_NEAR(p1.z, p0.z, 1e-9);
  EXPECT_NEAR(gas.energy(), e0, 1e-9 * e0);
  // Equilibrium keeps the species' temperatures equal (error of T_s: sqrt(2/(3 N_s)) = 1.5 %).
  EXPECT_NEAR(gas.temperature(0) / gas.temperature(1), 1.0, 4.0 * std::sqrt(2.0 * 2.0 / (3.0 * n_s)));
}

INSTANTIATE_TEST_SUITE_P(Groups, CollisionSpeciesRates,
                         ::testing::Values(std::pair{std::size_t{0}, host::PairSelection::uniform},
                                           std::pair{std::size_t{0}, host::PairSelection::weighted},
                                           std::pair{std::size_t{1500}, host::PairSelection::uniform}));

TEST(CollisionSpecies, UnequalTemperaturesRelaxToEquipartition) {
  // T_0 = 2, T_1 = 0.5 at the start; elastic collisions exchange energy until T_0 = T_1 = 1.25
  // (energy is conserved: the mean temperature stays). About 30 collisions per particle.
  Mixture gas(6000, 2.0e5, 2.0, 0.5);
  const double before = 0.5 * (gas.temperature(0) + gas.temperature(1));
  collide(gas, 1000, 0.8, 1, 0);
  const double t0 = gas.temperature(0), t1 = gas.temperature(1);
  EXPECT_NEAR(0.5 * (t0 + t1), before, 1e-9);
  EXPECT_NEAR(t0 / t1, 1.0, 4.0 * std::sqrt(4.0 / (3.0 * 3000)));
}

TEST(CollisionSpecies, WeightedPairsAcceptMostCandidatesAndRelaxToEquipartition) {
  // The envelopes bound |g| by c_i + c_j: most candidates collide (one species: 68-72 %), none
  // exceeds its bound, and the temperatures relax as with uniform candidates.
  Mixture gas(6000, 2.0e5, 2.0, 0.5);
  const Totals run = collide(gas, 1000, 0.8, 1, 0, host::PairSelection::weighted);
  EXPECT_EQ(run.exceeded, 0u);
  EXPECT_GT(static_cast<double>(run.accepted), 0.6 * static_cast<double>(run.candidates));  // 73.5 % here
  EXPECT_NEAR(gas.temperature(0) / gas.temperature(1), 1.0, 4.0 * std::sqrt(4.0 / (3.0 * 3000)));
}

TEST(CollisionSpecies, SameBitsOnOneThreadAndOnTwoWithSubpopulations) {
  Mixture one(8000, 2.0e5, 1.5, 0.7), two = one;
  const Totals a = collide(one, 40, 0.8, 1, 2000);
  const Totals b = collide(two, 40, 0.8, 2, 2000);
  EXPECT_GT(a.accepted, 1000u);
  EXPECT_EQ(a.accepted, b.accepted);
  EXPECT_EQ(one.vx, two.vx);
  EXPECT_EQ(one.vy, two.vy);
  EXPECT_EQ(one.vz, two.vz);
}

}  // namespace
