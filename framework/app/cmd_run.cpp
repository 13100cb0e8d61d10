// `gdsmc run` and `gdsmc validate`.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>

#include "app/commands.hpp"
#include "app/progress.hpp"
#include "config/reading.hpp"
#include "engine/plugin_calls.hpp"
#include "output/hdf5_file.hpp"
#include "study/checkpoint.hpp"
#include "study/ranks.hpp"
#include "study/study.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

const char* const kRunHelp = R"(gdsmc run PIPELINE.yaml [options]

Runs the pipeline and writes one HDF5 file (the pipeline's output.file, default
<pipeline name>.h5 in the current directory). The output is checked before the first step: its
directory exists and is writable, the name is valid, and it is new, a regular file or a symbolic
link (the link is replaced, not its target), never an input of the run. A file it replaces is
named on stderr. The file is written under .FILE.gdsmc-partial-HOST-NS-PID-XXXXXX beside it and
renamed when complete: a failed or interrupted run (also during the final write) leaves nothing
under either name, and a run removes the temporaries of FILE left by killed runs of this host.
A failed write (disk full) exits 1 and says the results are lost.

Options:
  --set key.path=value   override a pipeline value before checking it, e.g.
                         --set collision.alpha=0.5  --set run.particles=20000
                         --set diagnostics[1].record_every=40 (lists by index)
                         --set boundaries.y_min.temperature=2
  -o, --output FILE      write to FILE instead of output.file
  -q, --quiet            no progress and no summary (errors are still printed)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --resume               continue from the checkpoint beside the output (<output>.checkpoint/)
  --threads N            threads; default run.threads, else every core; 1 is serial. Runs
                         (sweep cases x realizations) go at once, and threads left over work
                         inside each run (slab layers, sub-populations of a homogeneous system,
                         blocks of particles) when it is large enough to share (two or more
                         sub-populations; a slab of 16384 particles or more). The output is the
                         same bits for any N; memory
                         grows with the runs at once (each holds its particles)
  -h, --help             this text

With output.plots: true the finished file is then drawn by `gdsmc plot` (PNGs in
<output>_plots/); a plot that fails is a warning, not a failed run.

At the end the run prints what its diagnostics summarize, its energy balance, and where the
steps' wall time went ("time in the steps [s]: ... flight, sort, collisions, ..."; the same
seconds are in /run/stage_seconds.* of the file).

Checkpoints: with run.checkpoint in the pipeline, e.g.
    run: {checkpoint: {every: 30 min}}     (or {every: {collisions_per_particle: 50}}, or both
                                            in a list: {every: [30 min, {collisions_per_particle: 50}]})
every run writes its whole state into <output>.checkpoint/ at those intervals, at SIGINT/SIGTERM
(the step under way is finished first) and when it finishes; each write replaces the previous
one atomically, so a run killed at any moment (SIGKILL, a crash, a lost node) loses at most one
interval. `gdsmc run PIPELINE.yaml --resume` (same --set and -o) continues every unfinished run
where its state was saved and gives the output of the uninterrupted run, to the bit; run.threads
and run.checkpoint may change, nothing else: a checkpoint of another pipeline text, another gdsmc
or plugin version, or plugin library content (a 64-bit hash of each .so) is refused with what
differs. Every entry of a checkpoint carries a checksum, checked before anything runs: a damaged
file is refused naming it. --resume says "finished" (exit 0) when the output of this pipeline is
complete, "nothing to resume" when there is no checkpoint, "damaged" naming the file. The
directory is removed once the output is written; a fresh run refuses to start over an existing
one. A state holds every particle (about N x 28 bytes homogeneous, N x 60 slab, per run under way).

Progress (s, t/tau0, T/T0, time left) goes to stderr: one refreshed line on a terminal,
a plain line every 10 s otherwise. The summary after the run goes to stdout.

Before anything runs, the pipeline is checked as `validate` checks it (and what validate says
about the numbers as read goes to stderr, unless --quiet), the memory the study needs
is estimated and the run is refused when it cannot fit in the memory available (see validate).

