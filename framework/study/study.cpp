#include "study/study.hpp"

#include "engine/plugin_calls.hpp"
#include "engine/work_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <iostream>
#include <mutex>
#include <optional>

#include "study/ranks.hpp"
#include "study/run_results.hpp"
#include "study/slab_ranks.hpp"
#include "study/summary.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {

using Clock = std::chrono::steady_clock;

// One run: a realization of a case, on whichever worker (or MPI rank) takes it. Everything it
// gives to the output is computed from (case, realization) alone, so the gathered output is the
// same bits for any number of workers and ranks.
struct Run {
  std::size_t case_index = 0;
  std::uint32_t realization = 0;
  std::string label;
  RunResults results;
  std::exception_ptr error;
};

// What rank 0 says of a rank that was lost: which, and the runs it had under way.
std::string lost_rank_text(const job::RunExchange::Failure& f, const std::vector<Run>& runs) {
  auto name = [&](std::size_t index) {
    std::string text = "run " + std::to_string(index + 1) + " of " + std::to_string(runs.size());
    if (!runs[index].label.empty()) text += " (" + runs[index].label + ")";
    return text;
  };
  std::string text = f.message + " of " + std::to_string(job::size()) + " ended without a word";
  if (!f.under_way.empty()) {
    text += " while running ";
    for (std::size_t k = 0; k < f.under_way.size(); ++k)
      text += (k == 0 ? "" : k + 1 == f.under_way.size() ? " and " : ", ") + name(f.under_way[k]);
  } else if (f.run < runs.size()) {
    text += " before it finished " + name(f.run);
  }
  return text + ": it was killed by a signal (the OOM killer, a user, the batch system) or crashed (mpirun names "
                "the signal)";
}

// Progress of the whole study, shared by the workers: each run's fraction, reported at most once
// per interval (and once at the very end).
class StudyClock {
 public:
  StudyClock(std::size_t runs, const std::function<void(const StudyProgress&)>& report, double interval)
      : fractions_(runs, 0.0), report_(report), interval_(interval) {}

