// Host pipeline features with no physics in them: realizations, sweeps, the steady-state stop and
// steady averages, the cases of a sweep (framework/study/, framework/engine/engine.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <gdsmc/physics/series.hpp>

#include "output/hdf5_file.hpp"
#include "study/cases.hpp"
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
  const host::LoadedPipeline base = host::load_pipeline(file, {"run.average_after.collisions_per_particle=2"}, {plugin_dir()});
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
  const h5::File output(dir / "sweep.h5");
  const hid_t f = output.id();
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
}

// The error stays structured: its key path, plugin and parameter as the case's load found them,
// the cases in sweep_cases, and the printed line the case's line followed by them.
TEST(Study, ASweepCaseWithABadValueIsRefusedBeforeAnythingRuns) {
  TempDir dir;
  const fs::path file = dir.write("sweep.yaml", std::string(kHcs) + "sweep:\n  collision.alpha: [0.5, 1.5]\n");
  const host::LoadedPipeline base = host::load_pipeline(file, {}, {plugin_dir()});
  try {
    host::expand_cases(base);
    FAIL() << "expected a PipelineError";
  } catch (const host::PipelineError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("sweep case 1 (collision.alpha=1.5)"), std::string::npos) << m;
    EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
    ASSERT_EQ(e.errors().size(), 1u) << m;
    const host::ConfigError& error = e.errors()[0];
    EXPECT_EQ(error.path, "collision.alpha");
    EXPECT_EQ(error.plugin, "inelastic_hard_spheres");
    EXPECT_EQ(error.parameter, "alpha");
    EXPECT_EQ(error.valid, "[0, 1]");
    EXPECT_EQ(error.sweep_cases, "in sweep case 1 (collision.alpha=1.5)");
    host::ConfigError without = error;
    without.sweep_cases.clear();
    EXPECT_EQ(error.text(), without.text() + "; in sweep case 1 (collision.alpha=1.5)");
    EXPECT_EQ(e.messages(), std::vector<std::string>{error.text()});
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

// output.realizations: each realization's own series under <group>/realizations/<k>.
TEST(Study, OutputRealizationsWritesEachRealizationsOwnSeries) {
  TempDir dir;
  const host::LoadedPipeline study = load_study(dir, kHcs, {"run.realizations=3", "output.realizations=true",
                                                          "run.average_after={collisions_per_particle: 1}"});
  const host::Pipeline& p = study.pipeline;
  ASSERT_TRUE(p.output_realizations);
  const auto cases = host::expand_cases(study);
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
  const auto plain = host::expand_cases(load_study(dir, kHcs, {"run.realizations=2"}));
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
    const auto cases = host::expand_cases(load_study(dir, kHcs, {"run.realizations=3", std::string("run.threads=") + threads}));
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

// A window on the other clock (t) that the run never reaches: the summary warns, and the NaN
// datasets say why in their description.
TEST(Study, ASteadyWindowNeverReachedIsWarnedAboutAndDescribed) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", small_pipeline("  average_after: {time: 1000}\n", "{collisions_per_particle: 1}"));
  const ProcessResult r = run_gdsmc({"run", file.string()}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(contains(r.out, "warning: run.average_after: the steady window t/tau0 >= 1000 holds no record (the last is at "
                              "t/tau0 = ")) << r.describe();
  h5::File f(dir / "out.h5");
  EXPECT_TRUE(std::isnan(h5::read_scalar(f.id(), "/diagnostics/temperature/temperature.steady_mean")));
  EXPECT_TRUE(contains(h5::read_string_attribute(f.id(), "/diagnostics/temperature/temperature.steady_mean", "description"),
                       "NaN: no record reached the window"));
}

// The cases of a sweep are resolved against the base pipeline's plugins: each library is loaded
// once, and a case's entries keep them loaded after the base is gone.
TEST(Study, SweepCasesShareTheBasePipelinesRegistry) {
  TempDir dir;
  std::vector<host::StudyCase> cases;
  const host::LoadedPlugin* loaded = nullptr;
  {
    const host::LoadedPipeline base = load_study(dir, kSmallHcsPipeline + "sweep:\n  collision.alpha: [0.5, 0.7, 0.9]\n");
    cases = host::expand_cases(base);
    loaded = base.plugins->find("inelastic_hard_spheres");
    ASSERT_NE(loaded, nullptr);
    EXPECT_EQ(base.pipeline.collision.plugin.get(), loaded);
  }
  ASSERT_EQ(cases.size(), 3u);
  for (const auto& c : cases) EXPECT_EQ(c.pipeline.collision.plugin.get(), loaded) << c.label;  // the same library
  // The base is gone: the cases still construct their collision rule from the library they hold.
  const auto result = host::run_study(cases, {}, 1.0, nullptr);
  EXPECT_EQ(result.output.cases.size(), 3u);
}

}  // namespace
}  // namespace gdsmc::test