MPI (a host built with it: `gdsmc --version`): `mpirun -np K gdsmc run PIPELINE.yaml` (or srun)
spreads the runs over K ranks, each with --threads threads (default: its share of its node's
cores), balanced by expected cost (particles x steps); rank 0 gathers every run and writes the
file: the same bits as --threads 1 without MPI. Progress and the summary are printed once; a run
that fails on any rank ends the job with its message and exit 1, nothing written; a rank that
dies (killed by a signal, crashed) is named with its runs, nothing written either; checkpoints
are shared, and resume at any number of ranks. See docs/cluster.md.
)";

const char* const kValidateHelp = R"(gdsmc validate PIPELINE.yaml [options]

Checks the pipeline without running it: YAML syntax, every key, every plugin and parameter
(type, range, unit), and that every plugin accepts its parameters and sets up (every plugin
object is constructed and every diagnostic begins; no particles are allocated and the initial
state is not generated, so a large N is checked as quickly as a small one). Every problem is
reported with file:line:column. The output file is checked as `run` checks it (a temporary file
is created beside it and removed at once; an existing file a run would replace is named).
Exit 0 when valid, 1 otherwise. Plugin files on the search path that could not be loaded (and
are therefore shadowed or missing) are reported as warnings.

Before the verdict it prints every dimensional value written as a bare number, what it was read
as (a length in lambda0, a time in tau0, ...) and its value in the other common units, then the
dimensionless numbers of each case (n sigma^3 and phi, Kn = lambda0/Ly and particles per layer
of a slab, dt over the mean free time) and those its diagnostics state as they begin (a_hat,
epsilon_star, ...). `units: explicit` in the pipeline makes a bare dimensional number an error.

