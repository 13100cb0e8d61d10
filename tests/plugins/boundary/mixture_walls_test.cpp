// The boundaries in a two-species mixture (SDK 6.5): diffuse and Maxwell walls re-emit a particle
// with the wall Maxwellian of its own species (thermal scale sqrt(T_w,s/m_s), WallHit::species),
// at a species' own wall temperature and accommodation when given; specular, periodic and
// Lees-Edwards do not involve the mass and treat every species alike. Each wall is called directly
// with hand-made hits; tolerances are argued next to each check.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "plugins/two_species_span.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::test;

std::string slab_yaml(const std::string& walls) {
  return "run: {seed: 1, particles: 1000, time_step: {value: 0.01, unit: tau0}, stop: {collisions_per_particle: 1}}\n"
         "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}\n"
         "boundaries: " + walls + "\n"
         "diagnostics: [temperature]\noutput: {file: out.h5}\n";
}

struct Wall {
  TempDir dir;
  PluginFromPipeline made;
  TwoSpecies gas;
  StepContext ctx;
  // begin() is called apart, so that an error it throws is caught while the plugin's library is
  // still loaded (the exception object's code lives there).
  explicit Wall(const std::string& walls, bool begin_now = true)
      : made(dir, slab_yaml(walls), "boundaries.y_min", 1000), gas(made.sys, 500, 500, 4.0) {
    ctx.system = &gas.sys;
    if (begin_now) begin();
  }
  void begin() {
    QuantityBoard board;
    made.object->publish(board);
    boundary().begin(gas.sys, board, Vec3{0, 0, 0});
  }
  Boundary& boundary() { return made.as<Boundary>(); }
  // One hit of species s on y_min, arriving with velocity v; the hit's own boundary stream.
  WallHit hit(std::uint32_t s, std::uint64_t k, const Vec3& v, HitResult* result = nullptr) {
    WallHit h;
    h.id = k;
    h.side = -1;
    h.position = {0.5, -0.5 * gas.sys.box[1], 0.5};
    h.velocity = v;
    h.species = s;
    Rng rng = host::StreamFactory::standalone(11, k, StreamPurpose::boundary);
    const HitResult r = boundary().interact(ctx, h, rng);
    if (result) *result = r;
    return h;
  }
};

// Moments of K re-emitted velocities of one species.
struct Emitted {
  double vx2 = 0, vy2 = 0, vz2 = 0, diffuse = 0;
  std::size_t count = 0;
};
Emitted emit(Wall& w, std::uint32_t s, std::size_t K) {
  Emitted e;
  const Vec3 in{0.3, -0.7, 0.2};  // arriving at y_min (v_y < 0)
  for (std::size_t k = 0; k < K; ++k) {
    const WallHit h = w.hit(s, 1000000 * (s + 1) + k, in);
    EXPECT_GT(h.velocity.y, 0.0);  // into the gas
    const bool specular = h.velocity.x == in.x && h.velocity.z == in.z && h.velocity.y == -in.y;
    if (specular) continue;
    e.diffuse += 1;
    e.vx2 += h.velocity.x * h.velocity.x;
    e.vy2 += h.velocity.y * h.velocity.y;
    e.vz2 += h.velocity.z * h.velocity.z;
  }
  e.count = K;
  const double n = e.diffuse;
  e.vx2 /= n;
  e.vy2 /= n;
  e.vz2 /= n;
  e.diffuse /= static_cast<double>(K);
  return e;
}

// The diffuse flux of species s: v_y Rayleigh with <v_y^2> = 2 T_w,s/m_s (004 Eqs. 7, 9), v_x and
// v_z Gaussian with variance T_w,s/m_s (Eqs. 6, 8). With K = 2e5 emissions, m v_y^2 / 2T is
// exponential (relative standard error of the mean 1/sqrt(K) = 0.0022) and m v_x^2 / T a chi^2_1
// (sqrt(2/K) = 0.0032): 5 standard errors, 0.011 and 0.016. The heavy species at T_w,s = 1.5 and
// m = 4 has <v_y^2> = 0.75 against 2 for the light one: a wall using the reference mass (or T_w)
// for every species fails by far.
TEST(MixtureWalls, DiffuseWallReemitsEachSpeciesFromItsOwnWallMaxwellian) {
  Wall w("{y_min: {plugin: diffuse_wall, temperature: 1.0, species_temperature: \"heavy: 1.5\"}, y_max: diffuse_wall}");
  const std::size_t K = 200000;
  for (std::uint32_t s : {0u, 1u}) {
    const double m = w.gas.sys.species_mass(s), T = s == 0 ? 1.0 : 1.5;
    const Emitted e = emit(w, s, K);
    EXPECT_EQ(e.diffuse, 1.0);
    EXPECT_NEAR(e.vy2 / (2.0 * T / m), 1.0, 5.0 / std::sqrt(double(K)));
    EXPECT_NEAR(e.vx2 / (T / m), 1.0, 5.0 * std::sqrt(2.0 / double(K)));
    EXPECT_NEAR(e.vz2 / (T / m), 1.0, 5.0 * std::sqrt(2.0 / double(K)));
    std::printf("diffuse_wall, species %u (m = %g, T_w = %g): <vy^2> m/2T_w = %.4f, <vx^2> m/T_w = %.4f, <vz^2> m/T_w = %.4f\n",
                s, m, T, e.vy2 * m / (2 * T), e.vx2 * m / T, e.vz2 * m / T);
  }
}

