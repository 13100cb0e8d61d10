// gdsmc: the host executable. Reads a pipeline, loads the plugins it names, runs, writes HDF5.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "conformance.hpp"
#include "engine.hpp"
#include "loader.hpp"
#include "pipeline.hpp"
#include "study.hpp"

namespace fs = std::filesystem;
using namespace gdsmc;
using namespace gdsmc::host;

namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) { g_interrupted.store(true); }

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

const char* kRunHelp = R"(gdsmc run PIPELINE.yaml [options]

Runs the pipeline and writes one HDF5 file (the pipeline's output.file, default
<pipeline name>.h5 in the current directory). The file is written under a temporary name and
renamed when complete: a failed or interrupted run leaves nothing under the final name.

Options:
  --set key.path=value   override a pipeline value before checking it, e.g.
                         --set collision.alpha=0.5  --set run.particles=20000
                         --set diagnostics[1].average_after=5 (lists by index)
  --output FILE          write to FILE instead of output.file
  --quiet                no progress and no summary (errors are still printed)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)

Progress (s, t/tau0, T/T0, time left) goes to stderr: one refreshed line on a terminal,
a plain line every 10 s otherwise. The summary after the run goes to stdout.
)";

const char* kValidateHelp = R"(gdsmc validate PIPELINE.yaml [--set key.path=value]... [--plugin-path P]...

Checks the pipeline without running it: YAML syntax, every key, every plugin and parameter
(type, range, unit), and that every plugin accepts its parameters and sets up (the initial state
is generated). Every problem is reported with file:line:column. Exit 0 when valid, 1 otherwise.
)";

const char* kPluginsHelp = R"(gdsmc plugins [NAME | FILE.so]... [--plugin-path P]...

Without arguments: every plugin found on the search path, by kind, with its version and a
one-line summary, and any file on the path that could not be loaded (and why).
With names or .so files: the full documentation of each, and every parameter with its type,
default, range and unit. A .so file is loaded and checked (ABI version, descriptor) first.
)";

int usage_error(const std::string& message) {
  std::cerr << "gdsmc: " << message << "\n(see `gdsmc --help`)\n";
  return 2;
}

void print_errors(const std::vector<std::string>& messages) {
  for (const auto& m : messages) std::cerr << "error: " << m << "\n";
  std::cerr << "gdsmc: " << messages.size() << (messages.size() == 1 ? " error" : " errors") << "; nothing was run or written\n";
}

struct Options {
  std::vector<std::string> positional, sets;
  std::vector<fs::path> plugin_paths;
  std::string output;
  bool quiet = false, help = false;
};

bool parse(int argc, char** argv, int first, Options& o, std::string& error) {
  for (int k = first; k < argc; ++k) {
    const std::string a = argv[k];
    auto value = [&](std::string& into) {
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        into = a.substr(eq + 1);
        return true;
      }
      if (k + 1 >= argc) {
        error = a + " needs a value";
        return false;
      }
      into = argv[++k];
      return true;
    };
    std::string v;
    if (a == "--help" || a == "-h") o.help = true;
    else if (a == "--quiet" || a == "-q") o.quiet = true;
    else if (a.rfind("--set", 0) == 0) { if (!value(v)) return false; o.sets.push_back(v); }
    else if (a.rfind("--output", 0) == 0 || a == "-o") { if (!value(v)) return false; o.output = v; }
    else if (a.rfind("--plugin-path", 0) == 0) { if (!value(v)) return false; o.plugin_paths.emplace_back(v); }
    else if (a.size() > 1 && a[0] == '-') { error = "unknown option '" + a + "'"; return false; }
    else o.positional.push_back(a);
  }
  return true;
}

std::string format_seconds(double s) {
  char buf[64];
  if (s < 0) return "?";
  if (s < 90) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 5400) std::snprintf(buf, sizeof buf, "%.0fm%02.0fs", std::floor(s / 60), std::fmod(s, 60.0));
  else std::snprintf(buf, sizeof buf, "%.1fh", s / 3600);
  return buf;
}

