// Paper 001's homogeneous heat flow: the thermostat of Eq. 4.2, the HCS at fixed temperature with
// and without the cloning-annihilation term of Eq. 3.17, the elastic conductivity kappa'/kappa0 =
// 1.025218, b'_1 by Eqs. 3.10 and 3.12, and the linearity of q_x in eps*. Every tolerance is argued
// next to its check.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::test;

struct HeatFlow {
  double alpha = 1.0;
  int particles = 20000;
  int realizations = 1;
  double epsilon_star = 0.05;
  std::string route = "kappa_prime";
  bool cloning = false;
  double stop_tau0 = 10, average_after_tau0 = 4;
  std::string diagnostics = "[temperature, heat_flux]";
  std::uint64_t seed = 11;
  std::string sampling = "bracketed";  // run.sampling
};

std::string heat_flow_yaml(const HeatFlow& h) {
  std::string forcings = "forcings:\n  - {plugin: heat_flux_force, epsilon_star: " + std::to_string(h.epsilon_star) +
                         ", route: " + h.route + "}\n";
  if (h.cloning) forcings += "  - {plugin: cloning_annihilation, reservoir_particles: 5000, reservoir_relaxation: 20}\n";
  forcings += "  - energy_momentum_thermostat\n";
  return "run:\n  seed: " + std::to_string(h.seed) + "\n  particles: " + std::to_string(h.particles) +
         "\n  realizations: " + std::to_string(h.realizations) +
         "\n  time_step: {value: 0.003, unit: tau0}\n  stop: {time: {value: " + std::to_string(h.stop_tau0) +
         ", unit: tau0}}\n  sample_every: 5\n  record_every: 50\n  average_after: {time: " +
         std::to_string(h.average_after_tau0) + "}\n  sampling: " + h.sampling + "\n" +
         "system: {density: 1.0e-3, temperature: 1.0}\ninitial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(h.alpha) + "}\n" + forcings +
         "diagnostics: " + h.diagnostics + "\noutput: {file: out.h5, particles: true}\n";
}

// Runs the pipeline with the gdsmc executable and opens its output.
fs::path run_heat_flow(const TempDir& dir, const HeatFlow& h) {
  const auto yaml = dir.write("pipeline.yaml", heat_flow_yaml(h));
  const ProcessResult r = run_gdsmc({"run", yaml.string(), "--quiet"}, dir.path(), 600);
  if (r.exit_code != 0) throw std::runtime_error(r.describe());
  return dir / "out.h5";
}

struct Ran {
  TempDir dir;
  h5::File file;
  explicit Ran(const HeatFlow& h) : file(run_heat_flow(dir, h)) {}
  double steady(const std::string& series) const {
    return h5::read_scalar(file.id(), "/diagnostics/heat_flux/" + series + ".steady_mean");
  }
  double error(const std::string& series) const {
    return h5::read_scalar(file.id(), "/diagnostics/heat_flux/" + series + ".steady_stderr");
  }
};

// Eq. 4.2 after every step: total momentum zero and kinetic energy (3/2) N T0, to round-off. The
// output velocities are in units of v0 = sqrt(2 T0/m), so sum V^2 = (3/2) N. Round-off: a sum of
// N = 2e4 terms of O(1) carries ~ 1e-16 sqrt(N) relative error; 1e-12 leaves room for the
// rescaling's own rounding and still fails for any physical residue (a force step moves the mean
// by ~ eps dt ~ 1e-4).
TEST(HeatFlux, ThermostatRestoresMomentumAndEnergyToRoundOff) {
  HeatFlow h;
  h.alpha = 0.5;
  h.stop_tau0 = 1;
  h.average_after_tau0 = 0;
  h.diagnostics = "[temperature]";
  Ran run(h);
  const auto vx = h5::read_doubles(run.file.id(), "/particles/vx");
  const auto vy = h5::read_doubles(run.file.id(), "/particles/vy");
  const auto vz = h5::read_doubles(run.file.id(), "/particles/vz");
  double p[3] = {0, 0, 0}, v2 = 0;
  for (std::size_t i = 0; i < vx.size(); ++i) {
    p[0] += vx[i];
    p[1] += vy[i];
    p[2] += vz[i];
    v2 += vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
  }
  const double n = static_cast<double>(vx.size());
  for (double c : p) EXPECT_LT(std::abs(c) / n, 1e-12);
  EXPECT_NEAR(v2 / (1.5 * n), 1.0, 1e-12);
}

