// The slab mover (framework/engine/streaming.cpp) on particles we own, with boundaries defined
// here: exact crossing times, flight under a body acceleration, repeated hits, containment and
// the boundary tallies. Tolerances are round-off budgets argued beside each check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "engine/cells.hpp"
#include "engine/streaming.hpp"

namespace {

using namespace gdsmc;
using host::first_crossing;

struct Specular final : Boundary {
  HitResult interact(const StepContext&, WallHit& hit, Rng&) const override {
    hit.velocity.y = -hit.velocity.y;
    return HitResult::reflected;
  }
};
struct Periodic final : Boundary {
  bool transfers() const override { return true; }
  HitResult interact(const StepContext&, WallHit&, Rng&) const override { return HitResult::transferred; }
};
struct Diffuse final : Boundary {  // re-emits at unit temperature, from the particle's own stream
  HitResult interact(const StepContext&, WallHit& hit, Rng& rng) const override {
    hit.velocity = {rng.normal(), -hit.side * std::sqrt(-2.0 * std::log(rng.uniform_open0())), rng.normal()};
    return HitResult::reflected;
  }
};
struct Sticky final : Boundary {  // a broken boundary: returns the particle moving outward
  HitResult interact(const StepContext&, WallHit&, Rng&) const override { return HitResult::reflected; }
};

struct Slab {
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::uint32_t> id;
  std::vector<std::uint32_t> cell;
  ParticleSpan span;
  double box[3] = {2.0, 1.0, 3.0};
  host::CellGrid grid;
  SystemInfo sys;
  StepContext ctx;
  host::StreamFactory streams{7, 0};
  explicit Slab(std::size_t n, std::uint64_t seed = 1)
      : x(n), y(n), z(n), vx(n), vy(n), vz(n), id(n), cell(n) {
    Rng rng = host::StreamFactory::standalone(seed, 0);
    for (std::size_t i = 0; i < n; ++i) {
      id[i] = i;
      x[i] = box[0] * rng.uniform();
      y[i] = box[1] * (rng.uniform() - 0.5);
      z[i] = box[2] * rng.uniform();
      vx[i] = rng.normal();
      vy[i] = rng.normal();
      vz[i] = rng.normal();
    }
    span.count = n;
    span.id = id.data();
    span.cell = cell.data();
    span.x = x.data(); span.y = y.data(); span.z = z.data();
    span.vx = vx.data(); span.vy = vy.data(); span.vz = vz.data();
    grid.slab(n, 10, box[1], box[0] * box[2]);
    sys.geometry = Geometry::slab;
    for (int a = 0; a < 3; ++a) sys.box[a] = box[a];
    ctx.system = &sys;
  }
  host::StreamingTally run(const Boundary& low, const Boundary& high, Vec3 g, double dt, int steps) {
    host::Mover mover(box, g, {host::Mover::Side{&low, "y_min"}, host::Mover::Side{&high, "y_max"}});
    host::StreamingTally tally;
    for (int s = 0; s < steps; ++s) {
      streams.set_step(static_cast<std::uint64_t>(s));
      mover.stream(span, cell.data(), nullptr, grid, s * dt, dt, ctx, streams, tally);
    }
    return tally;
  }
  bool all_inside() const {
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!(x[i] >= 0 && x[i] < box[0] && z[i] >= 0 && z[i] < box[2] && std::fabs(y[i]) <= 0.5 * box[1])) return false;
    return true;
  }
};

TEST(FirstCrossing, StraightFlight) {
  EXPECT_DOUBLE_EQ(first_crossing(0.0, 2.0, 0.0, 0.5, 1.0), 0.25);
  EXPECT_LT(first_crossing(0.0, 2.0, 0.0, 0.5, 0.2), 0.0);   // not within the step
  EXPECT_LT(first_crossing(0.0, -2.0, 0.0, 0.5, 10.0), 0.0); // moving away
  EXPECT_LT(first_crossing(0.5, -1.0, 0.0, 0.5, 1.0), 0.0);  // leaving the plane: no crossing at t = 0
}

