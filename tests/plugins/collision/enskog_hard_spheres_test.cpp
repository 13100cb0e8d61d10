// Enskog collisions and the modified shear flow of paper 002: conservation, the collisional
// transfer tensor, the chi-times-Boltzmann collision rate, the temperature equation (Eq. 4 with
// gamma = zeta), the phi -> 0 limit, and refused inputs. Small N, short runs; every tolerance is
// argued next to its check.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "config/system_info.hpp"
#include "engine/collision_stage.hpp"
#include "engine/streams.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

double carnahan_starling(double phi) { return (1 - phi / 2) / std::pow(1 - phi, 3); }
// n sigma^3 for a packing fraction (sigma = 1).
double density_of(double phi) { return 6.0 * phi / M_PI; }

// A homogeneous Enskog pipeline at (alpha, phi) with a tau0 = shear (no uniform_shear if < 0).
std::string enskog_yaml(double alpha, double phi, double shear, int particles, double stop_s, const std::string& forcings_extra,
                        const std::string& diagnostics, const std::string& collision = "") {
  std::string forcings = "forcings:\n";
  if (shear >= 0) forcings += "  - {plugin: uniform_shear, shear_rate: " + std::to_string(shear) + "}\n";
  forcings += forcings_extra;
  if (forcings == "forcings:\n") forcings = "forcings: []\n";
  const std::string coll = collision.empty() ? "{plugin: enskog_hard_spheres, alpha: " + std::to_string(alpha) +
                                                   (shear >= 0 ? "" : ", sheared: false") + "}"
                                             : collision;
  return "run:\n  seed: 7\n  particles: " + std::to_string(particles) +
         "\n  time_step: {value: 0.002, unit: tau0, follow_temperature: true}\n"
         "  stop: {collisions_per_particle: " + std::to_string(stop_s) + "}\n"
         "  sample_every: 1\n  record_every: 10\n  average_after: {collisions_per_particle: 0}\n"
         "system: {density: " + std::to_string(density_of(phi)) + ", sigma: 1, temperature: 1.0, domain: homogeneous}\n"
         "initial_state: maxwellian\n"
         "collision: " + coll + "\n" + forcings + "diagnostics:\n" + diagnostics + "output: {file: unused.h5}\n";
}

// The rule as the engine holds it, for direct use of the collision stage.
struct RuleBench {
  host::Pipeline pipeline;
  std::shared_ptr<PluginObject> object;
  CollisionRule* rule = nullptr;
  QuantityBoard board;
  SystemInfo sys;
  RuleBench(const t::TempDir& dir, double alpha, double phi, double a) {
    pipeline = t::load_yaml(dir, enskog_yaml(alpha, phi, a, 1000, 1, "", "  - temperature\n"));
    object = host::create_object(*pipeline.collision.plugin, pipeline.collision.params);
    rule = static_cast<CollisionRule*>(object.get());
    rule->publish(board);
    board.publish("shear_rate", a);
    sys = host::system_info(pipeline, 1000, 0);
    rule->begin(sys, board);
  }
};

