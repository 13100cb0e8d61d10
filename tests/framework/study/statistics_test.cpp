// Honest error bars: the host's steady averages and their errors
// (batch means of one realization, the scatter of several), tau_int, and the seed check of every
// error against the scatter of independent realizations (framework/study/statistics.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gdsmc/physics/series.hpp>

#include "study/statistics.hpp"
#include "study/study.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {


double scalar_named(const host::DiagnosticOutput& d, const std::string& name) {
  for (const auto& s : d.scalars)
    if (s.name == name) return s.value;
  throw std::runtime_error("no scalar " + name);
}
const host::DiagnosticOutput::Scalar& scalar_item(const host::DiagnosticOutput& d, const std::string& name) {
  for (const auto& s : d.scalars)
    if (s.name == name) return s;
  throw std::runtime_error("no scalar " + name);
}

// An AR(1) series x_k = phi x_{k-1} + noise: integrated autocorrelation time (1 + phi)/(1 - phi).
std::vector<double> ar1(std::size_t n, double phi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double v = g(rng) / std::sqrt(1 - phi * phi);
  for (auto& xi : x) {
    v = phi * v + g(rng);
    xi = v;
  }
  return x;
}

host::DiagnosticOutput series_output(const std::vector<double>& x) {
  host::DiagnosticOutput d("g", nullptr);
  const auto id = d.series("x", "1", "test series");
  for (std::size_t k = 0; k < x.size(); ++k) {
    d.begin_record(0.1 * static_cast<double>(k), 0.1 * static_cast<double>(k));
    d.append(id, x[k]);
  }
  return d;
}

TEST(ErrorBars, IntegratedAutocorrelationTimeOfAnAr1Series) {
  for (double phi : {0.0, 0.5, 0.8}) {
    const double expected = (1 + phi) / (1 - phi);
    const double tau = host::integrated_autocorrelation_time(ar1(40000, phi, 7));
    EXPECT_NEAR(tau, expected, 0.1 * expected) << "phi " << phi;
  }
}

