// Host pipeline features with no physics in them: realizations, sweeps, the steady-state stop and
// steady averages (framework/study.cpp, framework/engine.cpp).
#include <gtest/gtest.h>

#include <random>

#include <gdsmc/physics/series.hpp>

#include "output/hdf5_file.hpp"
#include "study/statistics.hpp"
#include "study/study.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {

const char* kHcs = R"(run:
  seed: 11
  particles: 600
  time_step: {value: 0.02, unit: tau0, follow_temperature: true}
  stop: {collisions_per_particle: 6}
  record_every: 5
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.8}
diagnostics: [temperature, cumulants]
)";

std::vector<host::DiagnosticOutput> run_one(const host::Pipeline& p, std::uint32_t realization) {
  host::Engine e(p, realization);
  e.run();
  return e.diagnostics();
}

const std::vector<double>& column(const std::vector<host::DiagnosticOutput>& d, const std::string& group,
                                  const std::string& name) {
  for (const auto& g : d)
    if (g.group() == group)
      for (const auto& c : g.columns)
        if (c.name == name) return c.values;
  throw std::runtime_error("no column " + group + "/" + name);
}

TEST(Study, RealizationsAreDistinctStreamsAveragedRecordByRecord) {
  TempDir dir;
  host::Pipeline p = load_yaml(dir, kHcs, {"run.realizations=4"});
  ASSERT_EQ(p.realizations, 4u);
  std::vector<std::vector<host::DiagnosticOutput>> runs;
  for (std::uint32_t r = 0; r < 4; ++r) runs.push_back(run_one(p, r));
  // Distinct streams: realizations differ.
  EXPECT_NE(column(runs[0], "temperature", "temperature"), column(runs[1], "temperature", "temperature"));
  // The same realization index reproduces bit for bit.
  EXPECT_EQ(column(runs[2], "cumulants", "a2"), column(run_one(p, 2), "cumulants", "a2"));

  const auto avg = host::average_realizations(runs, nullptr);
  const auto& mean = column(avg, "temperature", "temperature");
  const auto& se = column(avg, "temperature", "temperature_stderr");
  std::size_t records = runs[0][0].time.size();
  for (const auto& r : runs) records = std::min(records, r[0].time.size());
  ASSERT_EQ(mean.size(), records);
  for (std::size_t k = 0; k < records; ++k) {
    double m = 0;
    for (const auto& r : runs) m += column(r, "temperature", "temperature")[k];
    m /= 4;
    double v = 0;
    for (const auto& r : runs) v += std::pow(column(r, "temperature", "temperature")[k] - m, 2);
    // Same arithmetic up to summation order: a few ulps.
    EXPECT_NEAR(mean[k], m, 1e-14 * std::fabs(m)) << "record " << k;
    EXPECT_NEAR(se[k], std::sqrt(v / 3 / 4), 1e-12 * (std::fabs(m) + 1e-300)) << "record " << k;
  }
  // The initial state is T = T0 in every realization to round-off (exact_moments rescales it).
  EXPECT_LT(se[0], 1e-15);
}