TEST(FirstCrossing, ParabolaLeavingFromThePlaneComesBack) {
  // Thrown up from the floor y = -0.5 at v = 1 under g = -4: back at t = 2v/|g| = 0.5.
  EXPECT_NEAR(first_crossing(-0.5, 1.0, -4.0, -0.5, 1.0), 0.5, 1e-15);
  // Apex at y0 + v^2/(2|g|) = -0.5 + 0.125 never reaches the ceiling 0.5.
  EXPECT_LT(first_crossing(-0.5, 1.0, -4.0, 0.5, 10.0), 0.0);
  // Reaches y = 0 first on the way up: 0.5 = t - 2 t^2 has roots 0.5 +- 0 (tangent) -> 0.25 + ...
  const double t = first_crossing(-0.5, 3.0, -4.0, 0.0, 10.0);
  EXPECT_NEAR(-0.5 + 3.0 * t - 2.0 * t * t, 0.0, 1e-15);
  EXPECT_LT(t, 0.75);  // the first of the two roots (apex at t = 0.75)
}

TEST(Mover, SpecularWallsKeepEverySpeedAndNobodyLeaves) {
  Slab s(5000);
  std::vector<double> speed2(s.x.size());
  for (std::size_t i = 0; i < speed2.size(); ++i) speed2[i] = s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i];
  Specular wall;
  // dt = 0.3 with unit thermal speed in a gap of 1: many particles hit once or twice per step.
  const auto tally = s.run(wall, wall, {0, 0, 0}, 0.3, 200);
  EXPECT_TRUE(s.all_inside());
  for (std::size_t i = 0; i < speed2.size(); ++i)  // a sign flip is exact: not even round-off
    ASSERT_EQ(s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i], speed2[i]) << i;
  EXPECT_GT(tally.sides[0].hits, 10000u);
  EXPECT_GT(tally.sides[1].hits, 10000u);
  EXPECT_EQ(tally.sides[0].energy, 0.0);
  EXPECT_GT(tally.sides[0].momentum[1], 0.0);  // the floor pushes the gas up
  EXPECT_LT(tally.sides[1].momentum[1], 0.0);
  EXPECT_EQ(tally.sides[0].momentum[0], 0.0);
  for (std::size_t i = 0; i < s.cell.size(); ++i) ASSERT_EQ(s.cell[i], s.grid.layer_of(s.y[i]));
}

TEST(Mover, BouncingUnderGravityConservesMechanicalEnergy) {
  // Specular floor and ceiling with g along -y and along x: (1/2) v^2 - g.r is conserved along
  // the exact parabolas; positions are wrapped in x, so compare v_x with g_x t instead.
  Slab s(2000, 5);
  const Vec3 g{0.7, -3.0, 0.0};
  std::vector<double> e0(s.x.size()), vx0(s.x.size());
  for (std::size_t i = 0; i < e0.size(); ++i) {
    e0[i] = 0.5 * (s.vy[i] * s.vy[i]) - g.y * s.y[i];
    vx0[i] = s.vx[i];
  }
  Specular wall;
  const double dt = 0.05;
  const int steps = 400;
  const auto tally = s.run(wall, wall, g, dt, steps);
  EXPECT_TRUE(s.all_inside());
  double worst = 0;
  for (std::size_t i = 0; i < e0.size(); ++i) {
    const double e = 0.5 * (s.vy[i] * s.vy[i]) - g.y * s.y[i];
    worst = std::max(worst, std::fabs(e - e0[i]) / (std::fabs(e0[i]) + 1.0));
    // v_x grows as g_x t exactly: the walls do not touch it. Budget: 400 additions of 0.035
    // (each rounded to 2^-52 relative) plus the initial value.
    ASSERT_NEAR(s.vx[i], vx0[i] + g.x * dt * steps, 1e-12) << i;
  }
  // Each hit re-solves a quadratic; 400 steps with a few hits each accumulate ~1e-13 relative.
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(tally.sides[0].hits, 1000u);
}