// One realization: batches of >= 5 tau_int records; too short a window gives NaN and says why.
TEST(ErrorBars, SingleRealizationBatchesAreLongerThanTheCorrelationTimeOrTheErrorIsNaN) {
  std::vector<host::DiagnosticOutput> longer{series_output(ar1(4000, 0.9, 3))};  // tau_int = 19 records
  host::add_steady_averages(longer, 0.0, std::nullopt);
  const auto& se = scalar_item(longer[0], "x.steady_stderr");
  EXPECT_TRUE(std::isfinite(se.value));
  EXPECT_NE(se.doc.find("integrated autocorrelation time"), std::string::npos) << se.doc;
  const host::BatchSpec spec = host::choose_batches(ar1(4000, 0.9, 3));
  EXPECT_GE(static_cast<double>(spec.length), 5 * spec.tau);
  EXPECT_GE(spec.batches, host::kMinBatches);
  // sigma / sqrt(n) * sqrt(tau_int) is the true standard error: the estimate within 40 %.
  const double truth = std::sqrt(1 / (1 - 0.81)) * std::sqrt(19.0 / 4000.0);
  EXPECT_NEAR(se.value, truth, 0.4 * truth);

  // 40 records of tau_int = 19: at most 2 batches of >= 5 measured tau_int (the measured tau_int of
  // a window this short is itself too small; the error is NaN all the same).
  std::vector<host::DiagnosticOutput> shorter{series_output(ar1(40, 0.9, 3))};
  host::add_steady_averages(shorter, 0.0, std::nullopt);
  const auto& nan = scalar_item(shorter[0], "x.steady_stderr");
  EXPECT_TRUE(std::isnan(nan.value));
  EXPECT_NE(nan.doc.find("NaN: the window holds only"), std::string::npos) << nan.doc;
  EXPECT_TRUE(std::isfinite(scalar_named(shorter[0], "x.steady_mean")));

  // A NaN error of a series the diagnostic declares stationary is printed with its reason and the
  // remedy; a finite one is not, nor one of a series not declared stationary.
  EXPECT_TRUE(host::nan_error_warnings(shorter).empty()) << "x is not declared stationary";
  longer[0].attributes["stationary"] = "y,x";
  shorter[0].attributes["stationary"] = "y,x";
  EXPECT_TRUE(host::nan_error_warnings(longer).empty());
  const std::vector<std::string> lines = host::nan_error_warnings(shorter);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("1 steady error is NaN"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("x.steady_stderr"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("fewer than 4 batches"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("run.realizations"), std::string::npos) << lines[0];
}

// Several realizations: the error is the scatter of the realizations' own time averages / sqrt(K),
// and the mean is unchanged (the time average of the realization average).
TEST(ErrorBars, SeveralRealizationsTakeTheSteadyErrorFromTheScatterOfTheirOwnMeans) {
  const std::size_t K = 5, n = 300;
  std::vector<std::vector<host::DiagnosticOutput>> runs;
  std::vector<double> own;
  for (std::size_t r = 0; r < K; ++r) {
    const auto x = ar1(n, 0.7, 100 + r);
    runs.push_back({series_output(x)});
    double m = 0;
    for (std::size_t k = 100; k < n; ++k) m += x[k];  // records with s >= 10: k >= 100
    own.push_back(m / static_cast<double>(n - 100));
  }
  auto avg = host::average_realizations(runs, nullptr);
  host::add_steady_averages(avg, 10.0, std::nullopt, runs);
  const MeanError expected = mean_error(own);
  EXPECT_NEAR(scalar_named(avg[0], "x.steady_mean"), expected.mean, 1e-12);
  EXPECT_NEAR(scalar_named(avg[0], "x.steady_stderr"), expected.standard_error, 1e-12);
  EXPECT_NE(scalar_item(avg[0], "x.steady_stderr").doc.find("K = 5 realizations"), std::string::npos);
}

// The seed check of an error: chi2/dof of K values about their mean against
// their own errors, and its central 95 % band, checked against chi2 tables and by hand.
TEST(ErrorBars, SeedCheckBandIsTheCentral95PercentOfChiSquaredPerDof) {
  // chi2 quantiles: 19 dof 8.9065 (2.5 %), 32.8523 (97.5 %); 4 dof 0.4844, 11.1433.
  const host::SeedBand b20 = host::seed_chi2_band(20);
  EXPECT_NEAR(b20.low, 8.9065 / 19, 1e-4);
  EXPECT_NEAR(b20.high, 32.8523 / 19, 1e-4);
  const host::SeedBand b5 = host::seed_chi2_band(5);
  EXPECT_NEAR(b5.low, 0.4844 / 4, 1e-4);
  EXPECT_NEAR(b5.high, 11.1433 / 4, 1e-4);
  EXPECT_TRUE(std::isnan(host::seed_chi2_band(1).low));
  // 1, 2, 3 with errors 1 about their mean 2: (1 + 0 + 1) / 2.
  EXPECT_DOUBLE_EQ(host::seed_chi2_per_dof({1, 2, 3}, {1, 1, 1}), 1.0);
  // Errors 1 and sqrt(7): pooled <e^2> = 4 about the mean 2, (1 + 1)/4; weighted, the mean
  // (1 + 3/7)/(1 + 1/7) = 1.25 and 0.25^2 + 1.75^2/7 = 0.5 (one dof).
  EXPECT_NEAR(host::seed_chi2_per_dof({1, 3}, {1, std::sqrt(7.0)}), 0.5, 1e-12);
  EXPECT_NEAR(host::seed_chi2_per_dof({1, 3}, {1, std::sqrt(7.0)}, true), 0.5, 1e-12);
  // An error that is not finite and positive makes the check NaN, never a silent pass.
  EXPECT_TRUE(std::isnan(host::seed_chi2_per_dof({1, 2, 3}, {1, std::nan(""), 1})));
  EXPECT_TRUE(std::isnan(host::seed_chi2_per_dof({1, 2, 3}, {1, 0, 1})));
}

// Every scalar error of a study with realizations gets its seed check, and the summary names the
// errors outside the band. 20 realizations of a value x ~ N(0, 1) that quotes x_error = 1 (honest),
// of y = x quoting y_error = 0.4 (understated: chi2/dof ~ 1/0.16 = 6.25, far above 1.73 for any
// draw), of z whose error is NaN in one realization (left out of z's check, which then runs over
// 19), and of w whose error is NaN in all but one (not checked, named as such). The draws are
// seeded, so the honest checks' places inside their bands are deterministic here.
TEST(ErrorBars, EveryScalarErrorOfSeveralRealizationsGetsItsSeedCheck) {
  const std::size_t K = 20;
  std::mt19937_64 rng(29);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<host::DiagnosticOutput>> runs;
  for (std::size_t r = 0; r < K; ++r) {
    host::DiagnosticOutput d("g", nullptr);
    const double x = g(rng);
    d.scalars.push_back({"x", "1", "value", x});
    d.scalars.push_back({"x_error", "1", "its honest error", 1.0});
    d.scalars.push_back({"y_mean", "1", "value", x});
    d.scalars.push_back({"y_standard_error", "1", "an understated error", 0.4});
    d.scalars.push_back({"z", "1", "value", x});
    d.scalars.push_back({"z_error", "1", "an error NaN in one realization", r == 7 ? std::nan("") : 1.0});
    d.scalars.push_back({"w", "1", "value", x});
    d.scalars.push_back({"w_error", "1", "an error NaN in all but one realization", r == 3 ? 1.0 : std::nan("")});
    runs.push_back({std::move(d)});
  }
  const auto avg = host::average_realizations(runs, nullptr);
  const host::SeedBand band = host::seed_chi2_band(K);
  const double x = scalar_named(avg[0], "x_error_seed_chi2_dof");
  EXPECT_GE(x, band.low);
  EXPECT_LE(x, band.high);
  EXPECT_NEAR(scalar_named(avg[0], "y_standard_error_seed_chi2_dof"), x / (0.4 * 0.4), 1e-12);
  // z: realization 7 left out, the check over the other 19 (18 dof), said in its description.
  const auto& z = scalar_item(avg[0], "z_error_seed_chi2_dof");
  EXPECT_GE(z.value, host::seed_chi2_band(19).low);
  EXPECT_LE(z.value, host::seed_chi2_band(19).high);
  EXPECT_NE(z.doc.find("19 of the 20 realizations"), std::string::npos) << z.doc;
  EXPECT_NE(z.doc.find("1 left out"), std::string::npos) << z.doc;
  EXPECT_TRUE(std::isnan(scalar_named(avg[0], "w_error_seed_chi2_dof")));
  EXPECT_TRUE(std::isfinite(scalar_named(avg[0], "x_error_seed_chi2_dof_weighted")));
  EXPECT_EQ(avg[0].attributes.at("seed_chi2_band_95"), "[0.469, 1.73] for 19 dof");
  const std::string& check = avg[0].attributes.at("seed_check");
  EXPECT_NE(check.find("2 of 3 inside"), std::string::npos) << check;
  EXPECT_NE(check.find("outside: y_mean"), std::string::npos) << check;
  EXPECT_NE(check.find("up to 1 realization(s) left out"), std::string::npos) << check;
  EXPECT_NE(check.find("not checked, fewer than 2 finite errors: w"), std::string::npos) << check;
  // No error pair, no check: the companions of the host (_stderr) are not errors of a plugin.
  EXPECT_THROW(scalar_named(avg[0], "x_error_stderr_seed_chi2_dof"), std::runtime_error);
}

// The host's steady errors of one realization get the same seed check when a study has several
// realizations: 40 realizations of an AR(1) series (tau_int = 5.7 records, 2000 records from s = 10:
// the batch-means error is calibrated there, ErrorBars.SteadyErrorsOfIndependentRealizations... below),
// declared stationary; a series the diagnostic does not declare stationary gets no check.
TEST(ErrorBars, TheHostsSteadyErrorsOfOneRealizationAreCheckedAgainstTheRealizationsScatter) {
  const std::size_t K = 40;
  std::vector<std::vector<host::DiagnosticOutput>> runs;
  for (std::size_t r = 0; r < K; ++r) {
    host::DiagnosticOutput d = series_output(ar1(2100, 0.7, 500 + r));
    d.attributes["stationary"] = "all";
    runs.push_back({std::move(d)});
  }
  auto avg = host::average_realizations(runs, nullptr);
  for (auto& run : runs) host::add_steady_averages(run, 10.0, std::nullopt);
  host::add_seed_checks(runs, 0, avg[0], host::SeedErrors::steady);
  const host::SeedBand band = host::seed_chi2_band(K);
  const double chi2 = scalar_named(avg[0], "x.steady_stderr_seed_chi2_dof");
  EXPECT_GE(chi2, band.low);
  EXPECT_LE(chi2, band.high);
  EXPECT_NE(avg[0].attributes.at("seed_check_steady").find("1 of 1 inside"), std::string::npos)
      << avg[0].attributes.at("seed_check_steady");
  // Not declared stationary: no check.
  auto undeclared = runs;
  for (auto& run : undeclared) run[0].attributes.erase("stationary");
  auto plain = host::average_realizations(undeclared, nullptr);
  host::add_seed_checks(undeclared, 0, plain[0], host::SeedErrors::steady);
  EXPECT_THROW(scalar_named(plain[0], "x.steady_stderr_seed_chi2_dof"), std::runtime_error);
  EXPECT_EQ(plain[0].attributes.count("seed_check_steady"), 0u);
}

// Many short independent realizations of an equilibrium gas (elastic hard spheres: a2 fluctuates
// about a fixed mean): each run's single-realization steady error, used as a z-score of its steady
// mean against the grand mean, must have unit variance. Tolerance: the chi^2 of the K z-scores in
// the central 99.9 % interval of chi^2 with K - 1 degrees of freedom (Wilson-Hilferty), its upper
// end widened by the Student-t variance of z-scores whose errors come from B batches; and the
// scatter of the means over the mean squared error in the plain interval. Seeds 5-11 gave z-score
// chi^2 = 112-181 and scatter chi^2 = 98-156 (mean 130 = 1.10 x 119) for 119 degrees of freedom.
// The errors of plain batch means (batch length not checked against the correlation time) are printed.
TEST(ErrorBars, SteadyErrorsOfIndependentRealizationsHaveUnitVarianceZScores) {
  TempDir dir;
  const char* yaml = R"(run:
  seed: 5
  particles: 60
  time_step: {value: 0.1, unit: tau0}
  stop: {collisions_per_particle: 300}
  sample_every: 1
  record_every: 4
  average_after: {collisions_per_particle: 5}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 1.0}
diagnostics: [cumulants]
)";
  const host::Pipeline p = load_yaml(dir, yaml, {});
  const int K = 120;
  std::vector<double> mean(K), se(K), se_before(K);
  std::size_t fewest_batches = SIZE_MAX;
  double t_inflation = 0;  // mean over the runs of the Student-t variance (B - 1)/(B - 3)
  for (int r = 0; r < K; ++r) {
    host::Engine e(p, static_cast<std::uint32_t>(r));
    e.run();
    auto d = e.diagnostics();
    host::add_steady_averages(d, 5.0, std::nullopt);
    mean[r] = scalar_named(d[0], "a2.steady_mean");
    se[r] = scalar_named(d[0], "a2.steady_stderr");
    ASSERT_TRUE(std::isfinite(se[r]) && se[r] > 0) << scalar_item(d[0], "a2.steady_stderr").doc;
    if (r == 0) std::printf("%s\n", scalar_item(d[0], "a2.steady_stderr").doc.c_str());
    // Plain batch means (BatchMeans: up to 64 batches, length not checked), for the record.
    BatchMeans before;
    std::vector<double> window;
    const auto& a2 = series(e, "cumulants", "a2");
    for (std::size_t k = 0; k < a2.size(); ++k)
      if (d[0].collisions_per_particle[k] >= 5.0 && std::isfinite(a2[k])) {
        before.add(a2[k]);
        window.push_back(a2[k]);
      }
    se_before[r] = before.standard_error();
    const double batches = static_cast<double>(host::choose_batches(window).batches);
    fewest_batches = std::min(fewest_batches, static_cast<std::size_t>(batches));
    t_inflation += (batches - 1) / (batches - 3) / K;
  }
  double grand = 0;
  for (double m : mean) grand += m;
  grand /= K;
  double chi2 = 0, chi2_before = 0, scatter = 0, mean_var = 0;
  for (int r = 0; r < K; ++r) {
    scatter += (mean[r] - grand) * (mean[r] - grand);
    mean_var += se[r] * se[r] / K;
  }
  const double chi2_pooled = scatter / mean_var;
  for (int r = 0; r < K; ++r) {
    chi2 += (mean[r] - grand) * (mean[r] - grand) / (se[r] * se[r]);
    chi2_before += (mean[r] - grand) * (mean[r] - grand) / (se_before[r] * se_before[r]);
  }
  const double nu = K - 1, z = 3.2905;  // two-sided 99.9 %
  auto quantile = [nu](double zp) { return nu * std::pow(1 - 2 / (9 * nu) + zp * std::sqrt(2 / (9 * nu)), 3); };
  // Each z-score divides by an error estimated from B batches: Student's t with B - 1 degrees of
  // freedom, variance (B - 1)/(B - 3); the mean of that over the runs widens the z-score interval.
  std::printf("steady a2 of %d independent runs (>= %zu batches each):\n"
              "  sum of squared z-scores chi^2 = %.1f for %.0f degrees of freedom (99.9%% interval [%.1f, %.1f],"
              " x %.3f for Student's t)\n"
              "  scatter of the means / mean squared error: chi^2 = %.1f (99.9%% interval [%.1f, %.1f])\n"
              "  with the plain batch-means error: chi^2 = %.1f\n",
              K, fewest_batches, chi2, nu, quantile(-z), quantile(z), t_inflation, chi2_pooled, quantile(-z), quantile(z),
              chi2_before);
  ASSERT_GE(fewest_batches, 8u) << "the test needs well-estimated errors";
  // The squared errors are unbiased estimates of the variance of a run's steady mean:
  EXPECT_GT(chi2_pooled, quantile(-z));
  EXPECT_LT(chi2_pooled, quantile(z));
  // and the z-scores have unit variance up to Student's t:
  EXPECT_GT(chi2, quantile(-z));
  EXPECT_LT(chi2, quantile(z) * t_inflation);
}

}  // namespace
}  // namespace gdsmc::test