TEST(Study, SweepExpandsTheCartesianProductInOrderAndWritesASummary) {
  TempDir dir;
  std::string yaml = std::string(kHcs) + R"(run_extra: 0
sweep:
  collision.alpha: [0.5, 0.9]
  step:
    fine: {run.time_step.value: 0.01}
    coarse: {run.time_step.value: 0.04}
)";
  yaml.replace(yaml.find("run_extra: 0\n"), 13, "");
  const fs::path file = dir.write("sweep.yaml", yaml);
  host::Pipeline base = host::load_pipeline(file, {"run.average_after.collisions_per_particle=2"}, {plugin_dir()});
  const auto cases = host::expand_cases(base);
  ASSERT_EQ(cases.size(), 4u);
  const char* labels[4] = {"collision.alpha=0.5, step=fine", "collision.alpha=0.5, step=coarse",
                           "collision.alpha=0.9, step=fine", "collision.alpha=0.9, step=coarse"};
  const double alphas[4] = {0.5, 0.5, 0.9, 0.9}, steps[4] = {0.01, 0.04, 0.01, 0.04};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(cases[k].label, labels[k]);
    EXPECT_EQ(cases[k].pipeline.collision.params.real("alpha"), alphas[k]);
    EXPECT_EQ(cases[k].pipeline.time_step_tau0, steps[k]);
  }
  const auto result = host::run_study(cases, {}, 1.0, nullptr);
  host::write_hdf5(dir / "sweep.h5", result.output);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t f = H5Fopen((dir / "sweep.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(h5::read_doubles(f, "summary/collision.alpha"), std::vector<double>(alphas, alphas + 4));
  EXPECT_EQ(h5::read_strings(f, "summary/step"), (std::vector<std::string>{"fine", "coarse", "fine", "coarse"}));
  // Every case is written whole, and the summary's steady mean is the case's own scalar.
  const auto summary_a2 = h5::read_doubles(f, "summary/cumulants.a2.steady_mean");
  ASSERT_EQ(summary_a2.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const std::string g = "cases/" + std::to_string(k) + "/diagnostics/cumulants/";
    EXPECT_EQ(h5::read_scalar(f, g + "a2.steady_mean"), summary_a2[k]);
    EXPECT_EQ(h5::read_string_attribute(f, "cases/" + std::to_string(k), "case"), labels[k]);
  }
  H5Fclose(f);
}

TEST(Study, ASweepCaseWithABadValueIsRefusedBeforeAnythingRuns) {
  TempDir dir;
  const fs::path file = dir.write("sweep.yaml", std::string(kHcs) + "sweep:\n  collision.alpha: [0.5, 1.5]\n");
  host::Pipeline base = host::load_pipeline(file, {}, {plugin_dir()});
  try {
    host::expand_cases(base);
    FAIL() << "expected a PipelineError";
  } catch (const host::PipelineError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("sweep case 1 (collision.alpha=1.5)"), std::string::npos) << m;
    EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
  }
}

// The steady stop: the means of the series over the last two windows of W collisions per particle
// differ by at most tolerance x the newer mean. a2 of the HCS relaxes within a few collisions.
TEST(Study, SteadyStopEndsTheRunWhenTheCriterionHoldsAndNotBefore) {
  TempDir dir;
  const double window = 2, tolerance = 0.05;
  host::Pipeline p = load_yaml(dir, kHcs,
                               {"run.stop.collisions_per_particle=200", "run.stop.steady={series: temperature/temperature, window: 2, tolerance: 1.0}",
                                "run.record_every=2"});
  host::Engine e(p, 0);
  e.run();
  ASSERT_TRUE(e.reached_steady_state()) << "T/T0 changes by far less than 100% over 2 collisions per particle";
  const auto& d = diagnostic(e, "temperature");
  EXPECT_LT(d.collisions_per_particle.back(), 200.0);
  EXPECT_GE(d.collisions_per_particle.back(), 2 * window);

  // A criterion that a cooling gas never meets runs to the upper limit.
  host::Pipeline q = load_yaml(dir, kHcs,
                               {"run.stop.collisions_per_particle=8",
                                "run.stop.steady={series: temperature/temperature, window: 2, tolerance: 1.0e-6}"},
                               "q.yaml");
  host::Engine eq(q, 0);
  eq.run();
  EXPECT_FALSE(eq.reached_steady_state());
  EXPECT_GE(eq.context().collisions_per_particle(), 8.0);

  // Where it stopped, the criterion holds on the recorded series (recomputed here), and one
  // record earlier it did not.
  const auto& s = d.collisions_per_particle;
  const auto& T = column(e.diagnostics(), "temperature", "temperature");
  auto steady_at = [&](std::size_t last) {
    double sum[2] = {0, 0};
    int n[2] = {0, 0};
    for (std::size_t k = last + 1; k-- > 0;) {
      const double age = s[last] - s[k];
      if (age >= 2 * window) break;
      sum[age < window ? 1 : 0] += T[k];
      ++n[age < window ? 1 : 0];
    }
    if (n[0] < 3 || n[1] < 3 || s[last] < 2 * window) return false;
    return std::fabs(sum[1] / n[1] - sum[0] / n[0]) <= 1.0 * std::fabs(sum[1] / n[1]);
  };
  // The last record is the forced final one at the stop; the criterion held at the one before.
  ASSERT_GE(s.size(), 3u);
  EXPECT_TRUE(steady_at(s.size() - 2) || steady_at(s.size() - 1));
  (void)tolerance;
}