  void update(std::size_t run, const std::string& label, const Progress& pr) {
    if (!report_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    fractions_[run] = std::clamp(pr.fraction, 0.0, 1.0);
    if (pr.final) ++finished_;
    const auto now = Clock::now();
    const bool last = pr.final && finished_ == fractions_.size();
    if (!last && std::chrono::duration<double>(now - last_report_).count() < interval_) return;
    last_report_ = now;
    StudyProgress sp;
    sp.run = run;
    sp.runs = fractions_.size();
    sp.label = label;
    sp.progress = pr;
    double sum = 0;
    for (double f : fractions_) sum += f;
    sp.fraction = sum / static_cast<double>(fractions_.size());
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    sp.elapsed_seconds = elapsed;
    sp.remaining_seconds = sp.fraction > 0 ? elapsed * (1 - sp.fraction) / sp.fraction : -1;
    report_(sp);
  }
  double interval() const { return interval_; }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  std::mutex mutex_;
  std::vector<double> fractions_;
  std::size_t finished_ = 0;
  const std::function<void(const StudyProgress&)>& report_;
  double interval_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_report_ = start_;
};

// A decomposed run's blocks and migration, on stderr (rank 0): not in the output, whose bits are
// the single-process run's.
void describe_decomposition(const Engine& engine, int ranks) {
  const Engine::DecompositionStats s = engine.decomposition_stats();
  std::string blocks;
  for (std::size_t r = 0; r + 1 < s.bounds.size(); ++r)
    blocks += (r ? ", " : "") + std::to_string(s.bounds[r]) + "-" + std::to_string(s.bounds[r + 1] - 1);
  const double per_step = s.steps ? static_cast<double>(s.migrated) / static_cast<double>(s.steps) : 0.0;
  std::cerr << "gdsmc: decomposed over " << ranks << (ranks == 1 ? " rank" : " ranks") << " (layers " << blocks << " at the end; "
            << s.rebalanced << " rebalancings): " << fmt("%.4g", per_step) << " particles changed rank per step ("
            << bytes_text(per_step * sizeof(Migrant)) << " per step); rank 0: "
            << fmt("%.3g s migrating (%.1f %% of the steps), %.3g s in %llu gather(s) of every particle", s.migration_seconds,
                   100.0 * s.migration_seconds / std::max(engine.wall_seconds(), 1e-300), s.gather_seconds,
                   static_cast<unsigned long long>(s.gathers))
            << "\n";
}

// Runs `run` (study index `index`), telling `report` its progress about every `interval` seconds.
void execute(const StudyCase& sc, Run& run, const std::function<void(const Progress&)>& report, double interval,
             std::size_t index, const std::atomic<bool>* stop, unsigned threads, const CheckpointStore* checkpoints,
             const ParticleStager* particles, Decomposition* ranks) {
  const Pipeline& p = sc.pipeline;
  const std::unique_ptr<Engine> started =
      checkpoints && checkpoints->has_run(index) ? checkpoints->restore(index, sc, run.realization, threads)
                                                 : std::make_unique<Engine>(p, run.realization, threads);
  Engine& engine = *started;
  if (ranks) engine.decompose(*ranks);
  CheckpointSchedule schedule;
  if (checkpoints) {
    schedule.every_seconds = p.checkpoint_every_seconds;
    schedule.every_collisions_per_particle = p.checkpoint_every_collisions_per_particle;
    // A checkpoint that cannot be written (disk full) does not stop the run: the previous one stays.
    schedule.write = [&](const Engine& e) {
      try {
        checkpoints->write(index, sc, run.realization, e);
      } catch (const std::exception& error) {
        std::cerr << "gdsmc: warning: " << (run.label.empty() ? "" : run.label + ": ") << error.what()
                  << "; the run goes on, its previous checkpoint (if any) is kept\n";
      }
    };
  }
  engine.run(report, interval, stop, checkpoints ? &schedule : nullptr);
  RunResults& r = run.results;
  r.collisions = engine.context().collisions;
  r.steps = engine.context().step;
  r.wall_seconds = engine.wall_seconds();
  r.stage_seconds = engine.stage_seconds();
  r.steady = engine.reached_steady_state();
  if (ranks) {
    if (ranks->root()) describe_decomposition(engine, ranks->size());
    else return;  // rank 0 holds the results
  }
  if (run.realization == 0) {
    r.output = engine.output(particles);
    r.summary = engine.summary();
  }
  r.diagnostics = engine.diagnostics();
}

// The estimate took the steps of a stop at s from about one collision per particle per tau0 at T0;
// a gas that cools at a fixed run.time_step takes many more (an HCS to s = 40: 16205 steps, not
// 2000), and every step's records are kept. Once the first run of a case has finished, what it
// keeps is known: if the case's other runs and its average would not fit in the memory left, the
// study stops now, with the figures, instead of running out of memory after computing.
void check_case_memory(const StudyCase& sc, const Run& run, std::uint32_t runs_left) {
  const Pipeline& p = sc.pipeline;
  const double kept = diagnostics_bytes(run.results.diagnostics);
  // The runs still to finish keep as much each, the average its mean and standard errors, and
  // output.realizations a copy of every run's records.
  const double copies = runs_left + (p.realizations > 1 ? 2.0 : 0.0) + (p.output_realizations ? p.realizations : 0);
  const double need = copies * kept;
  const MemoryAvailable available = available_memory();
  if (need <= available.bytes) return;
  const double estimated_steps = case_memory(p, RunLayout{}).steps;
  std::string message = "memory: " + (run.label.empty() ? std::string("the first run") : "run '" + run.label + "'");
  message += fmt(" took %llu steps", static_cast<unsigned long long>(run.results.steps));
  if (estimated_steps > 0) message += fmt(" (the estimate assumed about %.0f)", estimated_steps);
  message += " and keeps " + bytes_text(kept) + " of diagnostics' records; the case's " + std::to_string(runs_left) +
             " runs left and its average would keep about " + bytes_text(need) + " more, but " +
             bytes_text(available.bytes) + " is available (" + available.source +
             "); stopped now rather than run out of memory after computing: record less often (record_every), stop "
             "sooner (run.stop), run fewer realizations, or let the step follow the temperature "
             "(run.time_step.follow_temperature: true; a cooling gas at a fixed step takes ever more steps per "
             "collision)";
  throw std::runtime_error(message);
}

// What each run is expected to cost (particles x steps), to balance the runs over MPI ranks.
std::vector<double> run_costs(const std::vector<StudyCase>& cases, const std::vector<Run>& runs) {
  std::vector<double> costs;
  for (const Run& run : runs) {
    const Pipeline& p = cases[run.case_index].pipeline;
    const double steps = case_memory(p, RunLayout{}).steps;  // 0 when only a steady state stops it
    costs.push_back(static_cast<double>(p.particles) * std::max(steps, 1.0));
  }
  return costs;
}

// A case from its runs (in realization order): the diagnostics averaged, the steady averages added.
CaseOutput gather_case(const StudyCase& sc, std::vector<Run*> runs, std::vector<std::string>& case_summary) {
  const Pipeline& p = sc.pipeline;
  CaseOutput case_out = std::move(*runs.front()->results.output);
  for (const auto& line : runs.front()->results.summary)
    case_summary.push_back((p.realizations > 1 ? "[realization 0] " : "") + line);
  std::vector<std::vector<DiagnosticOutput>> diagnostics;
  StageSeconds stages{};
  for (Run* run : runs) {
    RunResults& r = run->results;
    for (std::size_t k = 0; k < kStages; ++k) stages[k] += r.stage_seconds[k];
    if (run->realization > 0) {
      case_out.run["wall_seconds"] += r.wall_seconds;
      case_out.run["reached_steady_state"] = std::min(case_out.run["reached_steady_state"], r.steady ? 1.0 : 0.0);
    }
    diagnostics.push_back(std::move(r.diagnostics));
  }
  for (std::size_t k = 0; k < kStages; ++k)
    case_out.run[stage_attribute(static_cast<Stage>(k))] = stages[k];
  case_summary.push_back("time in the steps [s]: " + stage_times_text(stages));
  case_out.run["realizations"] = p.realizations;
  case_out.diagnostics = average_realizations(diagnostics, nullptr);
  add_steady_averages(case_out.diagnostics, p.average_after_collisions_per_particle, p.average_after_time_tau0,
                      diagnostics);
  // Each realization's own steady averages (one realization's errors, by batch means): written with
  // output.realizations, and checked against the realizations' scatter (issue 29 item 2).
  const bool steady = p.average_after_collisions_per_particle || p.average_after_time_tau0;
  if (steady && diagnostics.size() >= 2) {
    for (auto& run : diagnostics)
      add_steady_averages(run, p.average_after_collisions_per_particle, p.average_after_time_tau0);
    for (std::size_t d = 0; d < case_out.diagnostics.size(); ++d)
      add_seed_checks(diagnostics, d, case_out.diagnostics[d], SeedErrors::steady);
  }
  for (const auto& d : case_out.diagnostics)
    for (const char* key : {"seed_check", "seed_check_steady"}) {
      const auto check = d.attributes.find(key);
      if (check != d.attributes.end()) case_summary.push_back(check->second);
    }
  const std::string missed =
      steady_window_missed(case_out.diagnostics, p.average_after_collisions_per_particle, p.average_after_time_tau0);
  if (!missed.empty()) case_summary.push_back("warning: " + missed);
  else if (steady)
    for (auto& line : nan_error_warnings(case_out.diagnostics)) case_summary.push_back(std::move(line));
  if (p.output_realizations) {
    if (diagnostics.size() < 2)
      for (auto& run : diagnostics)
        add_steady_averages(run, p.average_after_collisions_per_particle, p.average_after_time_tau0);
    for (std::size_t d = 0; d < case_out.diagnostics.size(); ++d)
      for (auto& run : diagnostics) case_out.diagnostics[d].realizations.push_back(std::move(run[d]));
  }
  return case_out;
}

// A study under way on this process: its runs, the slots their cases are gathered into, its clock
// and, over the ranks of an MPI job, its exchange.
class StudyRunner {
 public:
  StudyRunner(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
              double report_interval, const std::atomic<bool>* interrupt, const CheckpointStore* checkpoints,
              const ParticleStager* particles, Decomposition* ranks);
  // Whether this process's runs go one after the other on this thread (one worker, no MPI).
  bool serial() const { return workers_ == 1 && !exchange_; }
  // Whether this process is a rank other than 0, whose runs' results went to rank 0.
  bool sends() const { return sends_; }
  void run_serial();
  void run_parallel(StudyResult& result);
  void assemble(StudyResult& result, bool sweep);

