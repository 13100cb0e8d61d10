// inelastic_hard_spheres in a mixture (SDK 6.5), at the SDK level: the rule begun on a hand-built
// two-species SystemInfo and called through its pair kernel with given impact directions. The
// binary collision of Garzo & Dufty, PRE 60, 5706 (1999), Eq. (2): total momentum m_a v1 + m_b v2
// conserved to round-off, the normal relative velocity reversed and scaled by alpha_ab, the energy
// loss mu_ab/2 (1 - alpha_ab^2)(g.s)^2 (mu_ab = m_a m_b/(m_a+m_b)) declared and measured, the
// per-species tallies; equal unit masses give the one-species rule to the bit; and the refusals of
// restitution_pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gdsmc/collision.hpp>

#include "config/errors.hpp"
#include "config/system_info.hpp"
#include "engine/particle_store.hpp"
#include "engine/streams.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::string pipeline_yaml(const std::string& collision) {
  return "run: {seed: 3, particles: 100, time_step: {value: 0.02, unit: tau0}, stop: {collisions_per_particle: 1}}\n"
         "system: {density: 1.0e-3, temperature: 1}\ninitial_state: maxwellian\n"
         "collision: " + collision + "\ndiagnostics: [temperature]\noutput: {file: unused.h5}\n";
}

// The rule built through the host's validation, begun on `species` (none: one species).
struct Rule {
  host::Pipeline pipeline;
  std::shared_ptr<PluginObject> object;
  QuantityBoard board;
  SystemInfo sys;
  CollisionRule& rule() const { return *static_cast<CollisionRule*>(object.get()); }
  Rule(const t::TempDir& dir, const std::string& collision, const std::vector<SpeciesInfo>& species) {
    pipeline = t::load_yaml(dir, pipeline_yaml(collision));
    object = host::create_object(*pipeline.collision.plugin, pipeline.collision.params);
    object->publish(board);
    sys = host::system_info(pipeline, 100, 0);
    if (!species.empty()) {
      sys.species = species.data();
      sys.species_count = species.size();
    }
    rule().begin(sys, board);
  }
};

const std::vector<SpeciesInfo> kMixture = {{"light", 1.0, 1.0, 0.5}, {"heavy", 3.7, 2.0, 0.5}};

// Particles 2q and 2q+1 collide with the impact direction dir[q]; species[k] of particle k.
struct Pairs {
  host::ParticleStore store;
  std::vector<std::uint32_t> species, is, js;
  std::vector<Vec3> v1, v2, dir;
  std::vector<double> u, tally;
  std::vector<std::uint8_t> accepted;
  ParticleSpan span;
  explicit Pairs(std::size_t pairs) : species(2 * pairs), is(pairs), js(pairs), v1(pairs), v2(pairs), dir(pairs),
                                      u(pairs), accepted(pairs) {
    store.allocate(2 * pairs, {});
    span = store.span();
    span.species = species.data();
    for (std::uint32_t q = 0; q < pairs; ++q) is[q] = 2 * q, js[q] = 2 * q + 1;
  }
  // Random pairs of species (a, b) cycling over the four ordered pairs, g.s > 0.
  void fill(Rng& rng, std::uint32_t species_count) {
    for (std::size_t q = 0; q < is.size(); ++q) {
      species[is[q]] = static_cast<std::uint32_t>(q % species_count);
      species[js[q]] = static_cast<std::uint32_t>((q / species_count) % species_count);
      v1[q] = {rng.normal(), rng.normal(), rng.normal()};
      v2[q] = {rng.normal(), rng.normal(), rng.normal()};
      dir[q] = rng.unit_vector();
      if (dot(v1[q] - v2[q], dir[q]) < 0) dir[q] = -1.0 * dir[q];
    }
  }
  double collide(const CollisionRule& rule, Rng& rng, double sigma = 1) {
    tally.assign(rule.tallies().size(), 0.0);
    PairBatch b;
    b.count = static_cast<std::uint32_t>(is.size());
    b.i = is.data();
    b.j = js.data();
    b.v1 = v1.data();
    b.v2 = v2.data();
    b.u = u.data();
    b.direction = dir.data();
    b.accepted = accepted.data();
    b.sigma = sigma;
    b.particles = &span;
    b.rng = &rng;
    b.tally = tally.empty() ? nullptr : tally.data();
    rule.collide_batch(b);
    EXPECT_EQ(b.collided, is.size());
    return b.energy_change;
  }
};