// Collisions conserve momentum to round-off; the collisional transfer tensor (Eq. 5) is symmetric
// to round-off (each collision adds sigma s_i dp_j with dp parallel to s), has positive normal
// components, and a negative xy component under a positive shear (eta^c > 0).
TEST(enskog, CollisionsConserveMomentumAndTransferTensorIsSymmetric) {
  t::TempDir dir;
  const double phi = 0.3, a = 0.1 * carnahan_starling(phi) / 1.0;  // Kn = 0.1 at T0 (a tau0 = chi Kn)
  RuleBench b(dir, 0.8, phi, a);
  const std::vector<std::string> names = b.rule->tallies();
  ASSERT_EQ(names.size(), 10u);
  EXPECT_EQ(names[1], "collisional_transfer_xy");
  EXPECT_EQ(names[9], "dissipated_energy");
  EXPECT_NEAR(*b.board.find("contact_value"), carnahan_starling(M_PI / 6 * b.sys.number_density), 1e-12);
  const std::size_t n = 4000;
  host::ParticleStore store;
  store.allocate(n, {});
  const ParticleSpan p = store.span();
  Rng init = host::StreamFactory::standalone(3, 0);
  for (std::size_t i = 0; i < n; ++i) p.set_velocity(i, {init.normal(), init.normal(), init.normal()});
  b.rule->bind(p);
  host::CellGrid grid;
  grid.homogeneous(n, b.sys.volume);
  grid.assign_and_sort(p.y.data, store.cells(), n);
  host::CollisionStage stage;
  stage.reset(1);
  stage.set_tally_count(names.size());
  host::StreamFactory streams(5, 0);
  auto momentum = [&](double m[3]) {
    t::ExactishSum s[3];
    for (std::size_t i = 0; i < n; ++i) {
      s[0].add(p.vx[i]);
      s[1].add(p.vy[i]);
      s[2].add(p.vz[i]);
    }
    for (int k = 0; k < 3; ++k) m[k] = s[k].value();
  };
  double before[3], after[3];
  momentum(before);
  std::vector<double> tally(names.size(), 0.0);
  std::uint64_t accepted = 0;
  for (int step = 0; step < 200; ++step) {
    streams.set_step(step);
    const auto totals = stage.run(*b.rule, p, grid, nullptr, 1.0, 1.0, b.sys.sigma, 0.01 * b.sys.time_unit0, streams);
    for (std::size_t k = 0; k < names.size(); ++k) tally[k] += totals.tallies[k];
    accepted += totals.accepted;
    EXPECT_EQ(totals.majorant_exceeded, 0u) << "step " << step;
  }
  momentum(after);
  ASSERT_GT(accepted, 10000u);
  // Round-off: ~accepted additions of velocity changes of order 1, eps ~ 1e-16 each.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(after[k], before[k], 1e-9) << "component " << k;
  EXPECT_NEAR(tally[1], tally[3], 1e-12 * std::fabs(tally[1]) + 1e-12);  // xy = yx
  EXPECT_NEAR(tally[2], tally[6], 1e-12 * (std::fabs(tally[0]) + 1));    // xz = zx
  EXPECT_NEAR(tally[5], tally[7], 1e-12 * (std::fabs(tally[0]) + 1));    // yz = zy
  for (int d : {0, 4, 8}) EXPECT_GT(tally[d], 0);
  // The shear makes P^c_xy negative by many standard errors: each collision adds
  // sigma dp s_x s_y, whose mean is -O(a sigma) times the diagonal's 1/3; with >1e4
  // collisions the sign cannot come from noise (|xy|/xx ~ 0.1 against a noise ~ 1e-2).
  EXPECT_LT(tally[1], -0.02 * tally[0]);
  EXPECT_GT(tally[9], 0);
}

// At alpha = 1 without shear the Enskog gas stays Maxwellian and collides chi times as often as the
// Boltzmann gas: in a Maxwellian at T0, s(t) = chi t / (sqrt(pi) tau0) (the Boltzmann clock of
// 000 Sec. IV.B times chi).
TEST(enskog, ElasticUnshearedGasKeepsMaxwellianAtChiTimesBoltzmannRate) {
  t::TempDir dir;
  const double phi = 0.3, chi = carnahan_starling(phi);
  const int n = 4000;
  host::Pipeline p = t::load_yaml(dir, enskog_yaml(1.0, phi, -1, n, 8, "", "  - temperature\n  - cumulants\n"));
  host::Engine e(p);
  e.run();
  const double s = e.context().collisions_per_particle();
  const double t_tau0 = e.context().time_in_tau0();
  const double expected = chi * t_tau0 / std::sqrt(M_PI);
  // The accepted count K = s N is a sum of nearly independent events: relative error 1/sqrt(K).
  const double K = s * n;
  EXPECT_NEAR(s / expected, 1.0, 4.0 / std::sqrt(K)) << "s = " << s << " at t = " << t_tau0 << " tau0";
  // Elastic: the temperature stays T0 to round-off.
  EXPECT_NEAR(t::series(e, "temperature", "temperature").back(), 1.0, 1e-9);
  // a2 of the final state: the standard error of <V^4>/15T^2 - 1 for a Maxwellian sample of n
  // particles is sqrt((945 - 225)/225 / n) = 1.79 / sqrt(n) = 0.028.
  const auto& a2 = t::series(e, "cumulants", "a2");
  EXPECT_NEAR(a2.back(), 0.0, 4 * 1.79 / std::sqrt(static_cast<double>(n)));
}