 private:
  void finish(std::size_t index);
  std::function<void(const Progress&)> progress_of(std::size_t index);
  void name_run(std::size_t index) const;
  void done(std::size_t index);
  void execute_run(std::size_t index);
  job::RunExchange::Receiver make_receiver();
  void end_exchange(StudyResult& result, const job::RunExchange::Receiver& receiver,
                    const std::exception_ptr& first_error, std::size_t first_failed);

  const std::vector<StudyCase>& cases_;
  const std::atomic<bool>* interrupt_;
  const CheckpointStore* checkpoints_;
  const ParticleStager* particles_;  // where realization 0 writes its final particles (output.particles)
  Decomposition* ranks_;              // --decompose: every run over every rank
  std::vector<Run> runs_;
  std::vector<std::size_t> first_run_;  // of each case
  // A case is gathered by the worker that finishes its last run (so that only the averaged
  // records of finished cases are kept, as in a serial study), into its own slot.
  std::vector<std::optional<CaseOutput>> gathered_;
  std::vector<std::vector<std::string>> case_summaries_;
  std::vector<std::uint32_t> left_;
  std::optional<StudyClock> clock_;
  std::unique_ptr<job::RunExchange> exchange_;
  bool sends_ = false;               // a rank other than 0: its runs' results go to rank 0
  std::vector<std::size_t> mine_;    // the runs this process executes, in study order
  std::uint32_t workers_ = 1, per_run_ = 1;
  std::mutex mutex_;
  std::vector<char> measured_;       // whether a finished run of the case was measured
  std::atomic<bool> stop_{false};
  std::exception_ptr received_error_;  // results from another rank that could not be read
};

// Every run of the study, its slots and clock, and which runs this process executes on how many workers.
StudyRunner::StudyRunner(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                         double report_interval, const std::atomic<bool>* interrupt, const CheckpointStore* checkpoints,
                         const ParticleStager* particles, Decomposition* ranks)
    : cases_(cases),
      interrupt_(interrupt),
      checkpoints_(checkpoints),
      particles_(particles),
      ranks_(ranks),
      first_run_(cases.size()),
      gathered_(cases.size()),
      case_summaries_(cases.size()),
      left_(cases.size()),
      measured_(cases.size(), 0) {
  // Every run, in case order and realization order within a case: the order workers take them in.
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    first_run_[ci] = runs_.size();
    const Pipeline& p = cases[ci].pipeline;
    for (std::uint32_t r = 0; r < p.realizations; ++r) {
      Run run;
      run.case_index = ci;
      run.realization = r;
      run.label = cases[ci].label;
      if (p.realizations > 1)
        run.label += (run.label.empty() ? "" : ", ") + std::string("realization ") + std::to_string(r);
      runs_.push_back(std::move(run));
    }
  }
  for (std::size_t ci = 0; ci < cases.size(); ++ci) left_[ci] = cases[ci].pipeline.realizations;

