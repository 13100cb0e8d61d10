// The progress report of a run without a terminal, and the time left as a short text
// (app/progress.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "app/progress.hpp"
#include "test_support.hpp"

namespace gdsmc::test {
namespace {

// Without a terminal, progress is a line every 10 s for the whole study, not one per realization.
TEST(Progress, ProgressWithoutATerminalIsNotALinePerRealization) {
  const Outcome o = gdsmc_in_dir("run", small_pipeline("  realizations: 300\n", "{collisions_per_particle: 0.2}", 50), {});
  ASSERT_EQ(o.result.exit_code, 0) << o.result.describe();
  int lines = 0;
  for (std::size_t pos = 0; (pos = o.result.err.find("[", pos)) != std::string::npos; ++pos)
    if (pos == 0 || o.result.err[pos - 1] == '\n') ++lines;
  EXPECT_LE(lines, 2) << o.result.err.substr(0, 2000);
}

// The time left, however large (an estimate from a tiny fraction done, a stop out of reach), is a
// short text.
TEST(Progress, TimeLeftIsShortHoweverLarge) {
  EXPECT_EQ(host::format_seconds(42), "42s");
  EXPECT_EQ(host::format_seconds(5399.7), "90m00s");
  EXPECT_EQ(host::format_seconds(7200), "2.0h");
  EXPECT_EQ(host::format_seconds(3 * 86400.0), "3d");
  EXPECT_EQ(host::format_seconds(1e65), ">1000d");
  EXPECT_EQ(host::format_seconds(HUGE_VAL), ">1000d");
  EXPECT_EQ(host::format_seconds(std::nan("")), "?");
  EXPECT_EQ(host::format_seconds(-1), "?");
}

}  // namespace
}  // namespace gdsmc::test
