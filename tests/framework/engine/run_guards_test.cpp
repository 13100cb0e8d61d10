// The engine's guards during a run: a step too large for the collisions and a stop time out of
// reach are refused at the step they are found, naming it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "test_support.hpp"

namespace gdsmc::test {
namespace {

using Clock = std::chrono::steady_clock;

// The engine's guards during a run (values that validation would refuse, set after loading, stand
// for a run whose temperature has drifted far from T0).

// Sets *flag after `seconds` unless stopped first: the old behaviour (running on) then ends in
// Interrupted instead of hanging the test.
class Watchdog {
 public:
  Watchdog(std::atomic<bool>& flag, double seconds)
      : thread_([this, &flag, seconds] {
          const auto start = Clock::now();
          while (!stop_ && seconds_since(start) < seconds) std::this_thread::sleep_for(std::chrono::milliseconds(5));
          if (!stop_) flag = true;
        }) {}
  ~Watchdog() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(RunGuards, AStepTooLargeForTheCollisionsIsRefusedDuringTheRun) {
  TempDir dir;
  host::Pipeline p = gdsmc::test::load_yaml(dir, small_pipeline());
  p.time_step_tau0 = 60;  // ~127 candidates per particle per step
  p.time_step_follows_temperature = false;
  host::Engine engine(p);
  try {
    engine.run();
    ADD_FAILURE() << "the run was not refused";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "at step 0 (t = 0 tau0, T/T0 = ")) << m;
    EXPECT_TRUE(contains(m, "), with dt = 60 tau0: the collision stage would test about ")) << m;
    EXPECT_TRUE(contains(m, "use a smaller run.time_step or run.time_step.follow_temperature: true")) << m;
  }
}

TEST(RunGuards, AStopTimeOutOfReachIsRefusedDuringTheRun) {
  TempDir dir;
  host::Pipeline p = gdsmc::test::load_yaml(dir, small_pipeline("", "{time: 1}"));
  p.time_step_tau0 = 1e-13;
  p.time_step_follows_temperature = false;
  host::Engine engine(p);
  std::atomic<bool> flag{false};
  Watchdog watchdog(flag, 10);
  try {
    engine.run({}, 1.0, &flag);
    ADD_FAILURE() << "the run ended";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "at step 0 (t = 0 tau0, T/T0 = ")) << e.what();
    EXPECT_TRUE(contains(e.what(), ": the stop time 1 tau0 is 1e+13 steps of dt = 1e-13 tau0 away (more than 1e+12)"))
        << e.what();
  }
}

}  // namespace
}  // namespace gdsmc::test