  clock_.emplace(runs_.size(), report, report_interval);
  // Over the ranks of an MPI job (study/ranks.hpp) each rank runs its share of the runs, and rank 0
  // also gathers those of the others, as they finish, into the same slots as its own.
  // Decomposed (--decompose), every rank takes part in every run, one after the other.
  if (job::distributed() && !ranks) exchange_ = std::make_unique<job::RunExchange>(run_costs(cases, runs_));
  sends_ = (exchange_ && !job::root()) || (ranks && !ranks->root());
  for (std::size_t index = 0; index < runs_.size(); ++index)
    if (!exchange_ || exchange_->mine(index)) mine_.push_back(index);
  workers_ = ranks ? 1 : study_threads(cases, mine_.size());
  per_run_ = ranks ? threads_per_run(cases, 1) : threads_per_run(cases, mine_.size());
}

// Counts run `index` as finished: its case's memory checked after the case's first run, the case
// gathered after its last.
void StudyRunner::finish(std::size_t index) {
  const std::size_t ci = runs_[index].case_index;
  std::uint32_t runs_left;
  bool first;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    runs_left = --left_[ci];
    first = !measured_[ci];
    measured_[ci] = 1;
  }
  if (first) check_case_memory(cases_[ci], runs_[index], runs_left);
  if (runs_left > 0) return;
  std::vector<Run*> case_runs;
  for (std::uint32_t r = 0; r < cases_[ci].pipeline.realizations; ++r)
    case_runs.push_back(&runs_[first_run_[ci] + r]);
  gathered_[ci] = gather_case(cases_[ci], case_runs, case_summaries_[ci]);
}

// Where run `index` reports its progress: to rank 0 from another rank, to the study's clock here.
std::function<void(const Progress&)> StudyRunner::progress_of(std::size_t index) {
  if (sends_) return [this, index](const Progress& pr) { exchange_->post_progress(index, pr); };
  return [this, index](const Progress& pr) { clock_->update(index, runs_[index].label, pr); };
}

