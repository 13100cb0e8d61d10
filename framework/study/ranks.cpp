#include "study/ranks.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>

#include <gdsmc/state.hpp>

#include "study/mpi_api.hpp"

namespace gdsmc::host::job {

namespace {

int g_rank = 0, g_size = 1, g_node_ranks = 1;
bool g_started = false;
// A rank was lost (rank 0 found it, and told the others with the exit status); on rank 0, which.
bool g_lost = false;
std::vector<char> g_lost_ranks;
// Rank 0's process, when this rank runs on the same host and in the same PID namespace (0
// otherwise, and on rank 0); whether it is gone, and whether this rank is the lowest such one.
pid_t g_root_pid = 0;
bool g_root_gone = false, g_root_watcher = false;
// SIGCONTs received: mpirun's first signal to every rank when it ends the job.
std::atomic<unsigned> g_continued{0};
static_assert(std::atomic<unsigned>::is_always_lock_free, "counted from a signal handler");
extern "C" void on_continue(int) { g_continued.fetch_add(1, std::memory_order_relaxed); }

// The environment variables by which launchers number their processes: Open MPI's mpirun, PMIx
// (srun --mpi=pmix, prrte), PMI-1/PMI-2 (MPICH's hydra, srun --mpi=pmi2).
const char* const kRankVariables[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"};

#ifdef GDSMC_WITH_MPI
enum Tag : int { kProgress = 1, kResultHead, kResultData, kEnd, kStop, kFinal, kStarted, kRollCall, kHere };
constexpr std::size_t kChunk = std::size_t{1} << 30;  // MPI counts are int: results go in chunks of 1 GiB
constexpr auto kPause = std::chrono::milliseconds(10);  // between polls of a rank that only waits

void send_bytes(const std::vector<unsigned char>& bytes, int to, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}
std::vector<unsigned char> receive_bytes(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_BYTE, &count);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}
std::optional<MPI_Status> probe(int source, int tag) {
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  return status;
}

// Whether rank 0's process has ended (known only on its host): then this rank stops, says nothing
// more to rank 0 and does not finalise MPI.
bool root_gone_now() {
  if (!g_root_gone && g_root_pid > 0 && ::kill(g_root_pid, 0) != 0 && errno == ESRCH) g_root_gone = g_lost = true;
  return g_root_gone;
}

// "HOST NS " of this process (its host name and PID namespace, as /proc/self/ns/pid names it), to
// which rank 0 appends its PID; "" when either is unknown.
std::string host_and_namespace() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0 || !host[0]) return "";
  char link[128] = {};
  const ssize_t n = ::readlink("/proc/self/ns/pid", link, sizeof link - 1);  // "pid:[4026531836]"
  std::string ns;
  for (ssize_t k = 0; k < std::max<ssize_t>(n, 0); ++k)
    if (link[k] >= '0' && link[k] <= '9') ns += link[k];
  if (ns.empty()) return "";
  return std::string(host) + " " + ns + " ";
}
#endif

}  // namespace

std::string build_text() {
#ifdef GDSMC_WITH_MPI
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string library(text, static_cast<std::size_t>(std::max(length, 0)));
  library = library.substr(0, library.find_first_of(",\n"));
  return "with MPI (" + library + ")";
#else
  return "without MPI";
#endif
}

int launcher_rank() {
  for (const char* name : kRankVariables)
    if (const char* value = std::getenv(name); value && *value) return std::atoi(value);
  return 0;
}

