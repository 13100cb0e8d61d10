// `gdsmc run` and `gdsmc validate`.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "app/commands.hpp"
#include "app/progress.hpp"
#include "output/hdf5_file.hpp"
#include "study/study.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

const char* const kRunHelp = R"(gdsmc run PIPELINE.yaml [options]

Runs the pipeline and writes one HDF5 file (the pipeline's output.file, default
<pipeline name>.h5 in the current directory). The file is written under a temporary name and
renamed when complete: a failed or interrupted run leaves nothing under the final name.

Options:
  --set key.path=value   override a pipeline value before checking it, e.g.
                         --set collision.alpha=0.5  --set run.particles=20000
                         --set diagnostics[1].record_every=40 (lists by index)
                         --set boundaries.y_min.temperature=2
  -o, --output FILE      write to FILE instead of output.file
  -q, --quiet            no progress and no summary (errors are still printed)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  -h, --help             this text

Progress (s, t/tau0, T/T0, time left) goes to stderr: one refreshed line on a terminal,
a plain line every 10 s otherwise. The summary after the run goes to stdout.

Before anything runs, the pipeline is checked as `validate` checks it, the memory the study needs
is estimated and the run is refused when it cannot fit in the memory available (see validate).
)";

const char* const kValidateHelp = R"(gdsmc validate PIPELINE.yaml [options]

Checks the pipeline without running it: YAML syntax, every key, every plugin and parameter
(type, range, unit), and that every plugin accepts its parameters and sets up (every plugin
object is constructed and every diagnostic begins; no particles are allocated and the initial
state is not generated, so a large N is checked as quickly as a small one). Every problem is
reported with file:line:column. Exit 0 when valid, 1 otherwise. Plugin files on the search path
that could not be loaded (and are therefore shadowed or missing) are reported as warnings.

The verdict gives the memory the study is estimated to need (particles, attributes, every
diagnostic's records, what each sweep case keeps until the file is written); a study that needs
more than is available (the smaller of MemAvailable and what ulimit -v / -d leave) is refused
with both figures. The pipeline file must be a regular file of at most 16 MiB. Checking a sweep
that takes more than 2 s prints its progress on stderr every 2 s.

Options (those of `run`, so that a run's command line can be checked by changing the command):
  --set key.path=value   override a pipeline value before checking it (repeatable)
  -o, --output FILE      the output file the verdict names (nothing is written)
  -q, --quiet            as for run: no progress lines (validate prints its verdict and problems)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  -h, --help             this text
)";

int usage_error(const std::string& message) {
  std::cerr << "gdsmc: " << message << "\n(see `gdsmc --help`)\n";
  return 2;
}

void print_errors(const std::vector<std::string>& messages) {
  for (const auto& m : messages) std::cerr << "error: " << m << "\n";
  std::cerr << "gdsmc: " << messages.size() << (messages.size() == 1 ? " error" : " errors") << "; nothing was run or written\n";
}

void print_warnings(const std::vector<std::string>& messages) {
  for (const auto& m : messages) std::cerr << "warning: " << m << "\n";
}

namespace {

// Load the pipeline and every case of its sweep, set each up once and estimate the memory before
// anything runs (a run builds every engine; validate only the plugin objects). Returns 0, or the
// exit status.
int prepare(const Options& o, bool run_it, Pipeline& p, std::vector<StudyCase>& cases, MemoryEstimate& memory) {
  try {
    p = load_pipeline(o.positional[0], o.sets, o.plugin_paths);
  } catch (const PipelineError& e) {
    print_errors(e.messages());
    return 1;
  } catch (const std::bad_alloc& e) {
    print_errors({o.positional[0] + ": " + failure_text(e, nullptr)});
    return 1;
  }
  print_warnings(p.warnings);
  if (!o.output.empty()) p.output_file = o.output;
  if (run_it) {
    const fs::path dir = fs::absolute(p.output_file).parent_path();
    if (!fs::is_directory(dir)) {
      print_errors({"output file " + p.output_file.string() + ": the directory " + dir.string() + " does not exist"});
      return 1;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  CheckProgress progress;  // a line every few seconds while a large sweep is checked
  if (!o.quiet)
    progress = [&](const char* stage, std::size_t done, std::size_t total) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << "gdsmc: checking the sweep: " << done << " of " << total << " cases " << stage << " ("
                << format_seconds(seconds) << ")\n";
    };
  bool estimated = false;
  try {
    cases = expand_cases(p, progress);
    memory = check_cases(cases, progress);
    estimated = true;
    if (run_it)
      for (const auto& c : cases) Engine check(c.pipeline, 0);
  } catch (const PipelineError& e) {
    print_errors(e.messages());
    return 1;
  } catch (const std::exception& e) {
    print_errors({p.file.string() + ": " + failure_text(e, estimated ? &memory : nullptr)});
    return 1;
  }
  return 0;
}

void print_summary(const Pipeline& p, std::size_t cases, const StudyResult& result) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "gdsmc: %s: %zu case(s) x %u realization(s), %llu steps, %.4g collisions in %.2f s (%.3g collisions/s)",
                p.file.filename().c_str(), cases, p.realizations, static_cast<unsigned long long>(result.steps),
                result.collisions, result.wall_seconds, result.wall_seconds > 0 ? result.collisions / result.wall_seconds : 0.0);
  std::cout << buf << "\n";
  for (const auto& line : result.summary) std::cout << line << "\n";
  std::cout << "output: " << fs::absolute(p.output_file).string() << "\n";
}

}  // namespace

int cmd_run(const Options& o, bool run_it) {
  if (o.positional.size() != 1) return usage_error(std::string(run_it ? "run" : "validate") + " takes one PIPELINE.yaml");
  Pipeline p;
  std::vector<StudyCase> cases;
  MemoryEstimate memory;
  if (const int status = prepare(o, run_it, p, cases, memory)) return status;
  if (!run_it) {
    std::cout << p.file.string() << ": valid (" << cases.size() << (cases.size() == 1 ? " case" : " cases") << " x "
              << p.realizations << (p.realizations == 1 ? " realization" : " realizations") << "; " << p.particles
              << " particles; " << p.diagnostics.size() << " diagnostics; output " << p.output_file.string()
              << "; about " << bytes_text(memory.bytes) << " of memory)\n";
    return 0;
  }
  install_interrupt_handlers();
  const bool tty = ::isatty(STDERR_FILENO);
  std::function<void(const StudyProgress&)> report;
  if (!o.quiet) report = progress_reporter(tty);
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
    print_errors({p.file.string() + ": " + failure_text(e, &memory)});
    return 1;
  }
  if (!o.quiet) print_summary(p, cases.size(), result);
  return 0;
}

}  // namespace gdsmc::host