// With eps = 0 the force vanishes and the thermostat holds the homogeneous cooling state at fixed
// temperature: its cumulant a2 is the HCS one (first Sonine, Eq. 2.16: 0.0498 at alpha = 0.5; the
// DSMC value agrees within 0.01, the accuracy of the first-Sonine formula, as the HCS tests show).
// With the cloning-annihilation term on, f = f0 is a fixed point of (1/2) zeta (f - f0), so a2 must
// stay there too (a wrong annihilation rate -- e.g. uniform instead of f0/f -- keeps a2 only by
// accident; a rate with the wrong tail would move it). Error: 4 realizations, N = 2e4, t in [3, 10]
// tau0; tolerance max(3 standard errors, 0.01).
TEST(HeatFlux, WithoutFieldTheHcsIsHeldAtFixedTemperatureWithAndWithoutCloning) {
  for (bool cloning : {false, true}) {
    HeatFlow h;
    h.alpha = 0.5;
    h.epsilon_star = 0.0;
    h.cloning = cloning;
    h.route = cloning ? "kappa" : "kappa_prime";
    h.realizations = 4;
    h.stop_tau0 = 10;
    h.average_after_tau0 = 3;
    h.diagnostics = "[temperature, cumulants]";
    // The thermostat's exactness is a property of the state after the step; a bracketed sample
    // after the collisions sees T before the thermostat restores it (1 - zeta dt / 2 on average).
    h.sampling = "after_step";
    Ran run(h);
    const double a2 = h5::read_scalar(run.file.id(), "/diagnostics/cumulants/a2.steady_mean");
    const double err = h5::read_scalar(run.file.id(), "/diagnostics/cumulants/a2.steady_stderr");
    const double T = h5::read_scalar(run.file.id(), "/diagnostics/temperature/temperature.steady_mean");
    std::printf("eps* = 0, alpha = 0.5, cloning %s: a2 = %.4f +- %.4f (first Sonine %.4f), T/T0 = %.15f\n",
                cloning ? "on" : "off", a2, err, sonine_a2(0.5), T);
    EXPECT_NEAR(a2, sonine_a2(0.5), std::max(3 * err, 0.01)) << (cloning ? "with cloning" : "without cloning");
    EXPECT_LT(err, 0.01) << "not precise enough to test anything";
    EXPECT_NEAR(T, 1.0, 1e-12);
  }
}

// The paper's anchor: at alpha = 1, kappa' = kappa and kappa/kappa0 = 1.025218 (converged Sonine,
// 001 ref. 37). eps* = 0.05 (still linear: Fig. 1 and the linearity test below). The response
// rises over ~10 tau (Fig. 1: "a steady-state value ... is reached after about ten collisions per
// particle"; averaging from 4 tau gave 1.001 +- 0.008, 3 errors low), so the window is t in
// [10, 22] tau0. 8 realizations of N = 2e4: the error is that of the 8 realization means (Student t
// with 7 degrees of freedom: 3 errors is the 98.1 % two-sided quantile). The check that the error
// is below 0.04 keeps the test meaningful; it does not separate 1.025 from the first-Sonine 1 (the
// validation report does, at N = 2e5). Also b'_1 by Eq. 3.10 and by Eq. 3.12: the paper's Appendix
// proves them equal; they come from the same particles, so their difference fluctuates less than
// either, and 3 times the larger error is a conservative bound.
TEST(HeatFlux, ElasticConductivityIsTheConvergedSonineValueAndBothSonineRoutesAgree) {
  HeatFlow h;
  h.alpha = 1.0;
  h.particles = 20000;
  h.realizations = 8;
  h.stop_tau0 = 22;
  h.average_after_tau0 = 10;
  Ran run(h);
  const double k = run.steady("conductivity_over_kappa0"), ke = run.error("conductivity_over_kappa0");
  const double b_full = run.steady("b1_full"), b_marg = run.steady("b1_marginal");
  const double e_full = run.error("b1_full"), e_marg = run.error("b1_marginal");
  std::printf("alpha = 1: kappa'/kappa0 = %.4f +- %.4f (1.025218); b'1 = %.4f +- %.4f (Eq. 3.10), %.4f +- %.4f (3.12)\n",
              k, ke, b_full, e_full, b_marg, e_marg);
  EXPECT_NEAR(k, 1.025218, 3 * ke);
  EXPECT_LT(ke, 0.04);
  EXPECT_NEAR(b_full, b_marg, 3 * std::max(e_full, e_marg));
  EXPECT_NEAR(k, 16.0 / (15.0 * std::sqrt(M_PI)) * b_full, 1e-9) << "Eq. 2.45 with kappa0 of Eq. 2.47";
}

// q_x is linear in eps*: q_x(0.05) / q_x(0.025) = 2 (Fig. 1: "the heat flux q_x is practically
// linear in eps*"). alpha = 0.5, N = 5e4, 3 realizations each, t in [4, 12] tau0: the transient
// is linear in eps* too, so the ratio holds before the steady state; the ratio's error from the
// two standard errors; tolerance 3 of them.
TEST(HeatFlux, HeatFluxIsLinearInTheField) {
  double q[2], e[2];
  int k = 0;
  for (double eps : {0.025, 0.05}) {
    HeatFlow h;
    h.alpha = 0.5;
    h.particles = 50000;
    h.realizations = 3;
    h.epsilon_star = eps;
    h.stop_tau0 = 12;
    h.average_after_tau0 = 4;
    h.seed = 21 + static_cast<std::uint64_t>(k);
    Ran run(h);
    q[k] = run.steady("q_x");
    e[k] = run.error("q_x");
    ++k;
  }
  const double ratio = q[1] / q[0];
  const double ratio_error = std::abs(ratio) * std::hypot(e[0] / q[0], e[1] / q[1]);
  std::printf("alpha = 0.5: q_x = %.5g +- %.2g (eps* 0.025), %.5g +- %.2g (0.05); ratio %.3f +- %.3f\n", q[0], e[0], q[1],
              e[1], ratio, ratio_error);
  EXPECT_LT(q[0], 0.0) << "eps along +x mimics grad ln T along +x: the heat flows to -x (Eq. 3.9, kappa' > 0)";
  EXPECT_NEAR(ratio, 2.0, 3 * ratio_error);
  EXPECT_LT(ratio_error, 0.25);
}

}  // namespace
