// Test support: a pipeline the gdsmc executable must refuse, run in a directory of its own.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/process.hpp"

namespace gdsmc::test {

struct Refusal {
  ProcessResult result;
  std::string file;  // the pipeline path as given on the command line
  std::string text;  // the pipeline
};

// Runs `gdsmc COMMAND pipeline.yaml [extra]` in a fresh directory holding only the pipeline, and
// checks the refusal: exit status 1, no crash, and nothing but the pipeline left in the directory.
inline Refusal refuse(const std::string& yaml, const std::vector<std::string>& extra = {},
                      const std::string& command = "run") {
  TempDir dir;
  Refusal r;
  r.text = yaml;
  r.file = dir.write("pipeline.yaml", yaml).string();
  std::vector<std::string> args = {command, r.file};
  args.insert(args.end(), extra.begin(), extra.end());
  r.result = run_gdsmc(args, dir.path());
  EXPECT_EQ(r.result.exit_code, 1) << command << "\n" << r.result.describe();
  EXPECT_EQ(r.result.signal, 0) << r.result.describe();
  EXPECT_EQ(dir.entries_except({"pipeline.yaml"}), std::vector<std::string>{}) << "a refused run left files behind";
  return r;
}

}  // namespace gdsmc::test