int cmd_run(const Options& o, bool run_it) {
  if (o.positional.size() != 1) return usage_error(std::string(run_it ? "run" : "validate") + " takes one PIPELINE.yaml");
  const fs::path file = o.positional[0];
  Pipeline p;
  try {
    p = load_pipeline(file, o.sets, o.plugin_paths);
  } catch (const PipelineError& e) {
    print_errors(e.messages());
    return 1;
  }
  if (!o.output.empty()) p.output_file = o.output;
  if (run_it) {
    const fs::path dir = fs::absolute(p.output_file).parent_path();
    if (!fs::is_directory(dir)) {
      print_errors({"output file " + p.output_file.string() + ": the directory " + dir.string() + " does not exist"});
      return 1;
    }
  }
  std::vector<StudyCase> cases;
  try {
    cases = expand_cases(p, o.sets, o.plugin_paths);
    // Set every case up once (plugins construct, diagnostics begin) before anything runs.
    for (const auto& c : cases) Engine check(c.pipeline, 0);
  } catch (const PipelineError& e) {
    print_errors(e.messages());
    return 1;
  } catch (const std::exception& e) {
    print_errors({p.file.string() + ": " + e.what()});
    return 1;
  }
  if (!run_it) {
    std::cout << p.file.string() << ": valid (" << cases.size() << (cases.size() == 1 ? " case" : " cases") << " x "
              << p.realizations << (p.realizations == 1 ? " realization" : " realizations") << "; " << p.particles
              << " particles; " << p.diagnostics.size() << " diagnostics; output " << p.output_file.string() << ")\n";
    return 0;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const bool tty = ::isatty(STDERR_FILENO);
  std::function<void(const StudyProgress&)> report;
  if (!o.quiet) {
    report = [tty](const StudyProgress& sp) {
      const Progress& pr = sp.progress;
      char line[384];
      std::string run = sp.runs > 1 ? "run " + std::to_string(sp.run + 1) + "/" + std::to_string(sp.runs) + " " : "";
      if (!sp.label.empty()) run += "(" + sp.label + ") ";
      std::snprintf(line, sizeof line, "[%3.0f%%] %ss = %-8.4g t = %-9.4g tau0  T/T0 = %-10.4g elapsed %s, left ~%s",
                    100 * sp.fraction, run.c_str(), pr.collisions_per_particle, pr.time_tau0, pr.temperature_over_T0,
                    format_seconds(pr.elapsed_seconds).c_str(), format_seconds(sp.remaining_seconds).c_str());
      if (tty) std::cerr << "\r" << line << "\033[K" << std::flush;
      else std::cerr << line << "\n";
    };
  }
  StudyResult result;
  try {
    result = run_study(cases, report, tty ? 0.25 : 10.0, &g_interrupted);
    if (report && tty) std::cerr << "\n";
    write_hdf5(p.output_file, result.output);
  } catch (const Engine::Interrupted&) {
    if (report && tty) std::cerr << "\n";
    std::cerr << "gdsmc: interrupted; no output written\n";
    return 130;
  } catch (const std::exception& e) {
    if (report && tty) std::cerr << "\n";
    print_errors({p.file.string() + ": " + e.what()});
    return 1;
  }
  if (!o.quiet) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "gdsmc: %s: %zu case(s) x %u realization(s), %llu steps, %.4g collisions in %.2f s (%.3g collisions/s)",
                  p.file.filename().c_str(), cases.size(), p.realizations, static_cast<unsigned long long>(result.steps),
                  result.collisions, result.wall_seconds, result.wall_seconds > 0 ? result.collisions / result.wall_seconds : 0.0);
    std::cout << buf << "\n";
    for (const auto& line : result.summary) std::cout << line << "\n";
    std::cout << "output: " << fs::absolute(p.output_file).string() << "\n";
  }
  return 0;
}