The verdict gives the memory the study is estimated to need (particles, attributes, every
diagnostic's records, what each sweep case keeps until the file is written); a study that needs
more than is available (the smaller of MemAvailable and what ulimit -v / -d leave) is refused
with both figures. The pipeline file must be a regular file of at most 16 MiB. Checking a sweep
that takes more than 2 s prints its progress on stderr every 2 s.

Options (those of `run`, so that a run's command line can be checked by changing the command):
  --set key.path=value   override a pipeline value before checking it (repeatable)
  -o, --output FILE      the output file to check (nothing is left behind)
  -q, --quiet            as for run: no progress lines (validate prints its verdict and problems)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --threads N            as for run: the runs at once that the memory estimate assumes
  --resume               also check that the checkpoint beside the output belongs to this
                         pipeline, gdsmc and plugins, and read every file of it as run --resume
                         would (checksums, each run's state); say how many runs it holds
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

// Where the output name came from, to locate a message about it.
std::string output_origin(const Options& o, const Pipeline& p) {
  if (!o.output.empty()) return "--output " + o.output;
  if (!p.output_file_where.file.empty()) return p.output_file_where.str() + ": output.file";
  return p.file.string() + ": output file (the default name)";
}

// What the run reads and must never be written over: the pipeline and every plugin library.
std::vector<RunInput> run_inputs(const Pipeline& p, const std::vector<StudyCase>& cases) {
  std::vector<RunInput> in{{p.file, "the pipeline"}};
  auto add = [&](const LoadedPlugin* lp) {
    if (lp) in.push_back({lp->file, "the library of plugin '" + lp->descriptor->name + "'"});
  };
  if (p.registry)
    for (const auto& lp : p.registry->plugins()) add(&lp);
  for (const auto& c : cases) {
    const Pipeline& q = c.pipeline;
    for (const PluginUse* u : {&q.initial_state, &q.collision}) add(u->plugin);
    for (const auto* uses : {&q.forcings, &q.boundaries, &q.diagnostics})
      for (const auto& u : *uses) add(u.plugin);
  }
  return in;
}

// The dimensionless values the diagnostics stated as they began (scalars of unit 1 and numeric
// attributes: a_hat, epsilon_star, packing_fraction, shear_rate_tau0, theory values).
std::string stated_text(const std::vector<DiagnosticOutput>& begun) {
  std::string text;
  for (const auto& d : begun) {
    std::vector<std::string> values;
    for (const auto& s : d.scalars)
      if (s.unit == "1") values.push_back(s.name + " = " + fmt("%.4g", s.value));
    for (const auto& [name, value] : d.attributes) {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      if (!value.empty() && end && *end == '\0') values.push_back(name + " = " + fmt("%.4g", v));
    }
    if (!values.empty()) text += "; " + d.group() + ": " + join(values, ", ");
  }
  return text;
}

// How the numbers of every case were read: each bare dimensional value once (config/reading.hpp),
// then per case the system's dimensionless numbers and what its diagnostics stated as they began.
std::vector<std::string> reading_report(const std::vector<StudyCase>& cases,
                                        const std::vector<std::vector<DiagnosticOutput>>& begun) {
  std::vector<std::string> bare, lines;
  for (const auto& c : cases)
    for (const auto& line : bare_value_lines(c.pipeline))
      if (std::find(bare.begin(), bare.end(), line) == bare.end()) bare.push_back(line);
  lines.push_back(bare.empty() ? "units: no dimensional value is written as a bare number"
                               : "units: the dimensional values written as bare numbers, and what they were read as:");
  for (const auto& line : bare) lines.push_back("  " + line);
  for (std::size_t k = 0; k < cases.size(); ++k)
    lines.push_back((cases.size() > 1 ? "case " + std::to_string(k) + " (" + cases[k].label + "): " : "system: ") +
                    system_numbers_line(cases[k].pipeline) + stated_text(begun[k]));
  return lines;
}

// Load the pipeline and every case of its sweep, check the output path (validate also creates
// and removes a temporary file beside it), set each case up once and estimate the memory before
// anything runs (a run builds every engine; validate only the plugin objects). Returns 0, or the
// exit status.
int prepare(const Options& o, bool run_it, Pipeline& p, std::vector<StudyCase>& cases, OutputTarget& target,
            MemoryEstimate& memory, std::vector<std::string>& reading) {
  try {
    p = load_pipeline(o.positional[0], o.sets, o.plugin_paths);
  } catch (const PipelineError& e) {
    print_warnings(e.warnings());
    print_errors(e.messages());
    return 1;
  } catch (const std::bad_alloc& e) {
    print_errors({o.positional[0] + ": " + failure_text(e, nullptr)});
    return 1;
  }
  print_warnings(p.warnings);
  if (!o.output.empty()) p.output_file = o.output;
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
    int threads = o.threads;
    // Under MPI, every core (run.threads 0) is this rank's share of its node's cores.
    if (threads < 0 && p.threads == 0 && job::distributed())
      threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency() / job::ranks_on_this_node()));
    if (threads >= 0) {  // --threads overrides run.threads (not part of the pipeline: results do not depend on it)
      p.threads = static_cast<std::uint32_t>(threads);
      for (auto& c : cases) c.pipeline.threads = p.threads;
    }
    try {
      target = check_output_path(p.output_file, run_inputs(p, cases));
      if (!run_it) probe_temporary(target);
      if (p.checkpoint || o.resume) {  // the checkpoint directory, and its longest file name
        std::size_t runs = 0;
        for (const auto& c : cases) runs += c.pipeline.realizations;
        check_checkpoint_directory(target, CheckpointStore::directory_for(p.output_file),
                                   ".run-" + std::to_string(runs) + ".partial-" + std::to_string(4194304));
      }
    } catch (const OutputPathError& e) {
      print_errors({output_origin(o, p) + ": " + e.what()});
      return 1;
    }
    memory = check_cases(cases, progress);
    estimated = true;
    std::vector<std::vector<DiagnosticOutput>> begun;
    for (const auto& c : cases) {
      if (run_it) begun.push_back(Engine(c.pipeline, 0).diagnostics());
      else begun.push_back(Engine::check_setup(c.pipeline));
    }
    reading = reading_report(cases, begun);
  } catch (const PipelineError& e) {
    print_errors(e.messages());
    return 1;
  } catch (const std::exception& e) {
    print_errors({p.file.string() + ": " + failure_text(e, estimated ? &memory : nullptr)});
    return 1;
  }
  return 0;
}