Session::Session() {
#ifdef GDSMC_WITH_MPI
  bool launched = false;
  for (const char* name : kRankVariables) launched = launched || std::getenv(name) != nullptr;
  // Not launched: no MPI_Init (a singleton start would look for a launcher, or start one).
  if (!launched) return;
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Init_thread failed");
  g_started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &g_node_ranks);
  MPI_Comm_free(&node);
  g_lost = false;
  g_lost_ranks.assign(static_cast<std::size_t>(g_size), 0);
  g_root_pid = 0;
  g_root_gone = g_root_watcher = false;
  if (g_size > 1) {
    // Rank 0's host, PID namespace and PID: a rank beside it can tell when it is gone.
    const std::string mine = host_and_namespace();
    char root[512] = {};
    if (g_rank == 0) std::snprintf(root, sizeof root, "%s%ld", mine.c_str(), static_cast<long>(::getpid()));
    MPI_Bcast(root, sizeof root, MPI_CHAR, 0, MPI_COMM_WORLD);
    const std::string root_id(root);
    if (g_rank > 0 && !mine.empty() && root_id.compare(0, mine.size(), mine) == 0)
      g_root_pid = static_cast<pid_t>(std::atol(root_id.c_str() + mine.size()));
    int watcher = g_root_pid > 0 ? g_rank : g_size;
    MPI_Allreduce(MPI_IN_PLACE, &watcher, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    g_root_watcher = watcher == g_rank;
    struct sigaction action {};
    action.sa_handler = on_continue;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGCONT, &action, nullptr);
  }
#else
  // Every rank would run the whole study and write the same file.
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!size) size = std::getenv("PMI_SIZE");
  if (launcher_rank() > 0 || (size && std::atoi(size) > 1))
    throw std::runtime_error("this gdsmc was built without MPI (gdsmc --version), but a launcher started it as "
                             "one of several ranks, each of which would run the whole study: run it without "
                             "mpirun/srun, or build gdsmc with MPI (libopenmpi-dev installed, -DGDSMC_WITH_MPI=ON)");
#endif
}

Session::~Session() {
#ifdef GDSMC_WITH_MPI
  // MPI_Finalize waits for every rank, a lost one too (until mpirun's SIGKILL): the job is over.
  if (g_started && !g_lost) MPI_Finalize();
#endif
  g_started = false;
  g_rank = 0;
  g_size = g_node_ranks = 1;
}

int rank() { return g_rank; }
int size() { return g_size; }
int ranks_on_this_node() { return g_node_ranks; }

int root_value(int value) {
#ifdef GDSMC_WITH_MPI
  if (distributed()) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  return value;
}

int largest(int value) {
#ifdef GDSMC_WITH_MPI
  if (distributed()) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
#endif
  return value;
}

int conclude(int status) {
#ifdef GDSMC_WITH_MPI
  if (distributed() && root()) {
    const int final[2] = {status, g_lost ? 1 : 0};
    for (int r = 1; r < size(); ++r)
      if (!g_lost_ranks[static_cast<std::size_t>(r)]) MPI_Send(final, 2, MPI_INT, r, kFinal, MPI_COMM_WORLD);
  }
#endif
  return status;
}

