// Bad slab pipelines through the gdsmc executable: each is refused with exit status 1, a message
// that names the place (file:line for the key, or the plugin and its parameter) and what would be
// valid, and nothing is written.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

const std::string kGood = R"(run:
  seed: 7
  particles: 1000
  time_step: {value: 0.01, unit: tau0}
  stop: {time: {value: 0.2, unit: tau0}}
system:
  density: 1.0e-3
  temperature: 1.0
  domain: slab
  box: {y: 2.5}
  layers: 10
initial_state: {plugin: maxwellian}
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
forcings: []
boundaries:
  y_min: {plugin: diffuse_wall, temperature: 1.0}
  y_max: {plugin: diffuse_wall, temperature: 1.0}
diagnostics: [temperature, profiles]
output: {file: out.h5}
)";

// `gdsmc validate` and `gdsmc run` both refuse (support/refusal.hpp), saying `must_say` and naming
// the pipeline file; returns run's stderr.
std::string refuse_both(const std::string& yaml, const std::string& must_say) {
  std::string err;
  for (const char* command : {"validate", "run"}) {
    const Refusal r = refuse(yaml, {"--quiet"}, command);
    EXPECT_TRUE(contains(r.result.err, must_say)) << command << ": expected '" << must_say << "' in\n" << r.result.describe();
    EXPECT_TRUE(contains(r.result.err, r.file)) << "the message should name the pipeline file\n" << r.result.describe();
    err = r.result.err;
  }
  return err;
}

TEST(SlabBadInput, GoodSlabPipelineRunsAndWrites) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", kGood);
  const ProcessResult r = run_gdsmc({"run", file.string(), "--quiet"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"out.h5", "pipeline.yaml"}));
}

TEST(SlabBadInput, SlabWithoutTwoBoundaries) {
  const std::string yaml = replace_once(kGood, "  y_max: {plugin: diffuse_wall, temperature: 1.0}\n", "");
  const std::string err = refuse_both(yaml, "missing 'y_max'");
  // yaml-cpp marks a block mapping at its first key: the boundaries mapping starts at y_min.
  EXPECT_TRUE(contains(err, ":" + std::to_string(line_of(yaml, "  y_min:")) + ":")) << err;
  refuse_both(replace_once(kGood, "boundaries:\n  y_min: {plugin: diffuse_wall, temperature: 1.0}\n  y_max: {plugin: diffuse_wall, temperature: 1.0}\n", ""),
         "a slab needs its two y boundaries");
}

TEST(SlabBadInput, LeesEdwardsOnOneSideOnly) {
  const std::string yaml = replace_once(kGood, "  y_max: {plugin: diffuse_wall, temperature: 1.0}",
                                   "  y_max: {plugin: lees_edwards, shear_rate: 4}");
  const std::string err = refuse_both(yaml, "both y boundaries must be 'lees_edwards' with the same parameters");
  EXPECT_TRUE(contains(err, "boundaries.y_max")) << err;
}

TEST(SlabBadInput, WallTemperatureMustBePositive) {
  const std::string yaml = replace_once(kGood, "  y_min: {plugin: diffuse_wall, temperature: 1.0}",
                                   "  y_min: {plugin: diffuse_wall, temperature: 0}");
  const std::string err = refuse_both(yaml, "boundaries.y_min.temperature");
  EXPECT_TRUE(contains(err, ":" + std::to_string(line_of(yaml, "temperature: 0")) + ":")) << err;
}

TEST(SlabBadInput, AccommodationOutsideZeroOne) {
  const std::string yaml = replace_once(kGood, "  y_min: {plugin: diffuse_wall, temperature: 1.0}",
                                   "  y_min: {plugin: maxwell_wall, temperature: 1.0, accommodation: 1.5}");
  const std::string err = refuse_both(yaml, "boundaries.y_min.accommodation");
  EXPECT_TRUE(contains(err, "1.5")) << err;
}

TEST(SlabBadInput, FewerThanOneParticlePerLayer) {
  const std::string yaml = replace_once(kGood, "  layers: 10", "  layers: 2000");
  const std::string err = refuse_both(yaml, "fewer than one particle per layer");
  EXPECT_TRUE(contains(err, ":" + std::to_string(line_of(yaml, "layers: 2000")) + ":")) << err;
}

TEST(SlabBadInput, BodyAccelerationWithLeesEdwardsIsRefusedWithTheReason) {
  std::string yaml = replace_once(kGood, "  y_min: {plugin: diffuse_wall, temperature: 1.0}\n  y_max: {plugin: diffuse_wall, temperature: 1.0}",
                             "  y: {plugin: lees_edwards, shear_rate: 4}");
  yaml = replace_once(yaml, "forcings: []", "forcings: [{plugin: body_acceleration, acceleration: 0.5}]");
  const std::string err = refuse_both(yaml, "shear_rate");
  EXPECT_TRUE(contains(err, "lees_edwards")) << err;
  EXPECT_TRUE(contains(err, "body")) << err;
}

TEST(SlabBadInput, BoundariesInAHomogeneousSystem) {
  std::string yaml = replace_once(kGood, "  domain: slab\n  box: {y: 2.5}\n  layers: 10\n", "");
  yaml = replace_once(yaml, "diagnostics: [temperature, profiles]", "diagnostics: [temperature]");
  refuse_both(yaml, "boundaries need a slab");
}

TEST(SlabBadInput, SlabWithoutItsGap) {
  refuse_both(replace_once(kGood, "  box: {y: 2.5}\n", ""), "a slab needs its gap");
  refuse_both(replace_once(kGood, "  box: {y: 2.5}\n", "  box: {y: {value: 2.5, unit: furlong}}\n"), "unknown length unit 'furlong'");
}

}  // namespace