void print_summary(const Pipeline& p, std::size_t cases, const StudyResult& result, double write_seconds) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "gdsmc: %s: %zu case(s) x %u realization(s), %llu steps, %.4g collisions in %.2f s (%.3g collisions/s)",
                p.file.filename().c_str(), cases, p.realizations, static_cast<unsigned long long>(result.steps),
                result.collisions, result.wall_seconds, result.wall_seconds > 0 ? result.collisions / result.wall_seconds : 0.0);
  std::cout << buf << "\n";
  for (const auto& line : result.summary) std::cout << line << "\n";
  if (job::distributed()) {
    std::snprintf(buf, sizeof buf,
                  "over %d MPI ranks: %zu run(s) received from ranks 1-%d (%s) in %.3g s of receiving, reading and "
                  "gathering; the file written in %.3g s",
                  job::size(), result.received_runs, job::size() - 1, bytes_text(result.received_bytes).c_str(),
                  result.received_seconds, write_seconds);
    std::cout << buf << "\n";
  }
  std::cout << "output: " << fs::absolute(p.output_file).string() << "\n";
}

// --resume where there is no checkpoint study file: the output is complete (the run finished and
// its checkpoint was removed: 0, "nothing to resume"), or there is nothing to resume (1). Returns
// -1 when there is a checkpoint to check (CheckpointStore says whether it is damaged).
int resume_without_checkpoint(const Pipeline& p, const fs::path& checkpoint_dir, bool run_it) {
  std::error_code ec;
  if (fs::exists(checkpoint_dir / "study", ec) || fs::exists(checkpoint_dir, ec)) return -1;
  const std::string out = p.output_file.string();
  if (fs::exists(p.output_file, ec)) {
    const std::optional<std::string> pipeline = read_root_text(p.output_file, "pipeline");
    if (pipeline && CheckpointStore::pipeline_identity(*pipeline) == CheckpointStore::pipeline_identity(p.resolved_text)) {
      std::cerr << "gdsmc: --resume: finished: " << out
                << " is the complete output of this pipeline (its checkpoint was removed when it was written); nothing "
                   "to resume, nothing "
                << (run_it ? "done" : "to check") << ". Run without --resume to compute it again (" << out
                << " would be replaced)\n";
      return 0;
    }
    print_errors({p.file.string() + ": --resume: nothing to resume: there is no checkpoint at " + checkpoint_dir.string() +
                  ", and " + out +
                  (pipeline ? " is the output of another pipeline (or of other --set values)"
                            : " is not a gdsmc output") +
                  "; run without --resume to start (" + out + " would be replaced), or give another -o"});
    return 1;
  }
  print_errors({p.file.string() + ": --resume: nothing to resume: there is no checkpoint at " + checkpoint_dir.string() +
                " and no output " + out + " (a run writes a checkpoint there when its pipeline sets run.checkpoint" +
                (p.checkpoint ? "" : ", which this one does not") + "); run without --resume to start"});
  return 1;
}

// "continue with `gdsmc run PIPELINE --resume ...`": the command that continues from the checkpoint.
std::string resume_text(const Options& o, const Pipeline& p) {
  std::string resume_command = "gdsmc run " + p.file.string() + " --resume";
  for (const auto& set : o.sets) resume_command += " --set '" + set + "'";
  if (!o.output.empty()) resume_command += " -o " + o.output;
  return "continue with `" + resume_command + "`" + (job::distributed() ? " under mpirun, at any number of ranks" : "");
}

