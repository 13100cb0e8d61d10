// The host's own one-value keys of run:, system: and output: are declared as plugin parameters are
// (config/host_schema.hpp) and read by the same reader: the defaults a pipeline gets are the
// schema's, a value out of range names its range, a misspelt choice or key gets the closest
// spelling, and each error carries the structured fields of any other.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "config/host_schema.hpp"
#include "test_support.hpp"

namespace {

using namespace gdsmc::test;

// The small HCS pipeline without its seed: it gives none of the keys whose defaults are checked.
const std::string kMinimal = replace_once(kSmallHcsPipeline, "  seed: 3\n", "");

TEST(HostSchema, APipelineThatGivesNoValueGetsTheSchemasDefaults) {
  TempDir dir;
  const gdsmc::host::Pipeline p = load_yaml(dir, kMinimal);
  EXPECT_EQ(p.seed, 1u);
  EXPECT_EQ(p.realizations, 1u);
  EXPECT_EQ(p.threads, 0u);
  EXPECT_EQ(p.sample_every, 1u);
  EXPECT_EQ(p.record_every, 1u);
  EXPECT_EQ(p.moments_every, 4u);
  EXPECT_FALSE(p.candidate_pairs_squared);
  EXPECT_EQ(p.pair_selection, 2u);  // auto
  EXPECT_TRUE(p.sampling_bracketed);
  EXPECT_EQ(p.sigma, 1.0);
  EXPECT_EQ(p.temperature, 1.0);
  EXPECT_FALSE(p.output_particles || p.output_realizations || p.output_plots);
}

TEST(HostSchema, GivenValuesReachThePipeline) {
  TempDir dir;
  const gdsmc::host::Pipeline p =
      load_yaml(dir, kMinimal, {"run.seed=9", "run.moments_every=2", "run.pair_selection=uniform",
                                "run.sampling=after_step", "run.candidate_pairs=squared", "system.temperature=2",
                                "output.plots=true"});
  EXPECT_EQ(p.seed, 9u);
  EXPECT_EQ(p.moments_every, 2u);
  EXPECT_EQ(p.pair_selection, 0u);
  EXPECT_FALSE(p.sampling_bracketed);
  EXPECT_TRUE(p.candidate_pairs_squared);
  EXPECT_EQ(p.temperature, 2.0);
  EXPECT_TRUE(p.output_plots);
}

TEST(HostSchema, RangesChoicesAndMisspeltKeysAreReportedAsForPluginParameters) {
  TempDir dir;
  try {
    (void)load_yaml(dir, kMinimal, {"run.realizations=0", "run.sampling=brackted", "system.temperatur=2"});
    FAIL() << "expected a PipelineError";
  } catch (const gdsmc::host::PipelineError& e) {
    std::map<std::string, const gdsmc::host::ConfigError*> by_path;
    for (const auto& error : e.errors()) by_path[error.path] = &error;
    ASSERT_TRUE(by_path.count("run.realizations")) << e.what();
    EXPECT_EQ(by_path["run.realizations"]->valid, "[1, 100000]");
    EXPECT_EQ(by_path["run.realizations"]->location, "--set run.realizations=0");
    ASSERT_TRUE(by_path.count("run.sampling")) << e.what();
    EXPECT_TRUE(contains(by_path["run.sampling"]->valid, "did you mean bracketed")) << by_path["run.sampling"]->valid;
    ASSERT_TRUE(by_path.count("system.temperatur")) << e.what();
    EXPECT_TRUE(contains(by_path["system.temperatur"]->message, "did you mean temperature")) << e.what();
  }
}

// Every key the sections accept is the schema's: a key of one value has a documented spec, and no
// key is named twice.
TEST(HostSchema, EachSectionsKeysAreDeclaredOnceWithADoc) {
  for (const auto* s : {&gdsmc::host::run_section(), &gdsmc::host::system_section(), &gdsmc::host::output_section()}) {
    std::set<std::string> seen;
    for (const auto& key : s->keys()) EXPECT_TRUE(seen.insert(key).second) << s->name << "." << key << " twice";
    for (const auto& key : s->values) EXPECT_FALSE(key.spec.doc.empty()) << s->name << "." << key.spec.name;
  }
}

}  // namespace