// How a crash inside a plugin names the run (engine/plugin_calls.hpp): set on the thread that
// builds its engine.
void StudyRunner::name_run(std::size_t index) const {
  std::string name;
  if (job::distributed()) name = "rank " + std::to_string(job::rank()) + " of " + std::to_string(job::size()) + ", ";
  if (runs_.size() > 1 || !runs_[index].label.empty())
    name += "run " + std::to_string(index + 1) + " of " + std::to_string(runs_.size());
  if (!runs_[index].label.empty()) name += " (" + runs_[index].label + ")";
  if (name.size() >= 2 && name.compare(name.size() - 2, 2, ", ") == 0) name.resize(name.size() - 2);
  set_thread_run_name(std::move(name));
}

// A run of this process that has finished: counted here, or (a rank other than 0) its results sent
// to rank 0.
void StudyRunner::done(std::size_t index) {
  if (!sends_) return finish(index);
  exchange_->post_result(index, save_run_results(runs_[index].results));
  runs_[index].results = RunResults{};
}

// This process's runs one after the other on this thread.
void StudyRunner::run_serial() {
  // Serial: the engine polls the interrupt flag itself; an error ends the study at once.
  for (std::size_t index = 0; index < runs_.size(); ++index) {
    name_run(index);
    if (!ranks_) {
      execute(cases_[runs_[index].case_index], runs_[index], progress_of(index), clock_->interval(), index, interrupt_,
              per_run_, checkpoints_, particles_, nullptr);
      finish(index);
      continue;
    }
    // Decomposed: an interrupt is agreed by every rank at a step; any other failure ends the job.
    try {
      execute(cases_[runs_[index].case_index], runs_[index], progress_of(index), clock_->interval(), index, interrupt_,
              per_run_, checkpoints_, particles_, ranks_);
    } catch (const Engine::Interrupted&) {
      throw;
    } catch (const std::exception& e) {
      if (ranks_->size() == 1) throw;  // alone: reported and cleaned up as any failed run
      std::cerr << "gdsmc: rank " << ranks_->rank() << " of " << ranks_->size() << ": error: "
                << (runs_[index].label.empty() ? "" : runs_[index].label + ": ") << failure_text(e, nullptr)
                << "\ngdsmc: the decomposed run failed on this rank; the job is ended, nothing was written\n"
                << std::flush;
      job::abort_job(1);
    }
    if (ranks_->root()) finish(index);
  }
}

// A worker thread: takes this process's runs in study order until none is left or the study stops.
// Run `index` on a worker of the study's pool; once a run has failed (or the user interrupted),
// the runs not yet begun are skipped.
void StudyRunner::execute_run(std::size_t index) {
  if (stop_.load()) return;
  try {
    if (sends_) exchange_->post_started(index);  // rank 0 names it if this rank dies
    name_run(index);
    execute(cases_[runs_[index].case_index], runs_[index], progress_of(index), clock_->interval(), index, &stop_,
            per_run_, checkpoints_, particles_, nullptr);
    done(index);
  } catch (...) {
    runs_[index].error = std::current_exception();
    stop_.store(true);
  }
}

// What rank 0's main thread does with what the other ranks send: their progress to the clock, each
// finished run read and counted as its own.
job::RunExchange::Receiver StudyRunner::make_receiver() {
  job::RunExchange::Receiver receiver;
  receiver.progress = [this](std::size_t index, const Progress& pr) { clock_->update(index, runs_[index].label, pr); };
  receiver.result = [this](std::size_t index, const std::vector<unsigned char>& bytes) {
    try {
      runs_[index].results = load_run_results(bytes);
      finish(index);
    } catch (...) {
      if (!received_error_) received_error_ = std::current_exception();
      stop_.store(true);
    }
  };
  return receiver;
}