// Rank 0's part (the whole run without MPI) once the output file is open: the study, the file,
// the checkpoint removed, the summary and the plots. Returns the exit status.
int finish_run(const Options& o, const Pipeline& p, const std::vector<StudyCase>& cases, const MemoryEstimate& memory,
               const std::string& notice, OutputFile& out, const std::optional<CheckpointStore>& checkpoints,
               std::chrono::steady_clock::time_point start, bool tty,
               const std::function<void(const StudyProgress&)>& report) {
  const fs::path checkpoint_dir = CheckpointStore::directory_for(p.output_file);
  auto end_line = [&] {
    if (report && tty) std::cerr << "\n";
  };
  auto lost = [&](const std::exception& e) {
    end_line();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "gdsmc: error: cannot write " << p.output_file.string() << ": " << e.what()
              << "; the results computed in " << format_seconds(seconds);
    if (checkpoints)  // what the checkpoint keeps of them
      std::cerr << " were not written; " << checkpoints->kept_text() << ": once that is fixed, " << resume_text(o, p) << "\n";
    else
      std::cerr << " are lost (they were held only in memory) and nothing was written\n";
    return 1;
  };
  if (!notice.empty()) std::cerr << "gdsmc: " << notice << "\n";
  const std::string resume_hint = resume_text(o, p);
  auto interrupted = [&](const std::string& when) {
    end_line();
    std::cerr << "gdsmc: interrupted" << when << "; no output written";
    if (checkpoints) std::cerr << "; every started run saved its state in " << checkpoint_dir.string() << ": " << resume_hint;
    std::cerr << "\n";
    return 130;
  };
  if (checkpoints && o.resume && !o.quiet)
    std::cerr << "gdsmc: resuming from " << checkpoint_dir.string() << " (" << checkpoints->describe(cases) << ")\n";
  StudyResult result;
  try {
    const ParticleStager particles = out.stager();  // the final particles straight into the file
    result = run_study(cases, report, tty ? 0.25 : 10.0, &g_interrupted, checkpoints ? &*checkpoints : nullptr,
                       &particles);
    end_line();
  } catch (const Engine::Interrupted&) {
    return interrupted("");
  } catch (const OutputInterrupted&) {
    return interrupted(" while writing " + p.output_file.string());
  } catch (const OutputWriteError& e) {  // the final particles, written as the run ends
    return lost(e);
  } catch (const RankLost& e) {
    end_line();
    std::cerr << "error: " << p.file.string() << ": " << e.what() << "\ngdsmc: the run failed; nothing was written";
    if (checkpoints)
      std::cerr << "; every run saved its state in " << checkpoint_dir.string()
                << " as the pipeline asks (those of the lost rank at their last checkpoint): " << resume_hint;
    std::cerr << "\n";
    return 1;
  } catch (const std::exception& e) {
    end_line();
    std::cerr << "error: " << p.file.string() << ": " << failure_text(e, &memory)
              << "\ngdsmc: the run failed; nothing was written";
    if (checkpoints) std::cerr << " (the checkpoint in " << checkpoint_dir.string() << " is kept)";
    std::cerr << "\n";
    return 1;
  }
  const auto write_start = std::chrono::steady_clock::now();
  try {
    out.commit(result.output);
  } catch (const OutputInterrupted&) {
    return interrupted(" while writing " + p.output_file.string());
  } catch (const std::exception& e) {
    if (checkpoints) {  // the finished runs are in the checkpoint: nothing is lost
      end_line();
      bool all_kept = false;
      std::cerr << "gdsmc: error: cannot write " << p.output_file.string() << ": " << e.what()
                << "; " << checkpoints->kept_text(&all_kept) << ": once that is fixed, " << resume_hint
                << (all_kept ? " (it only writes the file)" : "") << "\n";
      return 1;
    }
    return lost(e);
  }
  const double write_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - write_start).count();
  if (checkpoints) checkpoints->remove();  // the output is complete: the checkpoint has served
  if (!o.quiet) print_summary(p, cases.size(), result, write_seconds);
  if (p.output_plots) {
    std::string why;
    if (!plot_output(p.output_file, o.quiet, why))
      std::cerr << "gdsmc: warning: output.plots: " << p.output_file.string() << " is complete, but drawing it failed: "
                << why << " (run `gdsmc plot " << p.output_file.string() << "` once that is fixed)\n";
  }
  return 0;
}

// In an MPI job, what a rank other than 0 would print on stderr while the job sets up: kept back,
// since every rank checks the same pipeline and rank 0 says it once; printed only when this rank
// failed where rank 0 did not (a plugin missing on one node).
class StderrHold {
 public:
  explicit StderrHold(bool hold) {
    if (hold) saved_ = std::cerr.rdbuf(text_.rdbuf());
  }
  StderrHold(const StderrHold&) = delete;
  StderrHold& operator=(const StderrHold&) = delete;
  ~StderrHold() { end(false); }
  // Stop holding; print what was held, or drop it.
  void end(bool print) {
    if (!saved_) return;
    std::cerr.rdbuf(saved_);
    saved_ = nullptr;
    if (print) std::cerr << "gdsmc: rank " << job::rank() << " of " << job::size() << ":\n" << text_.str() << std::flush;
  }

 private:
  std::ostringstream text_;
  std::streambuf* saved_ = nullptr;
};

