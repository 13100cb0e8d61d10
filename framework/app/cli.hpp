// The options of each gdsmc command (run, validate, plugins, plot, inspect), read with the one
// option parser of util/options.hpp.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "util/options.hpp"

namespace gdsmc::host {

// The options each of run, validate, plugins, plot and inspect accepts (`gdsmc conformance` has its own table in
// conformance/runner.cpp; `gdsmc help` takes none). run and validate accept the same options, so
// that a run's command line can be checked by changing the command word; plugins accepts only
// --plugin-path and --help; plot --out and --help; inspect --long and --help. The main help (app/main.cpp) lists every one of them, which
// tests/framework/app/cli_help_test.cpp checks against these tables. Returns an empty table for
// any other word.
const std::vector<OptionSpec>& command_options(const std::string& command);

// The options of run, validate and plugins.
struct Options {
  std::vector<std::string> positional, sets;
  std::vector<std::filesystem::path> plugin_paths;
  std::string output;
  bool quiet = false, help = false;
  bool resume = false;  // --resume: continue from the output's checkpoint (run only)
  bool decompose = false;  // --decompose: each slab run split over the MPI job's ranks by layers
  int threads = -1;  // --threads N (0: every core); -1: not given (run.threads decides)
};
// Parse the options of `command` (run, validate or plugins: command_options(command)).
bool parse(const std::string& command, int argc, char** argv, int first, Options& o, std::string& error);

}  // namespace gdsmc::host
