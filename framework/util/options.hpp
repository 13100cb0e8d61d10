// The one command-line option parser of gdsmc: `run`, `validate`, `plugins`, `plot`, `inspect` and
// `conformance` all read their options through parse_args, with the same rules ("--name value" or
// "--name=value"; a flag takes no value; any other word starting with '-' is an error).
#pragma once
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

}  // namespace gdsmc::host