// A step of the set-up that every rank of an MPI job takes: every rank's exit status so far, and
// the failure's messages printed once (rank 0's, or those of a rank that failed alone). Returns
// 0 on every rank, or a failure's exit status on every rank. Without MPI: `status`.
int agree(int status, StderrHold& hold) {
  const int at_root = job::root_value(status), any = job::largest(status);
  if (status && !at_root) hold.end(true);
  return any;
}

// The checkpoint of this output before anything runs: checked (validate, --resume) or begun (a run
// that asks for one), on every rank. Returns the exit status when the command ends here.
std::optional<int> open_checkpoints(const Options& o, const Pipeline& p, const std::vector<StudyCase>& cases,
                                    bool run_it, StderrHold& hold, std::optional<CheckpointStore>& checkpoints) {
  const fs::path checkpoint_dir = CheckpointStore::directory_for(p.output_file);
  std::error_code exists_error;
  if (!run_it && !o.resume && p.checkpoint && fs::exists(checkpoint_dir / "study", exists_error)) {
    print_errors({p.file.string() + ": " + checkpoint_dir.string() +
                  " holds the checkpoint of an earlier run with this output, so `run` would refuse to start over "
                  "it: continue it with --resume (`validate --resume` checks that it fits), or remove the directory"});
    return 1;
  }
  if (o.resume) {
    // No checkpoint: the run finished (its output is there), or there is nothing to resume.
    const int status = job::root_value(job::root() ? resume_without_checkpoint(p, checkpoint_dir, run_it) : -1);
    if (status >= 0) return status;
  }
  if (o.resume || (run_it && p.checkpoint)) {
    // Rank 0 begins the checkpoint (or checks it, to resume); then the other ranks check it as a
    // resume does: it must be on a file system they share.
    auto open = [&](bool resume, const std::string& where) {
      try {
        checkpoints.emplace(checkpoint_dir, cases, resume);
      } catch (const std::exception& e) {
        print_errors({p.file.string() + ": " + where + e.what()});
        return 1;
      }
      return 0;
    };
    int opened = job::root() ? open(o.resume, "") : 0;
    if (job::root_value(opened) == 0 && !job::root())
      opened = open(true, "rank " + std::to_string(job::rank()) + " cannot use the checkpoint rank 0 " +
                              (o.resume ? "checked" : "began") +
                              " (every rank must see the same file system there): ");
    if (const int status = agree(opened, hold)) return status;
    // Every run file read before anything runs, as the resume reads it (validate: each whole state).
    int checked = 0;
    if (o.resume && job::root()) {
      try {
        checkpoints->check_runs(cases, !run_it);
      } catch (const std::exception& e) {
        print_errors({p.file.string() + ": " + e.what()});
        checked = 1;
      }
    }
    if (const int status = agree(checked, hold)) return status;
  }
  return std::nullopt;
}

// validate's verdict: the checkpoint it found, the notices and the reading of the pipeline, and
// what the study is (cases, realizations, particles, diagnostics, output, memory).
int print_valid(const Pipeline& p, const std::vector<StudyCase>& cases, const MemoryEstimate& memory,
                const std::vector<std::string>& reading, const std::string& notice,
                const std::optional<CheckpointStore>& checkpoints) {
  const fs::path checkpoint_dir = CheckpointStore::directory_for(p.output_file);
  if (checkpoints)
    std::cout << checkpoint_dir.string() << ": a checkpoint of this pipeline (" << checkpoints->describe(cases)
              << ")\n";
  if (!notice.empty()) std::cerr << "gdsmc: " << notice << "\n";
  for (const auto& line : reading) std::cout << line << "\n";
  std::cout << p.file.string() << ": valid (" << cases.size() << (cases.size() == 1 ? " case" : " cases") << " x "
            << p.realizations << (p.realizations == 1 ? " realization" : " realizations") << "; " << p.particles
            << " particles; " << p.diagnostics.size() << " diagnostics; output " << p.output_file.string()
            << "; about " << bytes_text(memory.bytes) << " of memory)\n";
  return 0;
}