TEST(Study, SteadyAveragesUseTheRecordsAfterTheThreshold) {
  std::vector<std::string> summary;
  host::DiagnosticOutput d("g", &summary);
  const auto id = d.series("x", "1", "test series");
  for (int k = 0; k < 200; ++k) {
    d.begin_record(0.5 * k, 0.1 * k);
    d.append(id, k < 100 ? 1000.0 : static_cast<double>(k % 2));  // after s = 10: 0, 1, 0, 1, ...
  }
  std::vector<host::DiagnosticOutput> ds{d};
  host::add_steady_averages(ds, 10.0, std::nullopt);
  double mean = std::nan(""), se = std::nan("");
  for (const auto& s : ds[0].scalars) {
    if (s.name == "x.steady_mean") mean = s.value;
    if (s.name == "x.steady_stderr") se = s.value;
  }
  EXPECT_EQ(mean, 0.5) << "records with s >= 10 only (exact: 50 zeros and 50 ones)";
  EXPECT_TRUE(std::isfinite(se));
  EXPECT_LT(se, 0.1);
}

// A diagnostic with one profile "rho" over `bins` bins: record k has the values value(k, b).
template <class Value>
host::DiagnosticOutput profile_output(std::size_t records, std::size_t bins, Value value) {
  host::DiagnosticOutput d("slab", nullptr);
  std::vector<double> centres;
  for (std::size_t b = 0; b < bins; ++b) centres.push_back(static_cast<double>(b));
  d.set_bins(centres);
  const auto id = d.profile("rho", "n", "density per bin");
  std::vector<double> row(bins);
  for (std::size_t k = 0; k < records; ++k) {
    d.begin_record(0.5 * static_cast<double>(k), 0.1 * static_cast<double>(k));
    for (std::size_t b = 0; b < bins; ++b) row[b] = value(k, b);
    d.append_profile(id, row.data());
    d.check_record("test");
  }
  return d;
}

const host::DiagnosticOutput::Array& array_named(const host::DiagnosticOutput& d, const std::string& name) {
  for (const auto& a : d.arrays)
    if (a.name == name) return a;
  throw std::runtime_error("no array " + name);
}