int await_status() {
#ifdef GDSMC_WITH_MPI
  // Polled (a blocking receive spins a core that rank 0 may need for the final write); a stop
  // rank 0 sent before the job ended is ignored, a roll call answered.
  while (distributed() && !root()) {
    if (root_gone_now()) return 1;
    if (const auto st = probe(0, MPI_ANY_TAG)) {
      if (st->MPI_TAG != kFinal) {
        receive_bytes(*st);
        if (st->MPI_TAG == kRollCall) MPI_Send(nullptr, 0, MPI_BYTE, 0, kHere, MPI_COMM_WORLD);
        continue;
      }
      int final[2] = {1, 0};
      MPI_Recv(final, 2, MPI_INT, 0, kFinal, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      g_lost = final[1] != 0;
      return final[0];
    }
    std::this_thread::sleep_for(kPause);
  }
#endif
  return 0;
}

struct RunExchange::State {
  std::vector<int> owner;  // rank of each run
  std::mutex mutex;        // the queues, filled by worker threads
  std::vector<std::size_t> started;
  std::vector<std::pair<std::size_t, Progress>> progress;
  std::vector<std::pair<std::size_t, std::vector<unsigned char>>> results;
  // Rank 0
  bool stop_sent = false;
  std::vector<char> ended, lost;             // by rank
  std::vector<std::set<std::size_t>> under_way;  // by rank: runs started and not received
  std::vector<char> run_received;                // by run
  // The roll call under way (since `called`): which ranks have answered.
  unsigned continued_seen = 0;
  bool calling = false;
  std::chrono::steady_clock::time_point called;
  std::vector<char> answered;
  std::vector<Failure> failures;
  bool others_interrupted = false;
  Received received;

  int unaccounted() const {  // ranks other than 0 that have neither ended nor been lost
    int n = 0;
    for (std::size_t r = 1; r < ended.size(); ++r) n += !ended[r] && !lost[r];
    return n;
  }
};

RunExchange::RunExchange(const std::vector<double>& costs) : s_(std::make_unique<State>()) {
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(static_cast<std::size_t>(size()), 0.0);
  s_->owner.assign(costs.size(), 0);
  for (std::size_t run : order) {
    const auto least = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    s_->owner[run] = static_cast<int>(least);
    load[least] += costs[run];
  }
  const auto ranks = static_cast<std::size_t>(size());
  s_->ended.assign(ranks, 0);
  s_->lost.assign(ranks, 0);
  s_->answered.assign(ranks, 0);
  s_->under_way.assign(ranks, {});
  s_->run_received.assign(costs.size(), 0);
  s_->continued_seen = g_continued.load();
}

RunExchange::~RunExchange() = default;

bool RunExchange::mine(std::size_t run) const { return s_->owner[run] == rank(); }

void RunExchange::post_started(std::size_t run) {
  std::lock_guard<std::mutex> lock(s_->mutex);
  s_->started.push_back(run);
}

void RunExchange::post_progress(std::size_t run, const Progress& progress) {
  std::lock_guard<std::mutex> lock(s_->mutex);
  s_->progress.emplace_back(run, progress);
}

void RunExchange::post_result(std::size_t run, std::vector<unsigned char> bytes) {
  std::lock_guard<std::mutex> lock(s_->mutex);
  s_->results.emplace_back(run, std::move(bytes));
}

#ifdef GDSMC_WITH_MPI
// Rank > 0: stops at rank 0's stop (or when rank 0 is gone), answers its roll calls, and sends it
// what the worker threads queued.
void RunExchange::send_to_root(std::atomic<bool>& stop) {
  if (root_gone_now()) {
    stop.store(true);
    return;
  }
  // A stop, or a roll call (answered at once). kFinal only comes once this rank has ended.
  while (const auto st = probe(0, MPI_ANY_TAG)) {
    receive_bytes(*st);
    if (st->MPI_TAG == kStop) stop.store(true);
    if (st->MPI_TAG == kRollCall) MPI_Send(nullptr, 0, MPI_BYTE, 0, kHere, MPI_COMM_WORLD);
  }
  decltype(s_->started) started;
  decltype(s_->progress) progress;
  decltype(s_->results) results;
  {
    std::lock_guard<std::mutex> lock(s_->mutex);
    started.swap(s_->started);
    progress.swap(s_->progress);
    results.swap(s_->results);
  }
  for (const std::size_t run : started) {
    const auto index = static_cast<std::uint64_t>(run);
    MPI_Send(&index, 1, MPI_UINT64_T, 0, kStarted, MPI_COMM_WORLD);
  }
  // Progress first: a run's final report reaches rank 0 before its results.
  for (const auto& [run, pr] : progress) {
    std::vector<unsigned char> bytes(sizeof(std::uint64_t) + sizeof(Progress));
    const auto index = static_cast<std::uint64_t>(run);
    std::memcpy(bytes.data(), &index, sizeof index);
    std::memcpy(bytes.data() + sizeof index, &pr, sizeof pr);
    send_bytes(bytes, 0, kProgress);
  }
  for (const auto& [run, bytes] : results) {
    const std::uint64_t head[2] = {run, bytes.size()};
    MPI_Send(head, 2, MPI_UINT64_T, 0, kResultHead, MPI_COMM_WORLD);
    for (std::size_t at = 0; at < bytes.size(); at += kChunk)
      MPI_Send(bytes.data() + at, static_cast<int>(std::min(kChunk, bytes.size() - at)), MPI_BYTE, 0, kResultData,
               MPI_COMM_WORLD);
  }
}

// Rank 0: asks every rank that has neither ended nor been lost to answer, unless a roll call is
// under way.
void RunExchange::call_roll() {
  if (s_->calling) return;
  s_->calling = true;
  s_->called = std::chrono::steady_clock::now();
  for (int r = 1; r < size(); ++r) {
    const auto ri = static_cast<std::size_t>(r);
    s_->answered[ri] = 0;
    if (!s_->ended[ri] && !s_->lost[ri]) MPI_Send(nullptr, 0, MPI_BYTE, r, kRollCall, MPI_COMM_WORLD);
  }
}

// Rank 0: a finished run from rank `from` (its head probed), received in chunks and handed to the receiver.
void RunExchange::receive_result(int from, std::atomic<bool>& stop, const Receiver& receiver) {
  const auto from_index = static_cast<std::size_t>(from);
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t head[2];
  MPI_Recv(head, 2, MPI_UINT64_T, from, kResultHead, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::vector<unsigned char> bytes(head[1]);
  for (std::size_t at = 0; at < bytes.size(); at += kChunk)
    MPI_Recv(bytes.data() + at, static_cast<int>(std::min(kChunk, bytes.size() - at)), MPI_BYTE, from, kResultData,
             MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  s_->under_way[from_index].erase(head[0]);
  if (head[0] < s_->run_received.size()) s_->run_received[head[0]] = 1;
  // A stopped job writes nothing: its results are not worth gathering (the main thread answers
  // the next roll call sooner).
  if (!stop.load()) receiver.result(head[0], bytes);
  s_->received.runs += 1;
  s_->received.bytes += static_cast<double>(bytes.size());
  s_->received.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Rank 0: every message the other ranks have sent so far (answers, runs started, progress, finished
// runs, how a rank ended).
void RunExchange::receive_from_ranks(std::atomic<bool>& stop, const Receiver& receiver) {
  while (const auto st = probe(MPI_ANY_SOURCE, MPI_ANY_TAG)) {
    const int from = st->MPI_SOURCE;
    const auto from_index = static_cast<std::size_t>(from);
    if (st->MPI_TAG == kHere) {
      receive_bytes(*st);
      s_->answered[from_index] = 1;
    } else if (st->MPI_TAG == kStarted) {
      std::uint64_t run = 0;
      MPI_Recv(&run, 1, MPI_UINT64_T, from, kStarted, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (run < s_->run_received.size() && !s_->run_received[run]) s_->under_way[from_index].insert(run);
    } else if (st->MPI_TAG == kProgress) {
      const std::vector<unsigned char> bytes = receive_bytes(*st);
      std::uint64_t run = 0;
      Progress pr;
      std::memcpy(&run, bytes.data(), sizeof run);
      std::memcpy(&pr, bytes.data() + sizeof run, sizeof pr);
      if (receiver.progress) receiver.progress(run, pr);
    } else if (st->MPI_TAG == kResultHead) {
      receive_result(from, stop, receiver);
    } else if (st->MPI_TAG == kEnd) {
      const std::vector<unsigned char> bytes = receive_bytes(*st);
      BufferStateReader in(bytes);
      std::uint32_t how = 0;
      std::uint64_t run = 0;
      std::string message;
      in.read("ended", how);
      in.read("run", run);
      in.read("message", message);
      s_->ended[from_index] = 1;
      if (how == 1) s_->failures.push_back(Failure::of(run, "rank " + std::to_string(from) + ": " + message));
      if (how == 2) s_->others_interrupted = true;
      if (how != 0) stop.store(true);
    } else {
      receive_bytes(*st);  // nothing else is sent to rank 0
    }
  }
}

// Rank 0: the roll call under way, ended once kRollCallSeconds have passed since it began.
void RunExchange::end_roll_call(std::atomic<bool>& stop) {
  // The roll call's end: a rank that has neither answered nor ended is lost.
  if (s_->calling &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - s_->called).count() >= kRollCallSeconds) {
    s_->calling = false;
    for (int r = 1; r < size(); ++r) {
      const auto ri = static_cast<std::size_t>(r);
      if (s_->answered[ri] || s_->ended[ri] || s_->lost[ri]) continue;
      s_->lost[ri] = 1;
      g_lost = true;
      g_lost_ranks[ri] = 1;
      Failure f;
      f.lost = true;
      f.rank = r;
      f.under_way.assign(s_->under_way[ri].begin(), s_->under_way[ri].end());
      f.run = std::numeric_limits<std::size_t>::max();
      if (!f.under_way.empty()) f.run = f.under_way.front();
      else
        for (std::size_t run = 0; run < s_->owner.size() && f.run == std::numeric_limits<std::size_t>::max(); ++run)
          if (s_->owner[run] == r && !s_->run_received[run]) f.run = run;
      f.message = "rank " + std::to_string(r);
      s_->failures.push_back(std::move(f));
      stop.store(true);
    }
  }
}
#endif

void RunExchange::poll(std::atomic<bool>& stop, const Receiver& receiver) {
#ifdef GDSMC_WITH_MPI
  if (!root()) {
    send_to_root(stop);
    return;
  }
  // Rank 0. A roll call at every SIGCONT (and below, when the job stops): every rank that has not
  // ended is asked to answer.
  if (const unsigned continued = g_continued.load(); continued != s_->continued_seen) {
    s_->continued_seen = continued;
    call_roll();
  }
  receive_from_ranks(stop, receiver);
  end_roll_call(stop);
  if (stop.load() && !s_->stop_sent) {
    s_->stop_sent = true;
    for (int r = 1; r < size(); ++r)
      if (!s_->lost[static_cast<std::size_t>(r)]) MPI_Send(nullptr, 0, MPI_BYTE, r, kStop, MPI_COMM_WORLD);
    call_roll();  // a rank that died stops nothing, and would be waited for
  }
#else
  (void)stop;
  (void)receiver;
#endif
}

std::optional<RunExchange::Failure> RunExchange::finish(std::atomic<bool>& stop, const Receiver& receiver,
                                                        const std::optional<Failure>& failure, bool interrupted) {
#ifdef GDSMC_WITH_MPI
  if (!root()) {
    if (root_gone_now()) return std::nullopt;
    // How it ended: 0 done, 1 failed, 2 interrupted (a signal to this rank), 3 stopped by rank 0.
    const std::uint32_t how = failure ? 1 : interrupted ? 2 : stop.load() ? 3 : 0;
    if (how == 0) poll(stop, receiver);  // the last results (not worth sending when the job stops)
    BufferStateWriter out;
    out.write("ended", how);
    out.write("run", static_cast<std::uint64_t>(failure ? failure->run : 0));
    out.write("message", failure ? failure->message : std::string());
    send_bytes(out.bytes(), 0, kEnd);
    return std::nullopt;
  }
  (void)failure;
  (void)interrupted;
  while (s_->unaccounted() > 0) {
    poll(stop, receiver);
    if (s_->unaccounted() > 0) std::this_thread::sleep_for(kPause);
  }
  if (s_->failures.empty()) return std::nullopt;
  return *std::min_element(s_->failures.begin(), s_->failures.end(),
                           [](const Failure& a, const Failure& b) { return a.run < b.run; });
#else
  (void)stop;
  (void)receiver;
  (void)failure;
  (void)interrupted;
  return std::nullopt;
#endif
}

bool root_gone() {
#ifdef GDSMC_WITH_MPI
  if (distributed() && !root()) return root_gone_now();
#endif
  return false;
}
bool watches_root() { return g_root_watcher; }

bool RunExchange::others_interrupted() const { return s_->others_interrupted; }
RunExchange::Received RunExchange::received() const { return s_->received; }

}  // namespace gdsmc::host::job
