// The subcommands of the gdsmc executable (main.cpp dispatches to them) and their help texts.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/cli.hpp"

namespace gdsmc::host {

extern const char* const kRunHelp;
extern const char* const kValidateHelp;
extern const char* const kPluginsHelp;
extern const char* const kPlotHelp;
extern const char* const kInspectHelp;

// `run` (run_it) or `validate`. Returns the exit status.
int cmd_run(const Options& o, bool run_it);
// `plugins`: list, or document the plugins named.
int cmd_plugins(const Options& o);

// `plot OUTPUT.h5 [--out DIR]`: replaces this process with the plotter (app/cmd_plot.cpp); argv is
// the executable's (argv[1] == "plot"). Returns only on an error.
int cmd_plot(int argc, char** argv);
// Runs the plotter on `output` (PNGs in <output>_plots/) and waits for it; quiet: its list of files
// is not printed. False with `error` set when it cannot run or fails (output.plots: true).
bool plot_output(const std::filesystem::path& output, bool quiet, std::string& error);
// `inspect OUTPUT.h5 [--long]`: provenance and datasets (app/cmd_inspect.cpp).
int cmd_inspect(int argc, char** argv);

// "gdsmc: message" and a pointer to --help on stderr; returns 2.
int usage_error(const std::string& message);
// Every message as "error: ..." and a count on stderr.
void print_errors(const std::vector<std::string>& messages);
// Every message as "warning: ..." on stderr.
void print_warnings(const std::vector<std::string>& messages);

}  // namespace gdsmc::host