// Maxwell's wall with alpha_heavy = 0.5 and alpha_light = 1: the heavy species is re-emitted
// diffusely in half of its hits (binomial standard error sqrt(0.25/K) = 0.0011 for K = 2e5; 5 of
// them 0.0056), the light one always; the diffuse part of the heavy flux has <v_y^2> = 2 T_w,s/m_s
// with the species' temperature (relative standard error 1/sqrt(K/2) = 0.0032; 5 of them 0.016).
TEST(MixtureWalls, MaxwellWallTakesEachSpeciesAccommodationAndTemperature) {
  Wall w("{y_min: {plugin: maxwell_wall, accommodation: 1.0, species_accommodation: \"heavy: 0.5\", "
         "species_temperature: \"heavy: 2.0\"}, y_max: diffuse_wall}");
  const std::size_t K = 200000;
  const Emitted light = emit(w, 0, K), heavy = emit(w, 1, K);
  EXPECT_EQ(light.diffuse, 1.0);
  EXPECT_NEAR(heavy.diffuse, 0.5, 5.0 * std::sqrt(0.25 / double(K)));
  EXPECT_NEAR(light.vy2 / 2.0, 1.0, 5.0 / std::sqrt(double(K)));
  EXPECT_NEAR(heavy.vy2 / (2.0 * 2.0 / 4.0), 1.0, 5.0 / std::sqrt(0.5 * double(K)));
  std::printf("maxwell_wall: heavy diffuse fraction %.4f (0.5), heavy <vy^2> m/2T_w = %.4f, light %.4f\n", heavy.diffuse,
              heavy.vy2 / (2.0 * 2.0 / 4.0), light.vy2 / 2.0);
}

// Specular, periodic and Lees-Edwards do not involve the mass: a hit gives the same result for
// either species, to the last bit, and they offer the extension gdsmc.species.
TEST(MixtureWalls, MassFreeBoundariesTreatEverySpeciesAlike) {
  for (const std::string walls : {"{y_min: specular_wall, y_max: specular_wall}", "{y: periodic}",
                                  "{y: {plugin: lees_edwards, shear_rate: 0.5}}", "{y_min: diffuse_wall, y_max: diffuse_wall}",
                                  "{y_min: {plugin: maxwell_wall, accommodation: 0.5}, y_max: diffuse_wall}"}) {
    Wall w(walls);
    EXPECT_NE(w.boundary().extension(species_id), nullptr) << walls;
    if (walls.find("diffuse") != std::string::npos) continue;
    for (std::uint64_t k = 0; k < 100; ++k) {
      const Vec3 in{0.1 * double(k % 7), -0.3 - 0.01 * double(k), 0.2};
      const WallHit a = w.hit(0, k, in), b = w.hit(1, k, in);
      EXPECT_EQ(a.velocity.x, b.velocity.x) << walls;
      EXPECT_EQ(a.velocity.y, b.velocity.y) << walls;
      EXPECT_EQ(a.velocity.z, b.velocity.z) << walls;
      EXPECT_EQ(a.position.x, b.position.x) << walls;
      EXPECT_EQ(a.position.y, b.position.y) << walls;
    }
  }
}

// Names are checked against the run's species when the wall begins; ranges when it is built.
TEST(MixtureWalls, UnknownSpeciesAndOutOfRangeValuesAreRefused) {
  for (const std::string wall : {"{plugin: diffuse_wall, species_temperature: \"medium: 2\"}",
                                 "{plugin: maxwell_wall, accommodation: 1, species_accommodation: \"medium: 0.5\"}"}) {
    Wall w("{y_min: " + wall + ", y_max: diffuse_wall}", false);
    try {
      w.begin();
      ADD_FAILURE() << wall << ": species 'medium' accepted";
    } catch (const ParameterError& e) {
      EXPECT_TRUE(contains(e.parameter(), "species_")) << e.parameter();
      EXPECT_TRUE(contains(e.what(), "'medium'")) << e.what();
      EXPECT_TRUE(contains(e.what(), "light, heavy")) << e.what();
    }
  }
  for (const std::string wall : {"{plugin: maxwell_wall, accommodation: 1, species_accommodation: \"heavy: 1.5\"}",
                                 "{plugin: diffuse_wall, species_temperature: \"heavy: -1\"}",
                                 "{plugin: diffuse_wall, species_temperature: \"heavy\"}"}) {
    bool refused = false;
    try {
      Wall w("{y_min: " + wall + ", y_max: diffuse_wall}");
    } catch (const std::exception& e) {
      refused = true;
      EXPECT_TRUE(contains(e.what(), "species_")) << e.what();
    }
    EXPECT_TRUE(refused) << wall;
  }
}

}  // namespace
