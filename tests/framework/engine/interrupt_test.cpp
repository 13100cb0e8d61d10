// Every run can be stopped: SIGINT and SIGTERM end a run within a second, and a second signal ends
// it at once even inside a plugin call that never returns.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

using Clock = std::chrono::steady_clock;

// SIGINT and SIGTERM about 1.5 s into a long run (2e5 elastic particles to s = 1e5): exit 130
// within a second, "interrupted", nothing written.
TEST(Interrupt, SigintAndSigtermEndALongRunWithinASecond) {
  for (const int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    TempDir dir;
    const auto file = dir.write("pipeline.yaml", small_pipeline("", "{collisions_per_particle: 100000}", 200000, 1.0));
    const auto start = Clock::now();
    Process p({"run", file.string(), "--quiet"}, dir.path());
    ASSERT_TRUE(p.wait_until_catches(sig)) << "the run never installed a handler for signal " << sig;
    std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.2, 1.5 - seconds_since(start))));
    const auto sent = Clock::now();
    p.send(sig);
    const ProcessResult r = p.wait(10);
    const double took = seconds_since(sent);
    ASSERT_FALSE(r.timed_out) << r.describe();
    EXPECT_LT(took, 1.0) << r.describe();
    EXPECT_EQ(r.exit_code, 130) << r.describe();
    EXPECT_TRUE(contains(r.err, "interrupted; no output written")) << r.describe();
    EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
  }
}

// A plugin call that never returns cannot poll the flag; a second signal ends the run at once.
TEST(Interrupt, ASecondSignalEndsARunStuckInAPluginCall) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", small_pipeline("", "{collisions_per_particle: 5}", 1000, 0.9,
                                                        "  - {plugin: temperature}\n  - {plugin: stuck_sample}\n"));
  Process p({"run", file.string(), "--quiet", "--plugin-path", gdsmc::test::test_plugin("stuck_sample").string()},
            dir.path());
  ASSERT_TRUE(p.wait_until_catches(SIGINT));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // now inside step 1's sample()
  p.send(SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto sent = Clock::now();
  p.send(SIGTERM);
  const ProcessResult r = p.wait(10);
  ASSERT_FALSE(r.timed_out) << "a second signal did not end a run stuck in a plugin call";
  EXPECT_LT(seconds_since(sent), 1.0);
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  EXPECT_TRUE(contains(r.err, "interrupted again; stopped at once, no output written")) << r.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{});
}

}  // namespace
}  // namespace gdsmc::test