// Modified USF (Eq. 15): anti_drag gives back exactly the energy the collisions dissipated, the
// replacement adds nothing on average, so dT/dt = -(2/3n) a P_xy (Eq. 4 with gamma = zeta), with P_xy
// the total (kinetic + collisional) shear stress the diagnostic measures.
TEST(enskog, AntiDragAndReplacementKeepTheViscousHeatingEquation) {
  t::TempDir dir;
  const double alpha = 0.8, phi = 0.2, chi = carnahan_starling(phi);
  const int n = 3000;
  host::Pipeline p = t::load_yaml(dir, enskog_yaml(alpha, phi, 0.1 * chi, n, 30,
                                                   "  - anti_drag\n  - {plugin: hcs_replacement, reservoir_particles: 5000}\n",
                                                   "  - enskog_shear_viscosity\n"));
  host::Engine e(p);
  e.run();
  const StepContext& ctx = e.context();
  double anti_drag = 0, replacement = 0;
  for (std::size_t k = 0; k < ctx.energy_ledger_size; ++k) {
    if (std::string(ctx.energy_ledger[k].stage) == "anti_drag") anti_drag = ctx.energy_ledger[k].energy;
    if (std::string(ctx.energy_ledger[k].stage) == "hcs_replacement") replacement = ctx.energy_ledger[k].energy;
  }
  const double dissipated = *ctx.collision_tally("dissipated_energy");
  ASSERT_GT(dissipated, 0);
  EXPECT_NEAR(anti_drag, dissipated, 1e-9 * dissipated);  // gamma = zeta, step by step

  const auto& T = t::series(e, "enskog_shear_viscosity", "temperature");
  const auto& pxy = t::series(e, "enskog_shear_viscosity", "P_xy_over_nT");
  const auto& time = t::diagnostic(e, "enskog_shear_viscosity").time;  // tau0
  // Integrate dT/dt = -(2/3) a (P_xy/nT) T over the records (record 0 is the initial state; each
  // later record holds the interval's means), in tau0 units: a tau0 = 0.1 chi.
  const double a_tau0 = 0.1 * chi;
  double predicted = T.front();
  for (std::size_t k = 1; k < T.size(); ++k) predicted += -(2.0 / 3.0) * a_tau0 * pxy[k] * T[k] * (time[k] - time[k - 1]);
  const double measured = T.back();
  // Noise: the replacement exchanges energy with random sign; its ledger entry is that noise
  // realised (mean 0). Each replacement changes the energy by about sqrt(3) T (the difference of
  // two independent (1/2)V^2, variance 3T^2/2 each), and there are K = dissipated / (3 T-bar).
  const double t_mean = 0.5 * (T.front() + T.back());
  const double K = dissipated / (3.0 * t_mean);
  const double noise_T = std::sqrt(3.0 * K) * t_mean / (1.5 * n);  // in T0 units
  EXPECT_NEAR(replacement / (1.5 * n), 0.0, 4 * noise_T);
  // The rise is large against the noise (otherwise the check would be empty) ...
  ASSERT_GT(measured - T.front(), 10 * noise_T);
  // ... and agrees with the integral within the replacement noise plus 1% of the rise for the
  // interval means of a product (T and P_xy/nT averaged separately over 10 steps).
  EXPECT_NEAR(measured, predicted, 4 * noise_T + 0.01 * (measured - T.front()))
      << "T_end = " << measured << ", T0 + integral = " << predicted;
  // Without the anti-drag the gas would have lost `dissipated`: far more than the tolerance.
  EXPECT_GT(dissipated / (1.5 * n), 10 * (4 * noise_T + 0.01 * (measured - T.front())));
}

