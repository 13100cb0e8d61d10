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
#include "study/slab_ranks.hpp"
#include "study/study.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

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

// What the run reads and must never be written over: the pipeline and every plugin library found
// (every case's entries are resolved against these, so no case adds a library of its own).
std::vector<RunInput> run_inputs(const LoadedPipeline& loaded) {
  std::vector<RunInput> in{{loaded.pipeline.file, "the pipeline"}};
  for (const auto& lp : loaded.plugins->plugins())
    in.push_back({lp.file, "the library of plugin '" + lp.descriptor->name + "'"});
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
int prepare(const Options& o, bool run_it, LoadedPipeline& loaded, std::vector<StudyCase>& cases, OutputTarget& target,
            MemoryEstimate& memory, std::vector<std::string>& reading) {
  Pipeline& p = loaded.pipeline;
  try {
    loaded = load_pipeline(o.positional[0], o.sets, o.plugin_paths);
  } catch (const PipelineError& e) {
    print_warnings(e.warnings());
    print_errors(e.messages());
    return 1;
  } catch (const std::bad_alloc& e) {
    print_errors({o.positional[0] + ": " + failure_text(e, nullptr)});
    return 1;
  }
  print_warnings(loaded.warnings);
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
    cases = expand_cases(loaded, progress);
    int threads = o.threads;
    // Under MPI, every core (run.threads 0) is this rank's share of its node's cores.
    if (threads < 0 && p.threads == 0 && job::distributed())
      threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency() / job::ranks_on_this_node()));
    if (threads >= 0) {  // --threads overrides run.threads (not part of the pipeline: results do not depend on it)
      p.threads = static_cast<std::uint32_t>(threads);
      for (auto& c : cases) c.pipeline.threads = p.threads;
    }
    try {
      target = check_output_path(p.output_file, run_inputs(loaded));
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
    if (o.decompose) {  // --decompose: every case a slab this job's ranks can split
      std::vector<std::string> refused;
      for (const auto& c : cases)
        if (const std::string why = Engine::why_not_decomposed(c.pipeline, job::size()); !why.empty())
          refused.push_back(p.file.string() + ": " + (c.label.empty() ? "" : "case " + c.label + ": ") + why);
      if (!refused.empty()) {
        print_errors(refused);
        return 1;
      }
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

void print_summary(const Pipeline& p, std::size_t cases, const StudyResult& result, double write_seconds, bool decomposed) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "gdsmc: %s: %zu case(s) x %u realization(s), %llu steps, %.4g collisions in %.2f s (%.3g collisions/s)",
                p.file.filename().c_str(), cases, p.realizations, static_cast<unsigned long long>(result.steps),
                result.collisions, result.wall_seconds, result.wall_seconds > 0 ? result.collisions / result.wall_seconds : 0.0);
  std::cout << buf << "\n";
  for (const auto& line : result.summary) std::cout << line << "\n";
  if (job::distributed() && decomposed) {
    std::cout << "over " << job::size() << " MPI ranks, each run decomposed by layers; the file written in "
              << fmt("%.3g", write_seconds) << " s\n";
  } else if (job::distributed()) {
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
// output.plots: the complete file drawn by `gdsmc plot`; a failure there is a warning.
void draw_plots(const Pipeline& p, bool quiet) {
  std::string why;
  if (!plot_output(p.output_file, quiet, why))
    std::cerr << "gdsmc: warning: output.plots: " << p.output_file.string() << " is complete, but drawing it failed: "
              << why << " (run `gdsmc plot " << p.output_file.string() << "` once that is fixed)\n";
}

int finish_run(const Options& o, const Pipeline& p, const std::vector<StudyCase>& cases, const MemoryEstimate& memory,
               const std::string& notice, OutputFile& out, const std::optional<CheckpointStore>& checkpoints,
               std::chrono::steady_clock::time_point start, bool tty,
               const std::function<void(const StudyProgress&)>& report, Decomposition* ranks) {
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
                       &particles, ranks);
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
  if (!o.quiet) print_summary(p, cases.size(), result, write_seconds, ranks != nullptr);
  if (p.output_plots) draw_plots(p, o.quiet);
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
                   std::optional<CheckpointStore>& checkpoints, Decomposition* ranks) {
  const fs::path checkpoint_dir = CheckpointStore::directory_for(p.output_file);
  try {
    run_study(cases, {}, 10.0, &g_interrupted, checkpoints ? &*checkpoints : nullptr, nullptr, ranks);
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
  LoadedPipeline loaded;
  const Pipeline& p = loaded.pipeline;
  std::vector<StudyCase> cases;
  OutputTarget target;
  MemoryEstimate memory;
  std::vector<std::string> reading;
  if (const int status = agree(prepare(o, run_it, loaded, cases, target, memory, reading), hold)) return status;
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
  // --decompose: every run's slab split over the ranks by layers (engine/decomposition.hpp).
  const std::unique_ptr<Decomposition> ranks = o.decompose ? job::slab_ranks() : nullptr;
  if (!job::root()) return run_other_rank(o, p, cases, target, checkpoints, ranks.get());
  return job::conclude(finish_run(o, p, cases, memory, notice, *out, checkpoints, start, tty, report, ranks.get()));
}

}  // namespace gdsmc::host
