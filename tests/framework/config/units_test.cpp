// Units of plugin parameters (framework/config/units.cpp, SDK Dimensions): composite dimensions,
// unit expressions in the reference units, the shorthands of SDK 1.x, and refusals that name the
// valid units.
#include <gtest/gtest.h>

#include "config/errors.hpp"
#include "config/units.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// Consistent reference scales: tau0 = lambda0 / sqrt(2 T0 / m), m = 1.
host::UnitScales scales() {
  host::UnitScales s;
  s.T0 = 1.5;
  s.lambda0 = 3.0;
  s.sigma = 0.25;
  s.tau0 = s.lambda0 / std::sqrt(2.0 * s.T0);
  return s;
}

double convert(double value, const std::string& unit, const Dimensions& d) {
  std::string why;
  auto v = host::to_reduced(value, unit, d, scales(), why);
  if (!v) throw std::runtime_error(why);
  return *v;
}

double convert(double value, const std::string& unit, Dimension d) { return convert(value, unit, dimensions_of(d)); }

constexpr Dimensions kNoiseStrength{.length = 2, .time = -3};  // velocity^2 / time

TEST(Units, ACompositeDimensionConvertsFromProductsOfTheReferenceUnits) {
  const auto s = scales();
  // A noise strength (velocity^2 / time) written as T0/(m tau0), lambda0^2 tau0^-3 or reduced.
  EXPECT_NEAR(convert(4, "T0/(m*tau0)", kNoiseStrength), 4 * s.T0 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(4, "T0 m^-1 tau0^-1", kNoiseStrength), 4 * s.T0 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(4, "lambda0^2 tau0^-3", kNoiseStrength), 4 * s.lambda0 * s.lambda0 / std::pow(s.tau0, 3), 1e-12);
  EXPECT_NEAR(convert(4, "sigma^2/tau0^3", kNoiseStrength), 4 * s.sigma * s.sigma / std::pow(s.tau0, 3), 1e-12);
  EXPECT_NEAR(convert(4, "2T0/(m tau0)", kNoiseStrength), 8 * s.T0 / s.tau0, 1e-12);
  EXPECT_EQ(convert(4, "reduced", kNoiseStrength), 4.0);
  // The same dimension declared through temperature and mass: T / (m t).
  const Dimensions via_temperature{.time = -1, .temperature = 1, .mass = -1};
  EXPECT_NEAR(convert(4, "T0/(m tau0)", via_temperature), 4 * s.T0 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(4, "lambda0^2/tau0^3", via_temperature), 4 * s.lambda0 * s.lambda0 / std::pow(s.tau0, 3), 1e-12);
  // A heating rate (energy / time) in T0/tau0; a noise strength is not one (mass differs).
  const Dimensions heating{.time = -1, .temperature = 1};
  EXPECT_NEAR(convert(4, "T0/tau0", heating), 4 * s.T0 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(4, "m lambda0^2 tau0^-3", heating), 4 * s.lambda0 * s.lambda0 / std::pow(s.tau0, 3), 1e-12);
  std::string why;
  EXPECT_FALSE(host::to_reduced(4, "T0/tau0", kNoiseStrength, s, why));
  EXPECT_NE(why.find("'T0/tau0' is mass length^2 time^-3, not length^2 time^-3"), std::string::npos) << why;
  // A bare number means lambda0^l tau0^t T0^T m^M.
  EXPECT_NEAR(host::reference_factor(kNoiseStrength, s), s.lambda0 * s.lambda0 / std::pow(s.tau0, 3), 1e-12);
  EXPECT_NEAR(host::reference_factor(via_temperature, s), s.T0 / s.tau0, 1e-12);
  EXPECT_EQ(host::reference_unit(via_temperature), "tau0^-1 T0 m^-1");
  EXPECT_EQ(host::reference_unit(kNoiseStrength), "lambda0^2 tau0^-3");
  EXPECT_EQ(to_string(kNoiseStrength), "length^2 time^-3");
}

TEST(Units, TheShorthandsOfSdk1KeepTheirMeaningAndUnits) {
  const auto s = scales();
  EXPECT_EQ(to_string(Dimension::velocity), "velocity");
  EXPECT_TRUE(dimensions_of(Dimension::none).dimensionless());
  EXPECT_TRUE((Dimensions{.length = 1, .time = -1} == Dimension::velocity));
  EXPECT_NEAR(convert(2, "sqrt(2T0/m)", Dimension::velocity), 2 * std::sqrt(2 * s.T0), 1e-12);
  EXPECT_NEAR(host::reference_factor(dimensions_of(Dimension::velocity), s), std::sqrt(2 * s.T0), 1e-12);
  EXPECT_NEAR(convert(2, "2T0/(m*lambda0)", Dimension::acceleration), 4 * s.T0 / s.lambda0, 1e-12);
  EXPECT_NEAR(host::reference_factor(dimensions_of(Dimension::acceleration), s), 2 * s.T0 / s.lambda0, 1e-12);
  EXPECT_NEAR(convert(0.5, "1/tau0", Dimension::inverse_time), 0.5 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(0.5, "tau0^-1", Dimension::inverse_time), 0.5 / s.tau0, 1e-12);
  EXPECT_NEAR(convert(7, "sigma", Dimension::length), 7 * s.sigma, 1e-12);
  EXPECT_NEAR(convert(7, "lambda0", Dimension::length), 7 * s.lambda0, 1e-12);
  EXPECT_NEAR(convert(7, "T0", Dimension::temperature), 7 * s.T0, 1e-12);
  EXPECT_NEAR(convert(7, "tau0", Dimension::time), 7 * s.tau0, 1e-12);
}