TEST(Mover, PeriodicBoundaryTransfersWithoutChangingVelocities) {
  Slab s(3000, 9);
  const std::vector<double> vy0 = s.vy;
  Periodic p;
  const auto tally = s.run(p, p, {0, 0, 0}, 0.7, 50);
  EXPECT_TRUE(s.all_inside());
  EXPECT_EQ(s.vy, vy0);
  EXPECT_GT(tally.sides[0].hits + tally.sides[1].hits, 1000u);
  EXPECT_EQ(tally.sides[0].energy + tally.sides[1].energy, 0.0);
}

TEST(Mover, ABoundaryThatSendsParticlesOutIsReportedByName) {
  Slab s(100);
  Sticky bad;
  try {
    s.run(bad, bad, {0, 0, 0}, 1.0, 5);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("y_"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not point into the gas"), std::string::npos) << e.what();
  }
}

// Particles [b, e) of a span, as a span of their own.
ParticleSpan part(const ParticleSpan& s, std::size_t b, std::size_t e) {
  ParticleSpan p = s;
  p.count = e - b;
  p.id = s.id + b;
  p.cell = s.cell + b;
  p.x = s.x.data + b; p.y = s.y.data + b; p.z = s.z.data + b;
  p.vx = s.vx.data + b; p.vy = s.vy.data + b; p.vz = s.vz.data + b;
  p.species = s.species ? s.species + b : nullptr;
  return p;
}

bool same_bits(const BoundaryTally& a, const BoundaryTally& b) {
  return a.hits == b.hits && std::memcmp(a.momentum, b.momentum, sizeof a.momentum) == 0 &&
         std::memcmp(&a.energy, &b.energy, sizeof a.energy) == 0;
}

// The wall tallies and the body force's work of a step do not depend on which particles share a
// block, nor on the order of the blocks: the same particles stored in another order (so every block
// of 16384 holds other particles) and streamed in two calls, the second half first, give the
// tallies of one call over all of them to the bit (and every particle the same state: its streams
// are keyed by its id). With the blocks' sums folded in double (before the fixed point) the
// permuted storage gave other bits. A mixture too: its per-species sides, particles weighed by mass.
TEST(Mover, TalliesHaveTheSameBitsForAnyStorageOrderAndSplitOfTheParticles) {
  const std::size_t n = 3 * host::Mover::kBlock + 1234, half = n / 2 + 77;
  const double masses[2] = {1.0, 2.5};
  for (const bool mixture : {false, true}) {
    Slab whole(n, 11), split(n, 11);
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::shuffle(order.begin(), order.end(), std::mt19937_64(13));
    std::vector<std::uint32_t> species(n), split_species(n);
    for (std::size_t i = 0; i < n; ++i) species[i] = whole.id[i] % 3 == 0 ? 1u : 0u;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = order[i];
      split.id[i] = whole.id[j];
      split.x[i] = whole.x[j]; split.y[i] = whole.y[j]; split.z[i] = whole.z[j];
      split.vx[i] = whole.vx[j]; split.vy[i] = whole.vy[j]; split.vz[i] = whole.vz[j];
      split_species[i] = species[j];
    }
    if (mixture) {
      whole.span.species = species.data();
      split.span.species = split_species.data();
    }
    Diffuse wall;
    // g has a y component (parabolas, hits under gravity) and others: every particle does work.
    host::Mover mover(whole.box, {0.4, -0.6, 0.1}, {host::Mover::Side{&wall, "y_min"}, host::Mover::Side{&wall, "y_max"}});
    mover.set_tally_units(1.3, 1.0);
    if (mixture) mover.set_species(masses, 2);
    host::WorkPool pool(2);
    const double dt = 0.1;
    for (std::uint64_t step = 0; step < 3; ++step) {
      whole.streams.set_step(step);
      split.streams.set_step(step);
      host::StreamingTally one, two;
      mover.stream(whole.span, whole.cell.data(), nullptr, whole.grid, dt * step, dt, whole.ctx, whole.streams, one, &pool);
      mover.stream(part(split.span, half, n), split.cell.data() + half, nullptr, split.grid, dt * step, dt, split.ctx,
                   split.streams, two, &pool);
      mover.stream(part(split.span, 0, half), split.cell.data(), nullptr, split.grid, dt * step, dt, split.ctx,
                   split.streams, two);
      ASSERT_GT(one.sides[0].hits, 500u);  // ~7 % of the particles hit a wall per step
      ASSERT_GT(one.sides[1].hits, 500u);
      ASSERT_NE(one.acceleration_energy, 0.0);
      EXPECT_TRUE(one.exact == two.exact) << "step " << step << (mixture ? ", mixture" : "");
      EXPECT_EQ(std::memcmp(&one.acceleration_energy, &two.acceleration_energy, sizeof(double)), 0)
          << one.acceleration_energy << " against " << two.acceleration_energy;
      for (int s = 0; s < 2; ++s) {
        EXPECT_TRUE(same_bits(one.sides[s], two.sides[s])) << "side " << s << ": energy " << one.sides[s].energy
                                                            << " against " << two.sides[s].energy;
        for (std::size_t q = 0; q < 2; ++q) {
          const std::size_t at = s * host::StreamingTally::kMaxSpecies + q;
          if (mixture) ASSERT_GT(one.species_sides[at].hits, 100u);
          EXPECT_TRUE(same_bits(one.species_sides[at], two.species_sides[at])) << "side " << s << ", species " << q;
        }
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = order[i];
      ASSERT_TRUE(split.x[i] == whole.x[j] && split.y[i] == whole.y[j] && split.z[i] == whole.z[j] &&
                  split.vx[i] == whole.vx[j] && split.vy[i] == whole.vy[j] && split.vz[i] == whole.vz[j])
          << "particle " << whole.id[j];
    }
  }
}

TEST(CellGrid, CountingSortListsEveryParticleOnceInIndexOrder) {
  Slab s(10000, 3);
  s.grid.assign_and_sort(s.y.data(), s.cell.data(), s.y.size());
  std::size_t total = 0;
  for (std::size_t c = 0; c < s.grid.count(); ++c) {
    const std::uint32_t* m = s.grid.members(c);
    for (std::uint32_t k = 0; k < s.grid.members_count(c); ++k) {
      ASSERT_EQ(s.cell[m[k]], c);
      if (k) ASSERT_LT(m[k - 1], m[k]);
    }
    total += s.grid.members_count(c);
  }
  EXPECT_EQ(total, s.y.size());
}

// The layers the mover counts while it flies (block by block, on two threads) give the sort the
// same offsets and member lists as the sort's own count of cell[]: 40000 particles are 3 blocks,
// the last one short, and dt = 0.3 sends many of them through the walls and across layers.
TEST(CellGrid, LayersCountedByTheMoverSortAsTheSortsOwnCount) {
  Slab s(40000, 5);
  ASSERT_EQ((s.y.size() + host::CellGrid::kSortBlock - 1) / host::CellGrid::kSortBlock, 3u);
  Specular wall;
  host::Mover mover(s.box, {0, 0, 0}, {host::Mover::Side{&wall, "y_min"}, host::Mover::Side{&wall, "y_max"}});
  host::WorkPool pool(2);
  host::CellGrid recount;
  recount.slab(s.y.size(), s.grid.count(), s.box[1], s.box[0] * s.box[2]);
  for (int step = 0; step < 3; ++step) {
    host::StreamingTally tally;
    s.streams.set_step(static_cast<std::uint64_t>(step));
    mover.stream(s.span, s.cell.data(), s.grid.block_counts(s.y.size()), s.grid, 0.3 * step, 0.3, s.ctx, s.streams,
                 tally, &pool);
    s.grid.sort_counted(s.cell.data(), s.y.size(), &pool);
    recount.sort(s.cell.data(), s.y.size());
    for (std::size_t c = 0; c < s.grid.count(); ++c) {
      ASSERT_EQ(s.grid.members_count(c), recount.members_count(c)) << "layer " << c;
      for (std::uint32_t k = 0; k < s.grid.members_count(c); ++k)
        ASSERT_EQ(s.grid.members(c)[k], recount.members(c)[k]) << "layer " << c << ", member " << k;
    }
  }
}

// The sort in two parts, as the collision stage drives it (CellGrid::place_blocks, then each
// block's scatter_block in any order): the same member lists as sort(), and last_block(c) is the
// last block holding a member of layer c, which the collisions of layer c wait for. 3 blocks, the
// last one short; layer 0 has one member far away, in the last block; layer 3 has none.
TEST(CellGrid, BlocksScatteredInAnyOrderGiveTheSortsListsAndEachLayersLastBlock) {
  const std::size_t n = 2 * host::CellGrid::kSortBlock + 777, layers = 5;
  std::vector<std::uint32_t> cell(n);
  for (std::size_t i = 0; i < n; ++i) cell[i] = static_cast<std::uint32_t>(i * 4 / n);  // layers 0, 1, 2, 4 in order
  for (std::uint32_t& c : cell)
    if (c == 3) c = 4;
  cell[n - 5] = 0;  // a member of layer 0 in the last block
  host::CellGrid sorted, placed;
  sorted.slab(n, layers, 1.0, 1.0);
  placed.slab(n, layers, 1.0, 1.0);
  sorted.sort(cell.data(), n);
  std::uint32_t* counts = placed.block_counts(n);
  std::fill(counts, counts + 3 * layers, 0u);
  for (std::size_t i = 0; i < n; ++i) ++counts[(i / host::CellGrid::kSortBlock) * layers + cell[i]];
  placed.place_blocks(n);
  std::size_t expected_last[layers];
  std::fill(expected_last, expected_last + layers, host::CellGrid::kNoBlock);
  for (std::size_t i = 0; i < n; ++i) expected_last[cell[i]] = i / host::CellGrid::kSortBlock;
  EXPECT_EQ(expected_last[0], 2u);
  EXPECT_EQ(expected_last[3], host::CellGrid::kNoBlock);
  for (std::size_t c = 0; c < layers; ++c) {
    EXPECT_EQ(placed.last_block(c), expected_last[c]) << "layer " << c;
    EXPECT_EQ(placed.members_count(c), sorted.members_count(c)) << "layer " << c;  // known before any scatter
  }
  for (std::size_t b : {2, 0, 1}) placed.scatter_block(cell.data(), b, n);
  for (std::size_t c = 0; c < layers; ++c)
    for (std::uint32_t k = 0; k < sorted.members_count(c); ++k)
      ASSERT_EQ(placed.members(c)[k], sorted.members(c)[k]) << "layer " << c << ", member " << k;
}

// The sampled moments of a homogeneous system in one pass around a mean the caller says is
// conserved, against the two passes of velocity_moments: to round-off when the given mean is the
// mean (here, N = 150001 particles in 3 blocks, a tail that is not a multiple of the lanes, a drift
// of 0.7 thermal speeds so that v - u' is not v); when it is off by 1e-3 of the thermal speed,
// above CellGrid::kConservedMeanTolerance, the two passes run instead and give their own bits.
TEST(CellGrid, OnePassSampledMomentsAroundAConservedMeanAreTheTwoPassMoments) {
  const std::size_t n = 150001;
  std::vector<double> vx(n), vy(n), vz(n);
  std::vector<std::uint32_t> id(n);
  std::mt19937_64 engine(11);
  std::normal_distribution<double> normal;
  for (std::size_t i = 0; i < n; ++i) {
    const double gx = normal(engine), gy = normal(engine), gz = normal(engine);
    vx[i] = 0.7 + gx;
    vy[i] = -0.2 + 1.3 * gy;  // anisotropic: second moments differ
    vz[i] = gz * (1.0 + 0.5 * gz * gz / (1.0 + gz * gz));  // a non-Gaussian fourth moment
    id[i] = static_cast<std::uint32_t>(i);
  }
  ParticleSpan span;
  span.count = n;
  span.id = id.data();
  span.vx = vx.data();
  span.vy = vy.data();
  span.vz = vz.data();
  const VelocityMoments exact = velocity_moments(span);
  host::CellGrid grid;
  grid.homogeneous(n, 1.0e6);
  SampledMoments two, one, off;
  grid.sampled_moments(span, 1e-3, two);
  grid.sampled_moments(span, 1e-3, one, nullptr, exact.mean);
  auto near = [](double a, double b, double scale) { return std::fabs(a - b) <= 1e-13 * scale; };
  const double T = exact.temperature;
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(near(one.local.mean[a], exact.mean[a], std::sqrt(T))) << a;
    EXPECT_EQ(one.cell_mean_velocity[a], one.local.mean[a]);
    for (int b = 0; b < 3; ++b) EXPECT_TRUE(near(one.local.second[a][b], exact.second[a][b], T)) << a << b;
  }
  EXPECT_TRUE(near(one.local.temperature, T, T));
  EXPECT_TRUE(near(one.local.fourth, exact.fourth, exact.fourth));
  EXPECT_TRUE(near(one.local.sixth, exact.sixth, exact.sixth));
  EXPECT_TRUE(near(one.kinetic_energy, two.kinetic_energy, two.kinetic_energy));
  const double moved[3] = {exact.mean[0] + 1e-3 * std::sqrt(T), exact.mean[1], exact.mean[2]};
  grid.sampled_moments(span, 1e-3, off, nullptr, moved);
  EXPECT_EQ(off.local.fourth, two.local.fourth);
  EXPECT_EQ(off.local.temperature, two.local.temperature);
  EXPECT_EQ(off.kinetic_energy, two.kinetic_energy);
}

