// `gdsmc plot`: runs the plotter, scripts/gdsmc_plot.py (Python 3 with h5py, numpy, matplotlib),
// which the build copies beside the executable and `cmake --install` puts in share/gdsmc/.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

#include "app/commands.hpp"
#include "util/subprocess.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

const char* const kPlotHelp = R"(gdsmc plot OUTPUT.h5 [options]

Draws every diagnostic of a gdsmc output file, one PNG per figure, and prints the path of each
file written:
  - time series against t/tau0 and against s (collisions per particle), with the band of one
    standard error over realizations (<series>_stderr), each realization's own series when the
    file has them (output.realizations), and the steady mean over its averaging window;
  - profiles against y (a few records, and the steady profile);
  - histograms as steps over their edges (with their _stderr as error bars);
  - other arrays: a 1-D one against the grid it declares (its attribute axis, OutputSink::axis:
    a profile's bin centres, a theory curve's alpha grid), else against its index; the scalars of
    each diagnostic as a table;
  - a sweep: every case's diagnostics (files case<k>-...), and every quantity of /summary against
    the swept parameter, with its error bars (files summary-...).
Theory a diagnostic wrote (a dataset with the attributes role = "theory", theory_of and equation;
e.g. temperature_haff with theory_of = temperature) is drawn as lines on the figures of the
measured quantities named by theory_of, or on its own figure when it names none. Axis labels give
the units of the datasets' `unit` attributes.

Options:
  --out DIR              write the PNG files in DIR (default: OUTPUT_plots/ beside OUTPUT.h5,
                         OUTPUT being the file name without .h5); created if missing
  -h, --help             this text

The plotter is gdsmc_plot.py, beside the gdsmc executable (a build tree) or in
<prefix>/share/gdsmc/ (an installation), run with /usr/bin/python3; it needs the Debian packages
python3-h5py, python3-numpy and python3-matplotlib (scripts/install-deps installs them). A
pipeline with `output: {plots: true}` runs it after a successful run.
Exit status: 0 drawn, 1 not a gdsmc output file (or a missing package), 2 bad command line.
)";

namespace {

constexpr const char* kPython = "/usr/bin/python3";

// The plotter beside the executable (build tree), else in <prefix>/share/gdsmc (installed).
fs::path plot_script() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  for (const fs::path& candidate : {dir / "gdsmc_plot.py", dir.parent_path() / "share" / "gdsmc" / "gdsmc_plot.py"})
    if (fs::is_regular_file(candidate, ec)) return candidate;
  return {};
}

// The plotter's command line, or an error message.
bool plot_command(const fs::path& output, const std::string& out_dir, std::vector<std::string>& argv, std::string& error) {
  const fs::path script = plot_script();
  if (script.empty()) {
    error = "cannot find the plotter gdsmc_plot.py beside the gdsmc executable or in <prefix>/share/gdsmc/ "
            "(build gdsmc again, or install it with `cmake --install`)";
    return false;
  }
  if (::access(kPython, X_OK) != 0) {
    error = std::string("plotting needs ") + kPython +
            ": install the Debian packages python3, python3-h5py, python3-numpy and python3-matplotlib";
    return false;
  }
  argv = {kPython, script.string(), output.string()};
  if (!out_dir.empty()) argv.insert(argv.end(), {"--out", out_dir});
  return true;
}

std::vector<char*> c_argv(std::vector<std::string>& args) {
  std::vector<char*> v;
  for (auto& a : args) v.push_back(a.data());
  v.push_back(nullptr);
  return v;
}

}  // namespace

int cmd_plot(int argc, char** argv) {
  Args args;
  std::string error;
  if (!parse_args(argc, argv, 2, command_options("plot"), args, error)) return usage_error("plot: " + error);
  if (args.has("--help")) return std::cout << kPlotHelp, 0;
  if (args.positional.size() != 1) return usage_error("plot takes one OUTPUT.h5 (a file written by `gdsmc run`)");
  const std::string out_dir = args.has("--out") ? args.all("--out").back() : "";
  if (args.has("--out") && out_dir.empty()) return usage_error("plot: --out needs a directory, got an empty name");
  std::vector<std::string> command;
  if (!plot_command(args.positional[0], out_dir, command, error)) {
    std::cerr << "gdsmc plot: " << error << "\n";
    return 1;
  }
  std::vector<char*> cargv = c_argv(command);
  std::cout.flush();
  ::execv(cargv[0], cargv.data());
  std::cerr << "gdsmc plot: cannot run " << command[0] << ": " << std::strerror(errno) << "\n";
  return 1;
}

bool plot_output(const fs::path& output, bool quiet, std::string& error) {
  std::vector<std::string> command;
  if (!plot_command(output, "", command, error)) return false;
  SubprocessOptions options;
  if (quiet) options.stdout_file = "/dev/null";
  ExitStatus status;
  try {
    Subprocess plotter(command, options);
    status = plotter.wait();
  } catch (const std::system_error& e) {
    error = "cannot start the plotter: " + e.code().message();
    return false;
  }
  if (status.exit_code == 0) return true;
  error = "the plotter (" + command[1] + ") " + status.text();
  return false;
}

}  // namespace gdsmc::host
