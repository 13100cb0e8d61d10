// The ranks of an MPI job (`mpirun -np K gdsmc run`, `srun --mpi=pmix gdsmc run`): a study's runs
// spread over them by expected cost, each finished run's results sent to rank 0, which reduces and
// writes them exactly as the serial study does (docs/cluster.md). Only ranks.cpp and
// slab_ranks.cpp include mpi.h.
// Built without MPI (-DGDSMC_WITH_MPI=OFF), or started without a launcher, the job is this process
// alone (rank 0 of 1) and nothing here communicates: MPI is not even initialised.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/engine.hpp"

namespace gdsmc::host::job {

// "with MPI (Open MPI v4.1.4, ...)" or "without MPI": for `gdsmc --version`.
std::string build_text();

// This process's rank as its launcher numbered it (mpirun, mpiexec, srun with PMI/PMIx), read from
// the environment without initialising MPI; 0 when it was not started by one. `validate` runs on
// launcher rank 0 alone.
int launcher_rank();

// Initialises MPI (only the main thread communicates) when a launcher started this process and
// the host was built with MPI; otherwise does nothing. Throws std::runtime_error when it fails,
// and when a host built without MPI was started as one of several ranks. In a job of several
// ranks it also counts the SIGCONTs this process receives: mpirun's first signal to every rank
// when it ends a job (one rank died, or mpirun was interrupted), 1 s before its SIGTERM and 2 s
// before its SIGKILL (Open MPI 4.1, odls_base_sigkill_timeout = 1); rank 0 then asks every rank
// whether it is still there (RunExchange).
// The returned guard finalises MPI, unless a rank was lost (a collective would wait for it).
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

// How long rank 0 waits for the answers to a roll call: a live rank answers from its main thread,
// which polls every few tens of milliseconds, and mpirun's SIGKILL comes 2 s after its SIGCONT.
constexpr double kRollCallSeconds = 0.5;

int rank();             // 0 without MPI
int size();             // 1 without MPI
inline bool root() { return rank() == 0; }
inline bool distributed() { return size() > 1; }
// Ranks on this node (those that share its memory and cores): 1 without MPI.
int ranks_on_this_node();

// Collective steps of `gdsmc run`, called by every rank in the same order (each returns at once
// when the job is not distributed):
// rank 0's value, on every rank.
int root_value(int value);
// The largest of every rank's value, on every rank (a status: 0, or the exit status of a failure).
int largest(int value);
// After the study: rank 0 tells every other rank the job's exit status (conclude), which waits
// for it (await_status) and returns it. Every rank answers rank 0's roll calls while it waits.
int conclude(int status);
int await_status();
// A rank other than 0 that runs on rank 0's host sees rank 0's process end (killed, crashed):
// it then stops its runs, and await_status() returns 1 at once. Elsewhere, and on rank 0: false.
bool root_gone();
// Whether this is the lowest rank on rank 0's host (other than 0): the one that says rank 0 is
// gone and removes its temporary file.
bool watches_root();

// The runs of a distributed study, between the main threads of the ranks (the study's worker
// threads only queue things here). Rank 0 receives every other rank's progress and finished runs;
// a failure or an interrupt on any rank stops every rank.
// A rank can also die without a word (SIGKILL from the OOM killer or a user, a crash in a plugin).
// Rank 0 then finds it by a roll call: at every SIGCONT (mpirun's first signal when it ends the
// job, about 1 s before its SIGTERM and 2 s before its SIGKILL) and when the job stops, it asks
// every rank that has not ended to answer, and a rank whose answer has not come kRollCallSeconds
// later is lost: the job stops, with that rank's runs under way as its failure.
class RunExchange {
 public:
  // Assigns the runs to ranks by expected cost (costs[k] of run k): largest first, each to the
  // rank with the least cost so far (ties: the lower run, the lower rank), the same on every rank.
  explicit RunExchange(const std::vector<double>& costs);
  ~RunExchange();
  bool mine(std::size_t run) const;

  // Worker threads of a rank other than 0: a run started, its progress, and its results once
  // finished (the bytes of save_run_results).
  void post_started(std::size_t run);
  void post_progress(std::size_t run, const Progress& progress);
  void post_result(std::size_t run, std::vector<unsigned char> bytes);

  // What rank 0 does with what the others send (called on its main thread).
  struct Receiver {
    std::function<void(std::size_t run, const Progress&)> progress;
    std::function<void(std::size_t run, const std::vector<unsigned char>&)> result;
  };
  // While this rank's workers run (main thread, every few tens of milliseconds): sends what is
  // queued (ranks > 0), receives (rank 0), and sets `stop` when any rank failed or was interrupted
  // (rank 0 then tells every rank to stop).
  void poll(std::atomic<bool>& stop, const Receiver& receiver);
  // Once this rank's workers have ended. Rank > 0: sends what is left and how it ended (`failure`:
  // the message of its first failed run, in study order, with that run; `interrupted`). Rank 0:
  // receives until every rank has ended or was lost, and returns the first failure of another rank
  // (in study order), "rank R: message" or a lost rank, if any.
  struct Failure {
    std::size_t run = 0;
    std::string message;
    // A rank that was lost (message empty): which, and the runs it had started and not sent (in
    // study order; `run` is the first of them, or of its runs not received when none had started).
    bool lost = false;
    int rank = 0;
    std::vector<std::size_t> under_way;

    static Failure of(std::size_t run, std::string message) {
      Failure f;
      f.run = run;
      f.message = std::move(message);
      return f;
    }
  };
  std::optional<Failure> finish(std::atomic<bool>& stop, const Receiver& receiver, const std::optional<Failure>& failure,
                                bool interrupted);
  // Rank 0, after finish(): whether a rank other than 0 ended because it was interrupted.
  bool others_interrupted() const;
  // Rank 0: the finished runs received from other ranks, their bytes, and the seconds spent
  // receiving them and handing them to the receiver (which reads and gathers them).
  struct Received {
    std::size_t runs = 0;
    double bytes = 0, seconds = 0;
  };
  Received received() const;

 private:
  struct State;
  std::unique_ptr<State> s_;

  // The parts of poll() (defined with MPI alone): a rank other than 0's, and rank 0's roll calls and
  // receiving.
  void send_to_root(std::atomic<bool>& stop);
  void call_roll();
  void receive_from_ranks(std::atomic<bool>& stop, const Receiver& receiver);
  void receive_result(int from, std::atomic<bool>& stop, const Receiver& receiver);
  void end_roll_call(std::atomic<bool>& stop);
};

}  // namespace gdsmc::host::job
