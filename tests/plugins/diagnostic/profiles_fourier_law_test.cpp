// profiles with fourier_law: true (plane Fourier flow): Fourier's law fitted to the steady T and q_y
// profiles of the central windows, beside the Chapman-Enskog conductivity 1.025218 kappa0(T_c)
// (001 Eq. 2.47). The diagnostic is fed constructed states whose every bin has an exactly known
// temperature and heat flux, so that kappa, its error and the theory have closed forms; it is
// refused for an inelastic gas; and a short elastic Fourier flow conducts as Chapman-Enskog says.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/cells.hpp"
#include "engine/particle_store.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc;
namespace t = gdsmc::test;

constexpr std::size_t kBins = 8;
constexpr std::size_t kPerBin = 9;  // particles per bin in a constructed state
const double kPi = std::acos(-1.0);

std::string pipeline_yaml(double alpha) {
  return "run:\n  seed: 5\n  particles: 72\n  time_step: {value: 0.05, unit: tau0}\n  stop: {time: 1}\n"
         "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 8}, layers: 8, bins: 8}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}\n"
         "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 0.9}\n  y_max: {plugin: diffuse_wall, temperature: 1.1}\n"
         "diagnostics:\n  - {plugin: profiles, fourier_law: true}\noutput: {file: unused.h5}\n";
}

// The diagnostic as the engine holds it, with its sink and the particles it is fed.
struct Bench : t::DiagnosticBench {
  host::ParticleStore store;
  host::CellGrid grid;  // the host's bin sums of each sample (SampledMoments::bin_sums)
  SampledMoments moments;
  StepContext ctx;
  double time = 0;
  Bench(const t::TempDir& dir, double alpha) : DiagnosticBench(dir, pipeline_yaml(alpha), "profiles", kBins * kPerBin) {
    board.publish("restitution", alpha);
    store.allocate(kBins * kPerBin, {});
    ctx.system = &sys;
    ctx.quantities = &board;
    grid.slab(kBins * kPerBin, sys.cells, sys.box[1], sys.cross_section());
    grid.set_sampling_system(&sys);
  }
  // One sample of the state whose bin b has T(b) = T[b] T0 and q_y(b) = q[b] n0 T0 sqrt(2T0/m), zero
  // flow and density n0: per bin the velocities (+-s, 0, 0), (0, +-s, 0), (0, 0, +-s), (0, 2w, 0) and
  // twice (0, -w, 0) (m = 1, T0 = 1), so that T = (6 s^2 + 6 w^2) / 27 and q_y = (1/2)(6 w^3) / V_bin
  // = w^3 n0 / 3 (n0 = 9 / V_bin).
  void sample(const std::vector<double>& T, const std::vector<double>& q, bool in_window) {
    const ParticleSpan p = store.span();
    std::size_t i = 0;
    for (std::size_t b = 0; b < kBins; ++b) {
      const double w = std::cbrt(3.0 * q[b] * std::sqrt(2.0)), s = std::sqrt(27.0 * T[b] / 6.0 - w * w);
      const double v[kPerBin][3] = {{s, 0, 0}, {-s, 0, 0}, {0, s, 0}, {0, -s, 0}, {0, 0, s},
                                    {0, 0, -s}, {0, 2 * w, 0}, {0, -w, 0}, {0, -w, 0}};
      for (const auto& vi : v) {
        p.y[i] = sys.bin_centre(b);
        p.set_velocity(i++, {vi[0], vi[1], vi[2]});
      }
    }
    ctx.in_average_window = in_window;
    grid.assign_and_sort(p.y.data, store.cells(), p.count);
    grid.sampled_moments(p, sys.number_density, moments, nullptr, nullptr, moments_bin_heat);
    ctx.moments = &moments;
    diag->sample(ctx, p);
  }
  void record() {
    out->begin_record(time, time);
    time += 1;
    diag->record(ctx, *out);
    out->check_record("profiles");
  }
};

}  // namespace