TEST(Study, ProfilesAreAveragedOverRealizationsElementByElement) {
  auto a = [](std::size_t k, std::size_t b) { return 1.0 + static_cast<double>(k) + 0.1 * static_cast<double>(b); };
  auto b = [](std::size_t k, std::size_t b) { return 2.0 * static_cast<double>(k * k) - static_cast<double>(b); };
  // The second realization has one record more: the average keeps the 4 common ones.
  const std::vector<std::vector<host::DiagnosticOutput>> runs{{profile_output(4, 3, a)}, {profile_output(5, 3, b)}};
  const auto avg = host::average_realizations(runs, nullptr);
  ASSERT_EQ(avg.size(), 1u);
  ASSERT_EQ(avg[0].profiles.size(), 2u);
  const auto& mean = avg[0].profiles[0];
  const auto& se = avg[0].profiles[1];
  EXPECT_EQ(mean.name, "rho");
  EXPECT_EQ(mean.unit, "n");
  EXPECT_EQ(se.name, "rho_stderr");
  EXPECT_EQ(se.unit, "n");
  EXPECT_EQ(avg[0].bin_centres, (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(avg[0].time.size(), 4u);
  ASSERT_EQ(mean.values.size(), 4u * 3u);
  ASSERT_EQ(se.values.size(), 4u * 3u);
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < 3; ++j) {
      const double x = a(k, j), y = b(k, j);
      // Two values: mean (x + y)/2, standard error sqrt(((x-m)^2 + (y-m)^2) / 1 / 2) = |x - y| / 2.
      EXPECT_NEAR(mean.values[k * 3 + j], 0.5 * (x + y), 1e-14 * (1 + std::fabs(x) + std::fabs(y))) << k << "," << j;
      EXPECT_NEAR(se.values[k * 3 + j], 0.5 * std::fabs(x - y), 1e-14 * (1 + std::fabs(x) + std::fabs(y))) << k << "," << j;
    }
  // Steady averages are taken of the mean profile, not of its stderr companion.
  auto with_steady = avg;
  host::add_steady_averages(with_steady, 0.0, std::nullopt);
  EXPECT_NO_THROW(array_named(with_steady[0], "rho.steady_mean"));
  EXPECT_THROW(array_named(with_steady[0], "rho_stderr.steady_mean"), std::runtime_error);
}

TEST(Study, SteadyProfileMeansArePerBinOverTheRecordsAfterTheThreshold) {
  // Bin 0 alternates 0, 1 after s = 10 (record 100), bin 1 is 3 there; both are 1000 before.
  auto value = [](std::size_t k, std::size_t b) {
    if (k < 100) return 1000.0;
    return b == 0 ? static_cast<double>(k % 2) : 3.0;
  };
  std::vector<host::DiagnosticOutput> ds{profile_output(200, 2, value)};
  host::add_steady_averages(ds, 10.0, std::nullopt);
  const auto& mean = array_named(ds[0], "rho.steady_mean");
  const auto& se = array_named(ds[0], "rho.steady_stderr");
  EXPECT_EQ(mean.shape, std::vector<std::size_t>{2});
  EXPECT_EQ(se.shape, std::vector<std::size_t>{2});
  EXPECT_EQ(mean.unit, "n");
  EXPECT_EQ(mean.data, (std::vector<double>{0.5, 3.0})) << "records with s >= 10 only";
  ASSERT_EQ(se.data.size(), 2u);
  EXPECT_TRUE(std::isfinite(se.data[0]));
  EXPECT_LT(se.data[0], 0.1);
  EXPECT_EQ(se.data[1], 0.0);
  // The series path gives the same numbers: bin 0 as a series.
  host::DiagnosticOutput s("g", nullptr);
  const auto id = s.series("x", "1", "bin 0 as a series");
  for (std::size_t k = 0; k < 200; ++k) {
    s.begin_record(0.5 * static_cast<double>(k), 0.1 * static_cast<double>(k));
    s.append(id, value(k, 0));
  }
  std::vector<host::DiagnosticOutput> ss{s};
  host::add_steady_averages(ss, 10.0, std::nullopt);
  EXPECT_EQ(ss[0].scalars[0].value, mean.data[0]);
  EXPECT_EQ(ss[0].scalars[1].value, se.data[0]);
}


// ---------------------------------------------------------------------------------------------
// Honest error bars (issue 8, item 6).

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

TEST(Study, IntegratedAutocorrelationTimeOfAnAr1Series) {
  for (double phi : {0.0, 0.5, 0.8}) {
    const double expected = (1 + phi) / (1 - phi);
    const double tau = host::integrated_autocorrelation_time(ar1(40000, phi, 7));
    EXPECT_NEAR(tau, expected, 0.1 * expected) << "phi " << phi;
  }
}

// One realization: batches of >= 5 tau_int records; too short a window gives NaN and says why.
TEST(Study, SingleRealizationBatchesAreLongerThanTheCorrelationTimeOrTheErrorIsNaN) {
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
TEST(Study, SeveralRealizationsTakeTheSteadyErrorFromTheScatterOfTheirOwnMeans) {
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

// The seed check of an error (issue 29 item 2): chi2/dof of K values about their mean against
// their own errors, and its central 95 % band, checked against chi2 tables and by hand.
TEST(Study, SeedCheckBandIsTheCentral95PercentOfChiSquaredPerDof) {
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
TEST(Study, EveryScalarErrorOfSeveralRealizationsGetsItsSeedCheck) {
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
// the batch-means error is calibrated there, Study.SteadyErrorsOfIndependentRealizations... below),
// declared stationary; a series the diagnostic does not declare stationary gets no check.
TEST(Study, TheHostsSteadyErrorsOfOneRealizationAreCheckedAgainstTheRealizationsScatter) {
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
// The errors before issue 8 (batch length not checked against the correlation time) are printed.
TEST(Study, SteadyErrorsOfIndependentRealizationsHaveUnitVarianceZScores) {
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
    // The estimate before issue 8 (BatchMeans: up to 64 batches, length not checked), for the record.
    BatchMeans before;
    std::vector<double> window;
    const auto& a2 = column(d, "cumulants", "a2");
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
              "  with the batch-means error before issue 8: chi^2 = %.1f\n",
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

// output.realizations: each realization's own series under <group>/realizations/<k>.
TEST(Study, OutputRealizationsWritesEachRealizationsOwnSeries) {
  TempDir dir;
  host::Pipeline p = load_yaml(dir, kHcs, {"run.realizations=3", "output.realizations=true",
                                           "run.average_after={collisions_per_particle: 1}"});
  ASSERT_TRUE(p.output_realizations);
  const auto cases = host::expand_cases(p);
  auto result = host::run_study(cases, nullptr, 1.0, nullptr);
  const fs::path file = dir.path() / "out.h5";
  host::write_hdf5(file, result.output);
  h5::File h(file);
  const hid_t f = h.id();
  for (int k = 0; k < 3; ++k) {
    const std::string g = "diagnostics/temperature/realizations/" + std::to_string(k) + "/";
    EXPECT_EQ(h5::read_doubles(f, g + "temperature"), column(std::vector<host::DiagnosticOutput>{run_one(p, k)}, "temperature", "temperature"))
        << "realization " << k;
    EXPECT_TRUE(h5::is_dataset(f, g + "collisions_per_particle"));
    EXPECT_TRUE(h5::is_dataset(f, g + "temperature.steady_mean"));
  }
  EXPECT_FALSE(h5::exists(f, "diagnostics/temperature/realizations/3"));
  EXPECT_NE(h5::read_string_attribute(f, "diagnostics/temperature/collisions_per_particle", "description")
                .find("accepted collisions / N"),
            std::string::npos);
  EXPECT_NE(h5::read_string_attribute(f, "run", "collisions_per_particle.description").find("two particles"),
            std::string::npos);
  // Without the option, no realizations group.
  const host::Pipeline q = load_yaml(dir, kHcs, {"run.realizations=2"});
  const auto plain = host::expand_cases(q);
  auto r2 = host::run_study(plain, nullptr, 1.0, nullptr);
  const fs::path file2 = dir.path() / "plain.h5";
  host::write_hdf5(file2, r2.output);
  h5::File h2(file2);
  const hid_t f2 = h2.id();
  EXPECT_FALSE(h5::exists(f2, "diagnostics/temperature/realizations"));
}

// The progress of a study: fraction, elapsed time and time left of the whole study.
// With one thread the runs follow each other, so run 2's reports start at 2/3; with two, run 2
// starts once one of runs 0 and 1 has finished, so at 1/3 at least. Either way the fraction never
// goes back, the elapsed time is the study's, and the last report is at 1.
TEST(Study, ProgressReportsCoverTheWholeStudy) {
  for (const char* threads : {"1", "2"}) {
    TempDir dir;
    host::Pipeline p = load_yaml(dir, kHcs, {"run.realizations=3", std::string("run.threads=") + threads});
    const auto cases = host::expand_cases(p);
    std::vector<host::StudyProgress> seen;
    host::run_study(cases, [&](const host::StudyProgress& sp) { seen.push_back(sp); }, 0.0, nullptr);
    ASSERT_FALSE(seen.empty());
    const double run2_from = std::string(threads) == "1" ? 2.0 / 3.0 : 1.0 / 3.0;
    double last_fraction = -1, last_elapsed = -1;
    bool saw_later_run = false;
    for (const auto& sp : seen) {
      EXPECT_GE(sp.fraction, last_fraction - 1e-12) << threads << " threads";
      EXPECT_GE(sp.elapsed_seconds, last_elapsed);
      EXPECT_GE(sp.elapsed_seconds, sp.progress.elapsed_seconds - 1e-9) << "study time includes the run's";
      last_fraction = sp.fraction;
      last_elapsed = sp.elapsed_seconds;
      if (sp.run == 2) {
        saw_later_run = true;
        EXPECT_GE(sp.fraction, run2_from - 1e-12) << threads << " threads";
      }
    }
    EXPECT_TRUE(saw_later_run);
    EXPECT_NEAR(seen.back().fraction, 1.0, 1e-9);
  }
}

}  // namespace
}  // namespace gdsmc::test