TEST(InelasticMixture, PublishesPairRestitutionsAndSpeciesTallies) {
  t::TempDir dir;
  const Rule one(dir, "{plugin: inelastic_hard_spheres, alpha: 0.8}", {});
  EXPECT_EQ(one.board.all().size(), 1u);  // "restitution" only: the one-species output is unchanged
  EXPECT_EQ(*one.board.find("restitution"), 0.8);
  EXPECT_TRUE(one.rule().tallies().empty());
  EXPECT_NE(one.rule().extension(species_id), nullptr);

  const Rule mix(dir, "{plugin: inelastic_hard_spheres, alpha: 0.8, restitution_pairs: 'heavy - light: 0.6, heavy-heavy: 0.9'}",
                 kMixture);
  EXPECT_EQ(*mix.board.find("restitution"), 0.8);
  EXPECT_EQ(*mix.board.find("restitution[0,0]"), 0.8);
  EXPECT_EQ(*mix.board.find("restitution[0,1]"), 0.6);
  EXPECT_EQ(*mix.board.find("restitution[1,1]"), 0.9);
  EXPECT_EQ(mix.board.find("restitution[1,0]"), nullptr);
  EXPECT_EQ(mix.rule().tallies(),
            (std::vector<std::string>{"species_energy_change[light]", "species_energy_change[heavy]"}));
}

// 4000 random pairs, a thousand of each ordered pair of species: every conservation law to
// round-off (16 eps of the magnitudes involved: a handful of roundings per component).
TEST(InelasticMixture, ConservesMomentumAndLosesTheEnergyOfGarzoDufty) {
  t::TempDir dir;
  const Rule mix(dir, "{plugin: inelastic_hard_spheres, alpha: 0.8, restitution_pairs: 'light-heavy: 0.6, heavy-heavy: 0.9'}",
                 kMixture);
  const double alpha[2][2] = {{0.8, 0.6}, {0.6, 0.9}};
  Pairs p(4000);
  Rng rng = host::StreamFactory::standalone(5, 0);
  p.fill(rng, 2);
  const std::vector<Vec3> w1 = p.v1, w2 = p.v2;  // before
  const double declared = p.collide(mix.rule(), rng, 1.5);
  double expected_total = 0, measured[2] = {0, 0};
  for (std::size_t q = 0; q < p.is.size(); ++q) {
    const std::uint32_t a = p.species[p.is[q]], b = p.species[p.js[q]];
    const double ma = kMixture[a].mass, mb = kMixture[b].mass, e = alpha[a][b];
    const Vec3 dp = (ma * p.v1[q] + mb * p.v2[q]) - (ma * w1[q] + mb * w2[q]);
    const double scale = ma * (norm(w1[q]) + norm(p.v1[q])) + mb * (norm(w2[q]) + norm(p.v2[q]));
    ASSERT_LE(norm(dp), 16 * kEps * scale) << "pair " << q << " species " << a << "," << b;
    const double gs = dot(w1[q] - w2[q], p.dir[q]), gs_after = dot(p.v1[q] - p.v2[q], p.dir[q]);
    ASSERT_NEAR(gs_after, -e * gs, 16 * kEps * (std::fabs(gs) + norm(w1[q]) + norm(w2[q])));  // restitution law
    const double mu = ma * mb / (ma + mb), loss = 0.5 * mu * (1 - e * e) * gs * gs;
    const double d1 = 0.5 * ma * (dot(p.v1[q], p.v1[q]) - dot(w1[q], w1[q]));
    const double d2 = 0.5 * mb * (dot(p.v2[q], p.v2[q]) - dot(w2[q], w2[q]));
    const double energy_scale = ma * dot(w1[q], w1[q]) + mb * dot(w2[q], w2[q]);
    ASSERT_NEAR(d1 + d2, -loss, 16 * kEps * energy_scale) << "pair " << q;
    measured[a] += d1;
    measured[b] += d2;
    expected_total -= loss;
  }
  EXPECT_NEAR(declared, expected_total, 1e-12 * std::fabs(expected_total));
  ASSERT_EQ(p.tally.size(), 2u);
  // The tallies: the energy each species received (computed without the difference of squares).
  for (int s = 0; s < 2; ++s) EXPECT_NEAR(p.tally[s], measured[s], 1e-12 * std::fabs(expected_total)) << s;
  EXPECT_NEAR(p.tally[0] + p.tally[1], declared, 1e-12 * std::fabs(expected_total));
  EXPECT_LT(declared, 0);
}