// T = 1 + g y + eps r, q_y = Q + delta d over 8 bins of one lambda0 (y = -3.5 .. 3.5 lambda0), with
// r = (1, -1, -1, 1, 1, -1, -1, 1) orthogonal to 1 and y and d = (1, -1, ...) of mean 0. Over all 8
// bins the line is then exactly T = 1 + g y, so kappa = -Q/g in sqrt(T0/m)/(pi sigma^2) (q in n0 T0
// sqrt(2T0/m), y in lambda0 = 1/(sqrt 2 pi n0 sigma^2)), i.e. -Q/(g (75/64) sqrt(pi)) in kappa0(T0),
// T_c = 1 and kappa_CE = 1.025218 kappa0(T0); Q is chosen so that kappa = kappa_CE. Its error:
// var g = s^2 / Syy with s^2 = 8 eps^2 / 6 and Syy = 42, and e_Q^2 = (8 delta^2 / 7) / 8. Only the
// samples in the steady window count: the record before it (a flat, hotter state with no flux) and
// the first sample of the record that straddles its start must leave no trace. The windows are the
// central 4, 6 and 8 bins (4, 6 and 8 lambda0).
TEST(ProfilesFourierLaw, ConductivityErrorAndTheoryOfAConstructedProfile) {
  t::TempDir dir;
  Bench b(dir, 1.0);
  b.diag->begin(b.sys, b.board, *b.out);
  const double g = 0.02, eps = 0.001, delta = 2e-4;
  const double kappa0 = 75.0 / 64.0 * std::sqrt(kPi), factor = 1.025218, Q = -g * factor * kappa0;
  const double r[kBins] = {1, -1, -1, 1, 1, -1, -1, 1};
  std::vector<double> T(kBins), q(kBins), hot(kBins, 1.5), none(kBins, 0.0);
  for (std::size_t k = 0; k < kBins; ++k) {
    const double y = b.sys.bin_centre(k) / b.sys.mean_free_path0;
    T[k] = 1.0 + g * y + eps * r[k];
    q[k] = Q + delta * (k % 2 ? -1.0 : 1.0);
  }
  b.sample(hot, none, false);  // a record wholly before the steady window
  b.sample(hot, none, false);
  b.record();
  b.sample(hot, none, false);  // a record that straddles its start
  b.sample(T, q, true);
  b.record();
  b.sample(T, q, true);  // a record inside it
  b.sample(T, q, true);
  b.record();
  b.diag->finish(b.ctx, *b.out);

  const auto& window = b.array("fourier_window");
  ASSERT_EQ(window.size(), 3u);
  EXPECT_NEAR(window[0], 4.0, 1e-12);
  EXPECT_NEAR(window[2], 8.0, 1e-12);
  const std::size_t all = 2;
  const double kappa = b.array("fourier_conductivity")[all], error = b.array("fourier_conductivity_error")[all];
  const double var_g = 8.0 * eps * eps / 6.0 / 42.0, var_Q = delta * delta / 7.0;
  const double expected_error = factor * std::sqrt(var_Q / (Q * Q) + var_g / (g * g));
  // Round-off only: the moments are sums of 9 terms per bin and sample.
  EXPECT_NEAR(kappa, factor, 1e-9);
  EXPECT_NEAR(error, expected_error, 1e-6 * expected_error);
  EXPECT_NEAR(b.array("fourier_centre_temperature")[all], 1.0, 1e-12);
  EXPECT_NEAR(b.array("theory_fourier_conductivity")[all], factor, 1e-9);
  EXPECT_NEAR(b.array("fourier_conductivity_over_chapman_enskog")[all], 1.0, 1e-9);
  EXPECT_NEAR(b.array("fourier_conductivity_over_chapman_enskog_error")[all], expected_error / factor, 1e-6 * expected_error);
  // The central 4 and 6 bins: r is orthogonal to y there too and d has mean 0, so kappa is the
  // same, but r's mean moves T_c to 1 + eps <r>: kappa / kappa_CE = 1 / sqrt(T_c).
  for (std::size_t w = 0; w < all; ++w) {
    const std::size_t n = 4 + 2 * w, first = (kBins - n) / 2;
    double mean_r = 0;
    for (std::size_t k = first; k < first + n; ++k) mean_r += r[k] / static_cast<double>(n);
    EXPECT_NEAR(b.array("fourier_conductivity")[w], factor, 1e-9) << n << " bins";
    EXPECT_NEAR(b.array("fourier_conductivity_over_chapman_enskog")[w], 1.0 / std::sqrt(1.0 + eps * mean_r), 1e-9) << n;
  }
  const auto tag = b.out->theory_tags.find("theory_fourier_conductivity");
  ASSERT_NE(tag, b.out->theory_tags.end());
  EXPECT_EQ(tag->second.measured, "fourier_conductivity");
  EXPECT_EQ(b.out->axes.at("fourier_conductivity_over_chapman_enskog"), "fourier_window");
}

