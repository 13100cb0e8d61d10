// gdsmc: the host executable. Reads a pipeline, loads the plugins it names, runs, writes HDF5.
// This file only dispatches to the subcommands (app/cmd_*.cpp, conformance/runner.cpp).
#include <iostream>
#include <string>

#include <gdsmc/plugin.hpp>

#include "app/commands.hpp"
#include "conformance/conformance.hpp"

using namespace gdsmc;
using namespace gdsmc::host;

namespace {

const char* kMainHelp = R"(gdsmc — Direct Simulation Monte Carlo of granular gases, with plugins.

Usage:
  gdsmc run PIPELINE.yaml [--set key.path=value]... [--output FILE] [--quiet] [--plugin-path P]...
  gdsmc validate PIPELINE.yaml [--set key.path=value]... [--plugin-path P]...
  gdsmc plugins [NAME | FILE.so]... [--plugin-path P]...
  gdsmc conformance PLUGIN.so [--params FILE.yaml] [--seed N] [--only CHECK]...
  gdsmc help [COMMAND]        (or COMMAND --help)
  gdsmc --version

Commands:
  run        run a pipeline and write one HDF5 file (docs/user-guide.md describes both)
  validate   check a pipeline and every plugin parameter without running it
  plugins    list the plugins found, or document the ones named
  conformance  check a plugin binary against the contract of its kind (`gdsmc conformance --help`)

Plugins are shared libraries found on the search path: --plugin-path entries, the pipeline's
`plugins:` list, $GDSMC_PLUGIN_PATH (colon-separated), then the plugins installed with gdsmc.

Exit status: 0 success, 1 invalid input or failed run (nothing written), 2 bad command line,
130 interrupted (nothing written).
)";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cout << kMainHelp;
    return 2;
  }
  const std::string cmd = argv[1];
  if (cmd == "--help" || cmd == "-h") {
    std::cout << kMainHelp;
    return 0;
  }
  if (cmd == "--version") {
    std::cout << "gdsmc " << version_string << " (SDK ABI " << sdk_abi_major << "." << sdk_abi_minor << ")\n";
    return 0;
  }
  if (cmd == "help") {
    const std::string topic = argc > 2 ? argv[2] : "";
    std::cout << (topic == "run" ? kRunHelp : topic == "validate" ? kValidateHelp : topic == "plugins" ? kPluginsHelp : kMainHelp);
    return 0;
  }
  if (cmd == "conformance") return run_conformance(argc - 1, argv + 1);
  Options o;
  std::string error;
  if (!parse(argc, argv, 2, o, error)) return usage_error(error);
  try {
    if (cmd == "run") {
      if (o.help) return std::cout << kRunHelp, 0;
      return cmd_run(o, true);
    }
    if (cmd == "validate") {
      if (o.help) return std::cout << kValidateHelp, 0;
      return cmd_run(o, false);
    }
    if (cmd == "plugins") {
      if (o.help) return std::cout << kPluginsHelp, 0;
      return cmd_plugins(o);
    }
  } catch (const std::exception& e) {
    std::cerr << "gdsmc: error: " << e.what() << "\n";
    return 1;
  }
  return usage_error("unknown command '" + cmd + "'");
}