// phi -> 0: Enskog collisions become those of inelastic_hard_spheres (chi -> 1, a sigma -> 0 against
// the thermal speed). Checked statistically in sheared flow: T and -P_xy/nT at s = 15 of 4
// realizations each, compared by the z-score of the difference of the means.
TEST(enskog, VanishingPackingFractionIsInelasticHardSpheres) {
  t::TempDir dir;
  const double alpha = 0.9, phi = 1e-4, shear = 1.0;
  auto measure = [&](const std::string& collision) {
    std::vector<double> temperature, stress;
    host::Pipeline p = t::load_yaml(dir, enskog_yaml(alpha, phi, shear, 2000, 15, "", "  - shear_rheology\n", collision));
    for (std::uint32_t r = 0; r < 4; ++r) {
      host::Engine e(p, r);
      e.run();
      temperature.push_back(t::series(e, "shear_rheology", "temperature").back());
      const auto& s = t::series(e, "shear_rheology", "minus_Pxy_over_nT");
      double m = 0;
      for (std::size_t k = s.size() / 2; k < s.size(); ++k) m += s[k];
      stress.push_back(m / static_cast<double>(s.size() - s.size() / 2));
    }
    return std::make_pair(t::mean_error(temperature), t::mean_error(stress));
  };
  const auto enskog = measure("");
  const auto ihs = measure("{plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}");
  auto z = [](const t::MeanError& x, const t::MeanError& y) {
    return (x.mean - y.mean) / std::sqrt(x.standard_error * x.standard_error + y.standard_error * y.standard_error);
  };
  EXPECT_LT(std::fabs(z(enskog.first, ihs.first)), 4.0) << enskog.first.mean << " vs " << ihs.first.mean;
  EXPECT_LT(std::fabs(z(enskog.second, ihs.second)), 4.0) << enskog.second.mean << " vs " << ihs.second.mean;
  // And the shear did act: -P_xy/nT is far from 0 in both.
  EXPECT_GT(ihs.second.mean, 10 * ihs.second.standard_error);
}

// Refused inputs: a located message naming the plugin and the parameter, exit 1, nothing written.
TEST(enskog, BadInputIsRefusedWithALocatedMessage) {
  t::TempDir dir;
  struct Case {
    std::string yaml, words[2];
  };
  const std::vector<Case> cases = {
      {enskog_yaml(0.9, 0.2, -1, 100, 1, "", "  - temperature\n",
                   "{plugin: enskog_hard_spheres, alpha: 0.9}"),  // sheared (default) but no uniform_shear
       {"'sheared'", "uniform_shear"}},
      {enskog_yaml(0.9, 0.2, 0.1, 100, 1, "", "  - temperature\n", "{plugin: enskog_hard_spheres, contact_value: -2}"),
       {"contact_value", "must be > 0"}},
      {enskog_yaml(0.9, 0.2, 0.1, 100, 1, "", "  - temperature\n", "{plugin: enskog_hard_spheres, contact_value: lots}"),
       {"contact_value", "neither carnahan_starling nor a number"}},
      {enskog_yaml(0.9, 0.8, 0.1, 100, 1, "", "  - temperature\n"), {"packing fraction", "close packing"}},
      {enskog_yaml(0.9, 0.2, 0.1, 100, 1, "", "  - temperature\n",
                   "{plugin: enskog_hard_spheres, alpha: 0.9, sheared: false}"),
       {"'sheared'", "set sheared: true"}},
  };
  for (const auto& c : cases) {
    const std::filesystem::path file = dir.write("bad.yaml", c.yaml);
    for (const char* cmd : {"validate", "run"}) {
      const auto r = t::run_gdsmc({cmd, file.string(), "--plugin-path", t::plugin_dir().string()},
                                  dir.path());
      EXPECT_EQ(r.exit_code, 1) << cmd << "\n" << r.err;
      EXPECT_NE(r.err.find("enskog_hard_spheres"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
      for (const auto& w : c.words) EXPECT_NE(r.err.find(w), std::string::npos) << "missing '" << w << "' in\n" << r.err;
    }
    EXPECT_EQ(dir.files(), std::vector<std::string>{"bad.yaml"});
  }
}

}  // namespace