// The sampled moments of a slab with only some MomentsPart asked for: those asked for have the bits
// of the full measurement (the same passes in the same order), the others are NaN (the cell means'
// pointer null), so that a diagnostic that reads a part it did not declare shows it.
TEST(CellGrid, SampledMomentsKeepThePartsAskedForToTheBitAndLeaveTheOthersNaN) {
  Slab s(10000, 5);
  s.grid.assign_and_sort(s.y.data(), s.cell.data(), s.y.size());
  SampledMoments all, energy, means, none;
  s.grid.sampled_moments(s.span, 1e-3, all);
  ASSERT_NE(all.cell_mean_velocity, nullptr);
  const std::vector<double> cell_means(all.cell_mean_velocity, all.cell_mean_velocity + 3 * s.grid.count());
  s.grid.sampled_moments(s.span, 1e-3, energy, nullptr, nullptr, moments_energy);
  s.grid.sampled_moments(s.span, 1e-3, means, nullptr, nullptr, moments_means);
  s.grid.sampled_moments(s.span, 1e-3, none, nullptr, nullptr, 0);
  ASSERT_TRUE(std::isfinite(all.local.temperature) && std::isfinite(all.local.sixth));
  EXPECT_EQ(energy.kinetic_energy, all.kinetic_energy);
  EXPECT_EQ(energy.cell_mean_velocity, nullptr);
  for (const SampledMoments* m : {&energy, &means, &none}) {
    EXPECT_EQ(m->local.count, 10000u);
    EXPECT_EQ(m->number_density, 1e-3);
    EXPECT_TRUE(std::isnan(m->local.temperature) && std::isnan(m->local.fourth) && std::isnan(m->local.sixth));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_TRUE(std::isnan(m->local.second[a][b]));
  }
  EXPECT_TRUE(std::isnan(means.kinetic_energy) && std::isnan(none.kinetic_energy));
  EXPECT_TRUE(std::isnan(energy.local.mean[0]) && std::isnan(none.local.mean[2]));
  ASSERT_NE(means.cell_mean_velocity, nullptr);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(means.local.mean[a], all.local.mean[a]);
  for (std::size_t k = 0; k < cell_means.size(); ++k) EXPECT_EQ(means.cell_mean_velocity[k], cell_means[k]) << k;
}

}  // namespace