// The theory beside kappa is that of dilute elastic hard spheres: an inelastic gas is refused,
// naming the parameter.
TEST(ProfilesFourierLaw, RefusesAnInelasticGas) {
  t::TempDir dir;
  Bench b(dir, 0.9);
  try {
    b.diag->begin(b.sys, b.board, *b.out);
    FAIL() << "an inelastic gas was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.parameter(), "fourier_law");
    EXPECT_NE(std::string(e.what()).find("restitution"), std::string::npos) << e.what();
  }
}

// Plane Fourier flow of elastic hard spheres (configs/fourier_elastic.yaml made short: N = 2e4, 40
// layers, dt = 0.1 tau0, 350 tau0 averaged from 150 tau0) in four seeds. The conductivity of the
// central 5 lambda0 over Chapman-Enskog's is 0.983 +- 0.006 in the long runs of
// docs/validation/sampling.md (the walls' Knudsen layers reach the centre at L = 10 lambda0); here
// each seed scatters by about 0.1 (the long runs' 0.014 at 10 times the particles, 2.25 times the
// window and half the layer width: 0.014 sqrt(22.5) = 0.07 and more; measured 1.006 +- 0.048 over
// the four seeds), so the mean of four is checked against 1 within 4 of its standard errors plus
// that 2 % bias. A wrong unit (sqrt 2, pi or 2 in kappa or lambda0) or a fit on the transient would
// be outside. The centre temperature is that of the walls' mean, 1 T0, within 0.02.
TEST(ProfilesFourierLaw, ElasticFourierFlowConductsAsChapmanEnskogSays) {
  t::TempDir dir;
  const std::string yaml = t::read_text(t::source_dir() / "configs" / "fourier_elastic.yaml");
  std::vector<double> ratio;
  for (int seed = 1; seed <= 4; ++seed) {
    host::Pipeline p = t::load_yaml(dir, yaml,
                                    {"run.seed=" + std::to_string(seed), "run.particles=20000", "system.layers=40",
                                     "run.time_step.value=0.1", "run.stop.time=350", "run.average_after.time=150",
                                     "run.sample_every=1", "run.record_every=100"});
    host::Engine e(p);
    e.run();
    const auto& d = t::diagnostic(e, "profiles");
    std::vector<double> window, r, centre;
    for (const auto& a : d.arrays) {
      if (a.name == "fourier_window") window = a.data;
      if (a.name == "fourier_conductivity_over_chapman_enskog") r = a.data;
      if (a.name == "fourier_centre_temperature") centre = a.data;
    }
    std::size_t five = window.size();
    for (std::size_t i = 0; i < window.size(); ++i)
      if (std::fabs(window[i] - 5.0) < 1e-9) five = i;
    ASSERT_LT(five, window.size()) << "no 5 lambda0 window";
    EXPECT_NEAR(centre.at(five), 1.0, 0.02) << "seed " << seed;
    ratio.push_back(r.at(five));
  }
  const t::MeanError m = t::mean_error(ratio);
  std::printf("  kappa/kappa_CE in the central 5 lambda0: %.4f +- %.4f over %zu seeds\n", m.mean, m.standard_error,
              ratio.size());
  EXPECT_NEAR(m.mean, 1.0, 4 * m.standard_error + 0.02);
  EXPECT_LT(m.standard_error, 0.08);  // the seeds' scatter is of the size argued above, not wild
}