// A rank other than 0 of an MPI job: its share of the runs, sent to rank 0 as they finish; rank 0
// reports any failure and ends the job with one exit status.
int run_other_rank(const Options& o, const Pipeline& p, const std::vector<StudyCase>& cases, const OutputTarget& target,
                   std::optional<CheckpointStore>& checkpoints) {
  const fs::path checkpoint_dir = CheckpointStore::directory_for(p.output_file);
  try {
    run_study(cases, {}, 10.0, &g_interrupted, checkpoints ? &*checkpoints : nullptr);
  } catch (const std::exception&) {
  }
  const int status = job::await_status();
  // Rank 0 died (killed, crashed): no one reports anything, but the lowest rank on its host, if
  // any, can say so and remove its temporary file.
  if (job::root_gone() && job::watches_root()) {
    std::cerr << "gdsmc: rank " << job::rank() << " of " << job::size()
              << ": rank 0, which gathers the runs and writes the output, ended without a word: it was killed by a "
                 "signal or crashed (mpirun names the signal); nothing was written";
    if (checkpoints)
      std::cerr << "; every run saved its state in " << checkpoint_dir.string()
                << " as the pipeline asks (those of rank 0 at their last checkpoint): " << resume_text(o, p);
    std::cerr << "\n";
    for (const auto& line : remove_stale_temporaries(target))
      std::cerr << "gdsmc: rank " << job::rank() << " of " << job::size() << ": " << line << "\n";
  }
  return status;
}

}  // namespace

int cmd_run(const Options& options, bool run_it) {
  // A crash inside a plugin (SIGSEGV, SIGBUS, SIGFPE, abort) names it, its role, the step and the
  // run, and removes the temporary output and the lock (engine/plugin_calls.hpp).
  install_fatal_signal_handlers();
  // In an MPI job (study/ranks.hpp) every rank checks the pipeline and runs its share of the
  // study; rank 0 alone prints progress and the summary, and writes the file.
  StderrHold hold(job::distributed() && !job::root());
  Options o = options;
  if (!job::root()) o.quiet = true;
  if (o.positional.size() != 1) return usage_error(std::string(run_it ? "run" : "validate") + " takes one PIPELINE.yaml");
  Pipeline p;
  std::vector<StudyCase> cases;
  OutputTarget target;
  MemoryEstimate memory;
  std::vector<std::string> reading;
  if (const int status = agree(prepare(o, run_it, p, cases, target, memory, reading), hold)) return status;
  if (run_it && !o.quiet)
    for (const auto& line : reading) std::cerr << line << "\n";
  const std::string notice = target.replacement_notice(run_it);
  // Checkpoints: checked (resume) or begun (a fresh run that asks for them) before anything runs.
  std::optional<CheckpointStore> checkpoints;
  if (const std::optional<int> status = open_checkpoints(o, p, cases, run_it, hold, checkpoints)) return *status;
  if (!run_it) return print_valid(p, cases, memory, reading, notice, checkpoints);
  // Handlers first: a signal from here on removes the temporary file (exit 130).
  install_interrupt_handlers();
  std::signal(SIGXFSZ, SIG_IGN);  // a file size limit (ulimit -f) is a write error, not a kill
  const auto start = std::chrono::steady_clock::now();
  const bool tty = ::isatty(STDERR_FILENO);
  std::function<void(const StudyProgress&)> report;
  if (!o.quiet) report = progress_reporter(tty);
  // Rank 0's alone in an MPI job: the output's lock (held until the run ends: another run that
  // would write the same output is refused meanwhile), then the output's temporary file.
  std::optional<OutputLock> lock;
  std::optional<OutputFile> out;
  int created = 0;
  if (job::root()) {
    try {
      lock.emplace(target);
      for (const auto& line : remove_stale_temporaries(target)) std::cerr << "gdsmc: " << line << "\n";
      out.emplace(target, &g_interrupted);
    } catch (const OutputPathError& e) {
      print_errors({output_origin(o, p) + ": " + e.what()});
      created = 1;
    }
  }
  if (const int status = agree(created, hold)) return status;
  hold.end(false);  // from here on, a rank's warnings (a checkpoint not written) are its own
  if (!job::root()) return run_other_rank(o, p, cases, target, checkpoints);
  return job::conclude(finish_run(o, p, cases, memory, notice, *out, checkpoints, start, tty, report));
}

}  // namespace gdsmc::host
