// gdsmc: the host executable. Reads a pipeline, loads the plugins it names, runs, writes HDF5.
// This file only dispatches to the subcommands (app/cmd_*.cpp, conformance/runner.cpp).
#include <hdf5.h>

#include <iostream>
#include <string>

#include <gdsmc/plugin.hpp>

#include "app/commands.hpp"
#include "conformance/conformance.hpp"
#include "study/ranks.hpp"

using namespace gdsmc;
using namespace gdsmc::host;

namespace {

// Every option of every command: tests/framework/app/cli_help_test.cpp checks this text against
// the option tables of the parsers (app/cli.cpp command_options, conformance/runner.cpp parse_config), each
// option inside its command's section (a section starts with a line "gdsmc COMMAND").
const char* kMainHelp = R"(gdsmc — Direct Simulation Monte Carlo of granular gases, with plugins.

Usage: gdsmc COMMAND [arguments] [options]     (options: "--name value" or "--name=value")

gdsmc run PIPELINE.yaml [options]
  Run a pipeline and write one HDF5 file (docs/user-guide.md, docs/output-format.md).
  --set key.path=value   override a pipeline value before checking it (repeatable), e.g.
                         --set collision.alpha=0.5  --set diagnostics[1].record_every=40
  -o, --output FILE      write to FILE instead of the pipeline's output.file
  -q, --quiet            no progress and no summary (errors are still printed)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --threads N            runs (cases x realizations) at once (default: every core); the output
                         is the same bits for any N
  --resume               continue the run from its checkpoint (<output>.checkpoint/, written
                         when the pipeline sets run.checkpoint); the output is the same bits
  --decompose            under mpirun: split each slab run over the ranks by layers instead
                         of spreading the runs; the output is the same bits at any rank count
  -h, --help             the help of `run`

gdsmc validate PIPELINE.yaml [options]
  Check a pipeline and every plugin parameter without running it, and estimate the memory it
  needs (refused when it cannot fit). Takes the options of `run`, so that a run's command line
  can be checked by changing the command word:
  --set key.path=value   override a pipeline value before checking it (repeatable)
  -o, --output FILE      the output file the verdict names (nothing is written)
  -q, --quiet            as for run: no progress lines (validate prints its verdict and problems)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --threads N            the runs at once the memory estimate assumes
  --resume               also check that the checkpoint beside the output belongs to this
                         pipeline, gdsmc and plugins, read every file of it as run --resume
                         would, and say how many runs it holds
  --decompose            also refuse what run --decompose would not split over the ranks
  -h, --help             the help of `validate`

gdsmc plugins [NAME | FILE.so]... [options]
  List the plugins found, by kind; or document the ones named, with every parameter.
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  -h, --help             the help of `plugins`

gdsmc conformance PLUGIN.so [options]
  Check a plugin binary against the contract of its kind, one line per check.
  --params FILE.yaml     parameter values for the plugin (a mapping name: value)
  --context FILE.yaml    a pipeline whose initial state, collision rule, forcings, system and
                         boundaries surround the plugin
  --seed N               seed of every random input (default 1); a failure names it
  --only CHECK           run only CHECK (a name or a prefix; repeatable, comma-separated)
  --plugin-path P        more plugin directories or files (for the context's plugins)
  --list                 list the checks that apply to the plugin and exit
  --no-fork              run the checks in this process (for a debugger)
  --timeout S            seconds allowed per check (default 120)
  -h, --help             the help of `conformance`: every check, by kind

gdsmc plot OUTPUT.h5 [options]
  Draw every diagnostic of an output file, one PNG per figure (series with their error bands,
  profiles, histograms, sweep summaries, theory lines); prints each file written. Python 3 with
  the Debian packages python3-h5py, python3-numpy, python3-matplotlib.
  --out DIR              the directory of the PNGs (default OUTPUT_plots/ beside OUTPUT.h5)
  -h, --help             the help of `plot`

gdsmc inspect OUTPUT.h5 [options]
  Print an output file's provenance (version, pipeline, seed, overrides, plugins) and every
  dataset with its shape and unit.
  -l, --long             also the whole pipeline text and each dataset's description
  -h, --help             the help of `inspect`

gdsmc help [COMMAND]
  This text, or the help of COMMAND (run, validate, plugins, conformance, plot, inspect).
  No options.

gdsmc --version          the release, the plugin SDK ABI and the build options (MPI, build
                         type, compiler, HDF5); CITATION.cff says how to cite gdsmc; MPI runs:
                         `mpirun -np K gdsmc run` (docs/cluster.md)
gdsmc --help, -h         this text

Plugins are shared libraries found on the search path: --plugin-path entries, the pipeline's
`plugins:` list, $GDSMC_PLUGIN_PATH (colon-separated), then the plugins installed with gdsmc.
The documentation is installed in <prefix>/share/doc/gdsmc/ (user-guide.md, output-format.md,
references.md, plugin-author-guide.md and examples/, one plugin project of each kind).

Exit status: 0 success, 1 invalid input or failed run (nothing written), 2 bad command line,
130 interrupted (nothing written). A failure of output.plots is a warning: the run exits 0.
)";

// `gdsmc --version`: what a bug report or a methods section needs to name this build.
std::string version_text() {
  std::string s = std::string("gdsmc ") + version_string + "\n";
  s += "SDK ABI " + std::to_string(sdk_abi_major) + "." + std::to_string(sdk_abi_minor) + " (plugins must be built against it)\n";
  const std::string mpi = job::build_text();  // "with MPI (<library>)" or "without MPI"
  s += std::string("MPI: ") + (mpi.rfind("with ", 0) == 0 ? "yes, built " : "no, built ") + mpi + "\n";
#if defined(__OPTIMIZE__) && defined(NDEBUG)
  s += "build: optimized, assertions off\n";
#elif defined(__OPTIMIZE__)
  s += "build: optimized, assertions on\n";
#else
  s += "build: not optimized (debug), assertions on\n";
#endif
#if defined(__clang__)
  s += std::string("compiler: clang ") + __clang_version__ + "\n";
#elif defined(__GNUC__)
  s += std::string("compiler: g++ ") + __VERSION__ + "\n";
#endif
  s += "HDF5: " + std::to_string(H5_VERS_MAJOR) + "." + std::to_string(H5_VERS_MINOR) + "." +
       std::to_string(H5_VERS_RELEASE) + "\n";
  s += "cite: CITATION.cff of the gdsmc sources; the papers it reproduces: references.md (<prefix>/share/doc/gdsmc/)\n";
  return s;
}

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
    std::cout << version_text();
    return 0;
  }
  if (cmd == "help") {
    const std::string topic = argc > 2 ? argv[2] : "";
    if (argc > 3) return usage_error("help takes one COMMAND");
    if (topic == "conformance") {
      char name[] = "conformance", help[] = "--help";
      char* args[] = {name, help, nullptr};
      return run_conformance(2, args);
    }
    if (!topic.empty() && topic != "run" && topic != "validate" && topic != "plugins" && topic != "plot" &&
        topic != "inspect" && topic != "help")
      return usage_error("help: unknown command '" + topic + "'");
    std::cout << (topic == "run"        ? kRunHelp
                  : topic == "validate" ? kValidateHelp
                  : topic == "plugins"  ? kPluginsHelp
                  : topic == "plot"     ? kPlotHelp
                  : topic == "inspect"  ? kInspectHelp
                                        : kMainHelp);
    return 0;
  }
  if (cmd == "conformance") return run_conformance(argc - 1, argv + 1);
  if (cmd == "plot") return cmd_plot(argc, argv);
  if (cmd == "inspect") return cmd_inspect(argc, argv);
  if (cmd != "run" && cmd != "validate" && cmd != "plugins") return usage_error("unknown command '" + cmd + "'");
  Options o;
  std::string error;
  if (!parse(cmd, argc, argv, 2, o, error)) return usage_error(cmd + ": " + error);
  try {
    if (cmd == "run") {
      if (o.help) return std::cout << kRunHelp, 0;
      const job::Session mpi;  // MPI, when mpirun (or srun) started this process
      return cmd_run(o, true);
    }
    if (cmd == "validate") {
      if (o.help) return std::cout << kValidateHelp, 0;
      if (job::launcher_rank() > 0) return 0;  // under mpirun the pipeline is checked once, by rank 0
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