// This process's runs on the worker threads while the main thread waits; throws the study's first
// failure (of this process, or over MPI ranks of another) or Engine::Interrupted.
void StudyRunner::run_parallel(StudyResult& result) {
  // Workers stop at the user's interrupt or at the first failed run (`stop`, polled by every
  // engine), or when another rank failed or was interrupted; the main thread forwards the
  // interrupt flag while it waits, and exchanges the ranks' messages.
  const job::RunExchange::Receiver receiver = make_receiver();
  {
    WorkPool pool(workers_ + 1);  // workers_ workers; this thread polls beside them
    pool.run_beside(
        mine_.size(), [this](std::size_t k) { execute_run(mine_[k]); },
        [&] {
          if (interrupt_ && interrupt_->load()) stop_.store(true);
          if (!exchange_) return;
          try {
            exchange_->poll(stop_, receiver);
          } catch (...) {
            stop_.store(true);  // the runs under way end at their next poll of stop_
            throw;
          }
        },
        std::chrono::milliseconds(exchange_ ? 20 : 50));
  }
  // The first run (in study order) that failed of itself; the runs stopped because of it, or by
  // the user, were interrupted and say nothing new.
  std::exception_ptr first_error;
  std::size_t first_failed = 0;
  for (std::size_t index = 0; index < runs_.size() && !first_error; ++index) {
    if (!runs_[index].error) continue;
    try {
      std::rethrow_exception(runs_[index].error);
    } catch (const Engine::Interrupted&) {
      continue;
    } catch (...) {
      first_error = runs_[index].error;
      first_failed = index;
    }
  }
  if (exchange_) end_exchange(result, receiver, first_error, first_failed);
  if (first_error) std::rethrow_exception(first_error);
  if (stop_.load()) throw Engine::Interrupted();
}

// Over MPI ranks, once this process's workers have ended: how it ended exchanged with the other
// ranks; throws another rank's failure (or loss, or interrupt) and results that could not be read,
// and counts what rank 0 received.
void StudyRunner::end_exchange(StudyResult& result, const job::RunExchange::Receiver& receiver,
                               const std::exception_ptr& first_error, std::size_t first_failed) {
  std::optional<job::RunExchange::Failure> failure;
  if (first_error) {
    try {
      std::rethrow_exception(first_error);
    } catch (const std::exception& e) {
      failure = job::RunExchange::Failure::of(first_failed, failure_text(e, nullptr));
    } catch (...) {
      failure = job::RunExchange::Failure::of(first_failed, "an exception that is not a std::exception");
    }
  }
  const auto other = exchange_->finish(stop_, receiver, failure, interrupt_ && interrupt_->load());
  if (other && other->lost) throw RankLost(lost_rank_text(*other, runs_));
  if (other && (!first_error || other->run < first_failed))
    throw RankFailure(other->message + (runs_[other->run].label.empty() ? "" : " (run " + runs_[other->run].label + ")"));
  if (received_error_) std::rethrow_exception(received_error_);
  if (exchange_->others_interrupted()) throw Engine::Interrupted();
  const job::RunExchange::Received received = exchange_->received();
  result.received_runs = received.runs;
  result.received_bytes = received.bytes;
  result.received_seconds = received.seconds;
}

// The study's result (on rank 0) from its gathered cases, in case order.
void StudyRunner::assemble(StudyResult& result, bool sweep) {
  for (std::size_t ci = 0; ci < cases_.size(); ++ci) {
    const StudyCase& sc = cases_[ci];
    const Pipeline& p = sc.pipeline;
    for (std::uint32_t r = 0; r < p.realizations; ++r) {
      result.collisions += runs_[first_run_[ci] + r].results.collisions;
      result.steps += runs_[first_run_[ci] + r].results.steps;
    }
    CaseOutput case_out = std::move(*gathered_[ci]);
    if (sweep) {
      case_out.group = "cases/" + std::to_string(ci);
      case_out.attributes["case"] = sc.label;
      for (const auto& [axis, value] : sc.axis_values) case_out.attributes["sweep." + axis] = value;
      result.summary.push_back("case " + std::to_string(ci) + ": " + sc.label);
      for (const auto& line : case_summaries_[ci]) result.summary.push_back("  " + line);
    } else {
      for (const auto& line : case_summaries_[ci]) result.summary.push_back(line);
    }
    if (p.realizations > 1) add_realization_lines(case_out.diagnostics, p.realizations, sweep, result.summary);
    result.output.cases.push_back(std::move(case_out));
  }
  if (sweep) result.output.summary = summary_table(cases_, result.output.cases);
  result.wall_seconds = clock_->elapsed();
  result.threads = workers_;
}

}  // namespace

StudyResult run_study(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                      double report_interval, const std::atomic<bool>* interrupt, const CheckpointStore* checkpoints,
                      const ParticleStager* particles, Decomposition* ranks) {
  StudyResult result;
  describe_provenance(cases.front().pipeline, result.output);
  const bool sweep = cases.size() > 1 || !cases.front().label.empty();
  StudyRunner study(cases, report, report_interval, interrupt, checkpoints, particles, ranks);
  if (study.serial())
    study.run_serial();
  else
    study.run_parallel(result);
  if (study.sends()) return result;  // rank 0 holds the study's results
  study.assemble(result, sweep);
  return result;
}

}  // namespace gdsmc::host