// Two species of unit mass and alpha everywhere: the velocities and the declared energy of the
// one-species rule, to the bit. Two species of mass 2: the same velocities, twice the energy.
TEST(InelasticMixture, EqualMassesGiveTheOneSpeciesRuleBitForBit) {
  t::TempDir dir;
  const std::string entry = "{plugin: inelastic_hard_spheres, alpha: 0.73}";
  const Rule one(dir, entry, {});
  const std::vector<SpeciesInfo> unit = {{"a", 1.0, 1.0, 0.5}, {"b", 1.0, 2.0, 0.5}};
  const std::vector<SpeciesInfo> double_mass = {{"a", 2.0, 1.0, 0.5}, {"b", 2.0, 2.0, 0.5}};
  const Rule mix(dir, entry, unit), heavy(dir, entry, double_mass);
  Pairs p(1000), m(1000), h(1000);
  Rng draw = host::StreamFactory::standalone(9, 0);
  p.fill(draw, 1);
  m.fill(draw, 2);
  m.v1 = p.v1, m.v2 = p.v2, m.dir = p.dir;
  h.species = m.species, h.v1 = p.v1, h.v2 = p.v2, h.dir = p.dir;
  Rng r1 = host::StreamFactory::standalone(1, 0), r2 = r1, r3 = r1;
  const double e_one = p.collide(one.rule(), r1), e_mix = m.collide(mix.rule(), r2), e_heavy = h.collide(heavy.rule(), r3);
  EXPECT_EQ(std::memcmp(p.v1.data(), m.v1.data(), p.v1.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(p.v2.data(), m.v2.data(), p.v2.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(p.v1.data(), h.v1.data(), p.v1.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(p.v2.data(), h.v2.data(), p.v2.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(e_mix, e_one);  // the same sum of the same terms
  EXPECT_EQ(e_heavy, 2 * e_one);
  EXPECT_LT(e_one, 0);
}

std::string refusal(const std::string& pairs, const std::vector<SpeciesInfo>& species) {
  t::TempDir dir;
  try {
    const Rule r(dir, "{plugin: inelastic_hard_spheres, alpha: 0.8, restitution_pairs: '" + pairs + "'}", species);
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.parameter(), "restitution_pairs");
    return e.what();
  } catch (const host::PipelineError& e) {
    std::string all;
    for (const auto& m : e.messages()) all += m + "\n";
    return all;
  }
  return "";
}

TEST(InelasticMixture, RestitutionPairsRefusesWhatItCannotUse) {
  struct Case {
    std::string pairs;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"light-heavy 0.8", {"has no ':'", "light-heavy: 0.8"}},
      {"light-heavy: high", {"'high'", "not a number"}},
      {"light-heavy: 1.2", {"outside [0, 1]"}},
      {"light-heavy: -0.1", {"outside [0, 1]"}},
      {"light-heavy: 0.8,, heavy-heavy: 0.7", {"empty entry"}},
      {"light-medium: 0.8", {"'light-medium'", "the species are: light, heavy"}},
      {"light: 0.8", {"the species are: light, heavy"}},
      {"light-heavy: 0.8, heavy-light: 0.7", {"heavy-light", "given twice"}},
      {"heavy-heavy: 0.8, heavy-heavy: 0.7", {"heavy-heavy", "given twice"}},
  };
  for (const auto& c : cases) {
    const std::string text = refusal(c.pairs, kMixture);
    ASSERT_FALSE(text.empty()) << "accepted: " << c.pairs;
    for (const auto& w : c.words) EXPECT_NE(text.find(w), std::string::npos) << "'" << w << "' not in: " << text;
  }
  // Names with a '-' of their own split where both sides are species.
  const std::vector<SpeciesInfo> dashed = {{"glass-bead", 1.0, 1.0, 0.5}, {"steel", 3.0, 1.0, 0.5}};
  EXPECT_EQ(refusal("glass-bead-steel: 0.5", dashed), "");
  // A one-species system has no species to name.
  const std::string one = refusal("light-heavy: 0.8", {});
  EXPECT_NE(one.find("single species"), std::string::npos) << one;
}

}  // namespace