TEST(Units, AnUnknownUnitOrOneOfAnotherDimensionIsRefusedNamingTheValidUnits) {
  std::string why;
  EXPECT_FALSE(host::to_reduced(1, "furlong", kNoiseStrength, scales(), why));
  for (const char* valid : {"furlong", "reduced", "lambda0^2 tau0^-3", "lambda0", "sigma", "tau0", "T0", "m"})
    EXPECT_NE(why.find(valid), std::string::npos) << valid << " missing from: " << why;
  why.clear();
  EXPECT_FALSE(host::to_reduced(1, "tau0", kNoiseStrength, scales(), why));
  EXPECT_NE(why.find("'tau0' is time"), std::string::npos) << why;
  EXPECT_NE(why.find("length^2 time^-3"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(host::to_reduced(1, "T0/(tau0", kNoiseStrength, scales(), why));
  EXPECT_NE(why.find("expected ')'"), std::string::npos) << why;
}

const char* kUsf = R"(run:
  seed: 3
  particles: 100
  time_step: {value: 0.01, unit: tau0}
  stop: {collisions_per_particle: 1}
system: {density: 1.0e-3, temperature: 2.0}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
forcings:
  - {plugin: uniform_shear, shear_rate: SHEAR}
diagnostics: [temperature]
output: {file: unused.h5}
)";

std::string usf(const std::string& shear) {
  std::string y = kUsf;
  y.replace(y.find("SHEAR"), 5, shear);
  return y;
}

TEST(Units, APipelineValueInAProductOfReferenceUnitsIsConvertedAtLoadTime) {
  TempDir dir;
  const host::Pipeline bare = load_yaml(dir, usf("0.5"));
  const host::Pipeline written = load_yaml(dir, usf("{value: 0.5, unit: sqrt(2T0/m)/lambda0}"));
  const double expected = 0.5 / bare.time_unit0();
  ASSERT_EQ(bare.forcings.size(), 1u);
  EXPECT_NEAR(bare.forcings[0].params.real("shear_rate"), expected, 1e-12 * expected);
  EXPECT_NEAR(written.forcings[0].params.real("shear_rate"), expected, 1e-12 * expected);
}

TEST(Units, APipelineWithAnUnknownUnitIsRefusedWithTheValidUnits) {
  TempDir dir;
  try {
    load_yaml(dir, usf("{value: 0.5, unit: furlong/fortnight}"));
    FAIL() << "an unknown unit was accepted";
  } catch (const host::PipelineError& e) {
    const std::string all = join(e.messages(), "\n");
    EXPECT_NE(all.find("unknown unit 'furlong/fortnight'"), std::string::npos) << all;
    EXPECT_NE(all.find("tau0^-1"), std::string::npos) << all;
    EXPECT_NE(all.find("reduced"), std::string::npos) << all;
    EXPECT_NE(all.find("pipeline.yaml:"), std::string::npos) << "file:line of the value: " << all;
  }
}

// run.stop.time and run.average_after.time take the same forms: a bare number of tau0 or
// {value: T, unit: tau0}; another unit is refused at its line, naming the valid one.
TEST(Units, StopAndAverageTimesTakeANumberOrAValueWithTheUnitTau0) {
  TempDir dir;
  auto with_times = [](const std::string& stop, const std::string& after) {
    std::string y = usf("0.5");
    y = replace_once(y, "  stop: {collisions_per_particle: 1}\n",
                     "  stop: {time: " + stop + "}\n  average_after: {time: " + after + "}\n");
    return y;
  };
  const host::Pipeline bare = load_yaml(dir, with_times("3", "1.5"));
  const host::Pipeline written = load_yaml(dir, with_times("{value: 3, unit: tau0}", "{value: 1.5, unit: tau0}"));
  EXPECT_EQ(bare.stop_time_tau0, 3.0);
  EXPECT_EQ(written.stop_time_tau0, 3.0);
  EXPECT_EQ(bare.average_after_time_tau0, 1.5);
  EXPECT_EQ(written.average_after_time_tau0, 1.5);
  try {
    load_yaml(dir, with_times("3", "{value: 1.5, unit: s}"));
    FAIL() << "a time in seconds was accepted";
  } catch (const host::PipelineError& e) {
    const std::string all = join(e.messages(), "\n");
    EXPECT_NE(all.find("run.average_after.time.unit"), std::string::npos) << all;
    EXPECT_NE(all.find("unknown unit 's' (valid: tau0)"), std::string::npos) << all;
  }
}

TEST(Units, PluginsCommandShowsTheDimensionAndItsReferenceUnit) {
  TempDir dir;
  const auto r = run_gdsmc({"plugins", "uniform_shear", "--plugin-path", plugin_dir().string()}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("dimension 1/time  unit tau0^-1"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace gdsmc::test
