// The one command-line option parser of gdsmc: `run`, `validate`, `plugins` and `conformance`
// all read their options through parse_args, with the same rules ("--name value" or
// "--name=value"; a flag takes no value; any other word starting with '-' is an error).
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gdsmc::host {

struct OptionSpec {
  std::vector<std::string> names;  // e.g. {"--output", "-o"}; values are filed under names[0]
  std::string needs;               // what the value is ("a value", "a file"); empty for a flag
};

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> values;  // by the option's first name; flags get ""

  bool has(const std::string& name) const { return values.count(name) != 0; }
  const std::vector<std::string>& all(const std::string& name) const;
};

// Parse argv[first..argc). Returns false with `error` set ("--set needs a value",
// "unknown option '--x'").
bool parse_args(int argc, char** argv, int first, const std::vector<OptionSpec>& specs, Args& out, std::string& error);

// The options each of run, validate, plugins, plot and inspect accepts (`gdsmc conformance` has its own table in
// conformance/runner.cpp; `gdsmc help` takes none). run and validate accept the same options, so
// that a run's command line can be checked by changing the command word; plugins accepts only
// --plugin-path and --help; plot --out and --help; inspect --long and --help. The main help (app/main.cpp) lists every one of them, which
// tests/cli_help_test.cpp checks against these tables. Returns an empty table for any other word.
const std::vector<OptionSpec>& command_options(const std::string& command);

// The options of run, validate and plugins.
struct Options {
  std::vector<std::string> positional, sets;
  std::vector<std::filesystem::path> plugin_paths;
  std::string output;
  bool quiet = false, help = false;
  bool resume = false;  // --resume: continue from the output's checkpoint (run only)
  int threads = -1;  // --threads N (0: every core); -1: not given (run.threads decides)
};
// Parse the options of `command` (run, validate or plugins: command_options(command)).
bool parse(const std::string& command, int argc, char** argv, int first, Options& o, std::string& error);

}  // namespace gdsmc::host