void print_plugin_doc(const LoadedPlugin& lp) {
  const PluginDescriptor& d = *lp.descriptor;
  std::cout << d.name << " (" << to_string(d.kind) << " plugin, version " << d.version << ", SDK ABI " << lp.abi_major
            << "." << lp.abi_minor << ")\n  file: " << lp.file.string() << "\n  " << d.summary << "\n\n";
  std::string doc = d.documentation;
  std::size_t start = 0;
  while (start < doc.size()) {
    const auto end = doc.find('\n', start);
    std::cout << "  " << doc.substr(start, end == std::string::npos ? std::string::npos : end - start) << "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  std::cout << "\n  parameters:" << (d.parameters.empty() ? " none" : "") << "\n";
  for (const auto& s : d.parameters) {
    std::cout << "    " << s.name << " (" << to_string(s.type) << ")";
    if (s.default_) std::cout << "  default " << value_text(*s.default_);
    else std::cout << "  required";
    const std::string r = s.range_text();
    if (!r.empty()) std::cout << "  range " << r;
    if (s.dimension != Dimension::none) std::cout << "  unit " << to_string(s.dimension);
    std::cout << "\n        " << s.doc << "\n";
  }
  if (d.kind == PluginKind::diagnostic)
    std::cout << "    (every diagnostic also takes: name, sample_every, record_every)\n";
  std::cout << "\n";
}

int cmd_plugins(const Options& o) {
  PluginRegistry reg;
  std::vector<std::string> errors;
  for (const auto& pth : o.plugin_paths) {
    try { reg.add(pth); } catch (const PluginLoadError& e) { errors.push_back(e.what()); }
  }
  for (const auto& pth : PluginRegistry::default_search_path()) reg.add(pth);
  if (o.positional.empty()) {
    for (auto kind : {PluginKind::collision_rule, PluginKind::forcing, PluginKind::boundary, PluginKind::initial_state,
                      PluginKind::diagnostic}) {
      std::cout << to_string(kind) << ":\n";
      bool any = false;
      for (const auto& lp : reg.plugins())
        if (lp.descriptor->kind == kind) {
          any = true;
          char buf[512];
          std::snprintf(buf, sizeof buf, "  %-32s %-8s %s", lp.descriptor->name.c_str(), lp.descriptor->version.c_str(),
                        lp.descriptor->summary.c_str());
          std::cout << buf << "\n";
        }
      if (!any) std::cout << "  (none)\n";
    }
    std::cout << "\n`gdsmc plugins NAME` documents a plugin and its parameters.\n";
    for (const auto& w : reg.warnings()) std::cerr << "warning: " << w << "\n";
    for (const auto& e : errors) std::cerr << "error: " << e << "\n";
    return errors.empty() ? 0 : 1;
  }
  int status = errors.empty() ? 0 : 1;
  for (const auto& e : errors) std::cerr << "error: " << e << "\n";
  for (const auto& name : o.positional) {
    if (name.size() > 3 && name.substr(name.size() - 3) == ".so") {
      try {
        const LoadedPlugin lp = load_plugin(name);
        print_plugin_doc(lp);
      } catch (const PluginLoadError& e) {
        std::cerr << "error: " << e.what() << "\n";
        status = 1;
      }
      continue;
    }
    if (const LoadedPlugin* lp = reg.find(name)) {
      print_plugin_doc(*lp);
    } else {
      auto close = closest_names(name, reg.names());
      std::string hint;
      for (const auto& c : close) hint += (hint.empty() ? "" : ", ") + c;
      std::cerr << "error: no plugin named '" << name << "'" << (hint.empty() ? "" : "; did you mean " + hint + "?")
                << " (`gdsmc plugins` lists them)\n";
      status = 1;
    }
  }
  return status;
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
