// scripts/report_runs.py, with which the validation reports find their runs by provenance: three
// small real outputs under names that say nothing (one run with --set overrides, the same pipeline
// as it is, a sweep in a subfolder) are each found by their pipeline file, overrides and sweep axes;
// a selection that two outputs match fails naming both. Needs /usr/bin/python3 with python3-h5py
// (scripts/install-deps).
#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace gdsmc::test;

namespace {

// Run `pipeline` (a file in dir) into dir/output with extra arguments.
void run(const TempDir& dir, const std::string& pipeline, const std::string& output, std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"run", (dir / pipeline).string(), "-q", "--plugin-path", plugin_dir().string(),
                                "-o", (dir / output).string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const ProcessResult r = run_gdsmc(args, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.describe();
}

// /usr/bin/python3 with these arguments, in dir.
ProcessResult python(const TempDir& dir, const std::vector<std::string>& args) {
  Process p(args, dir.path(), {}, "/usr/bin/python3");
  return p.wait(120);
}

// A python -c program with report_runs importable and the outputs indexed as `runs` (argv[1]: the folder).
ProcessResult select(const TempDir& dir, const std::string& program) {
  const std::string prelude = "import sys; sys.path.insert(0, '" + (source_dir() / "scripts").string() +
                              "'); import report_runs; runs = report_runs.index(sys.argv[1])\n";
  return python(dir, {"-c", prelude + program, (dir / "outputs").string()});
}

class ReportRuns : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    dir_->write("tiny.yaml", kSmallHcsPipeline);
    dir_->write("tiny_sweep.yaml", kSmallHcsPipeline + "sweep: {collision.alpha: [0.9, 0.7]}\n");
    fs::create_directories(*dir_ / "outputs/deeper");
    run(*dir_, "tiny.yaml", "outputs/x1.h5", {"--set", "collision.alpha=0.8", "--set", "run.seed=9"});
    run(*dir_, "tiny.yaml", "outputs/q.h5");
    run(*dir_, "tiny_sweep.yaml", "outputs/deeper/a.h5");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TempDir* dir_;
};
TempDir* ReportRuns::dir_ = nullptr;

TEST_F(ReportRuns, ListsEveryOutputWithItsConfigOverridesAndAxes) {
  const ProcessResult r = python(*dir_, {(source_dir() / "scripts/report_runs.py").string(), (*dir_ / "outputs").string()});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::string out = (*dir_ / "outputs").string();
  EXPECT_NE(r.out.find(out + "/x1.h5: config tiny, axes (none), 1 case(s)\n    --set collision.alpha=0.8\n"
                             "    --set run.seed=9\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(out + "/q.h5: config tiny, axes (none), 1 case(s)\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(out + "/deeper/a.h5: config tiny_sweep, axes collision.alpha, 2 case(s)\n"), std::string::npos) << r.out;
}

TEST_F(ReportRuns, SelectsEachRunByProvenanceWhateverItsFileName) {
  const ProcessResult r = select(*dir_,
                                 "import os\n"
                                 "name = lambda o: os.path.relpath(o.path, sys.argv[1]) if o else None\n"
                                 "print('overridden', name(runs.one(config='tiny', set={'collision.alpha': 0.8})))\n"
                                 "print('seeded', name(runs.one(config='tiny', has=('run.seed',))))\n"
                                 "print('as configured', name(runs.one(config='tiny', unset=('collision.alpha',))))\n"
                                 "s = runs.one(axes=('collision.alpha',))\n"
                                 "print('sweep', name(s), s.config, [c.sweep['collision.alpha'] for c in s.cases])\n"
                                 "print('alpha', [c.param('collision', 'alpha') for c in s.cases])\n"
                                 "print('none', name(runs.one(config='tiny', set={'collision.alpha': 0.5})))\n");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.out,
            "overridden x1.h5\n"
            "seeded x1.h5\n"
            "as configured q.h5\n"
            "sweep deeper/a.h5 tiny_sweep ['0.9', '0.7']\n"
            "alpha ['0.9', '0.7']\n"
            "none None\n");
}

TEST_F(ReportRuns, AnAmbiguousSelectionFailsNamingBothFiles) {
  const ProcessResult r = select(*dir_, "runs.one(config='tiny')\n");
  EXPECT_NE(r.exit_code, 0) << r.describe();
  const std::string out = (*dir_ / "outputs").string();
  EXPECT_NE(r.err.find("2 outputs match {'config': 'tiny'}"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(out + "/q.h5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(out + "/x1.h5"), std::string::npos) << r.err;
}

}  // namespace
