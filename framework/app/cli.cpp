#include "app/cli.hpp"

#include <cstdlib>

namespace gdsmc::host {

const std::vector<OptionSpec>& command_options(const std::string& command) {
  static const std::vector<OptionSpec> run = {{{"--help", "-h"}, ""},
                                              {{"--quiet", "-q"}, ""},
                                              {{"--set"}, "a value"},
                                              {{"--output", "-o"}, "a value"},
                                              {{"--plugin-path"}, "a value"},
                                              {{"--threads"}, "a number"},
                                              {{"--resume"}, ""},
                                              {{"--decompose"}, ""}};
  static const std::vector<OptionSpec> plugins = {{{"--help", "-h"}, ""}, {{"--plugin-path"}, "a value"}};
  static const std::vector<OptionSpec> plot = {{{"--help", "-h"}, ""}, {{"--out"}, "a directory"}};
  static const std::vector<OptionSpec> inspect = {{{"--help", "-h"}, ""}, {{"--long", "-l"}, ""}};
  static const std::vector<OptionSpec> none;
  if (command == "run" || command == "validate") return run;
  if (command == "plugins") return plugins;
  if (command == "plot") return plot;
  if (command == "inspect") return inspect;
  return none;
}

bool parse(const std::string& command, int argc, char** argv, int first, Options& o, std::string& error) {
  const std::vector<OptionSpec>& specs = command_options(command);
  Args args;
  if (!parse_args(argc, argv, first, specs, args, error)) return false;
  o.positional = args.positional;
  o.help = args.has("--help");
  o.quiet = args.has("--quiet");
  o.resume = args.has("--resume");
  o.decompose = args.has("--decompose");
  o.sets = args.all("--set");
  for (const auto& p : args.all("--plugin-path")) o.plugin_paths.emplace_back(p);
  if (args.has("--threads")) {
    const std::string& t = args.all("--threads").back();
    char* end = nullptr;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0' || v < 0 || v > 4096) {
      error = "--threads needs a whole number between 0 (every core) and 4096, got '" + t + "'";
      return false;
    }
    o.threads = static_cast<int>(v);
  }
  if (args.has("--output")) {
    o.output = args.all("--output").back();
    if (o.output.empty()) {
      error = "--output needs a file name, got an empty one";
      return false;
    }
  }
  return true;
}

}  // namespace gdsmc::host
