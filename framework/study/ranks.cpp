#include "study/ranks.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>

#include <gdsmc/state.hpp>

#ifdef GDSMC_WITH_MPI
#define OMPI_SKIP_MPICXX 1  // the C API alone (the deprecated C++ bindings need another library)
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace gdsmc::host::job {

namespace {

int g_rank = 0, g_size = 1, g_node_ranks = 1;
bool g_started = false;

// The environment variables by which launchers number their processes: Open MPI's mpirun, PMIx
// (srun --mpi=pmix, prrte), PMI-1/PMI-2 (MPICH's hydra, srun --mpi=pmi2).
const char* const kRankVariables[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"};

#ifdef GDSMC_WITH_MPI
enum Tag : int { kProgress = 1, kResultHead, kResultData, kEnd, kStop, kFinal };
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
  if (g_started) MPI_Finalize();
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
  if (distributed() && root())
    for (int r = 1; r < size(); ++r) MPI_Send(&status, 1, MPI_INT, r, kFinal, MPI_COMM_WORLD);
#endif
  return status;
}

int await_status() {
#ifdef GDSMC_WITH_MPI
  // Polled (a blocking receive spins a core that rank 0 may need for the final write); a stop
  // rank 0 sent before the job ended is ignored.
  while (distributed() && !root()) {
    if (const auto st = probe(0, MPI_ANY_TAG)) {
      if (st->MPI_TAG != kFinal) {
        receive_bytes(*st);
        continue;
      }
      int status = 1;
      MPI_Recv(&status, 1, MPI_INT, 0, kFinal, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      return status;
    }
    std::this_thread::sleep_for(kPause);
  }
#endif
  return 0;
}

struct RunExchange::State {
  std::vector<int> owner;  // rank of each run
  std::mutex mutex;        // the queues, filled by worker threads
  std::vector<std::pair<std::size_t, Progress>> progress;
  std::vector<std::pair<std::size_t, std::vector<unsigned char>>> results;
  // Rank 0
  bool stop_sent = false;
  int ended = 0;
  std::vector<Failure> failures;
  bool others_interrupted = false;
  Received received;
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
}

RunExchange::~RunExchange() = default;

bool RunExchange::mine(std::size_t run) const { return s_->owner[run] == rank(); }

void RunExchange::post_progress(std::size_t run, const Progress& progress) {
  std::lock_guard<std::mutex> lock(s_->mutex);
  s_->progress.emplace_back(run, progress);
}

void RunExchange::post_result(std::size_t run, std::vector<unsigned char> bytes) {
  std::lock_guard<std::mutex> lock(s_->mutex);
  s_->results.emplace_back(run, std::move(bytes));
}

void RunExchange::poll(std::atomic<bool>& stop, const Receiver& receiver) {
#ifdef GDSMC_WITH_MPI
  if (!root()) {
    if (const auto st = probe(0, kStop)) {
      receive_bytes(*st);
      stop.store(true);
    }
    decltype(s_->progress) progress;
    decltype(s_->results) results;
    {
      std::lock_guard<std::mutex> lock(s_->mutex);
      progress.swap(s_->progress);
      results.swap(s_->results);
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
    return;
  }
  while (const auto st = probe(MPI_ANY_SOURCE, MPI_ANY_TAG)) {
    const int from = st->MPI_SOURCE;
    if (st->MPI_TAG == kProgress) {
      const std::vector<unsigned char> bytes = receive_bytes(*st);
      std::uint64_t run = 0;
      Progress pr;
      std::memcpy(&run, bytes.data(), sizeof run);
      std::memcpy(&pr, bytes.data() + sizeof run, sizeof pr);
      if (receiver.progress) receiver.progress(run, pr);
    } else if (st->MPI_TAG == kResultHead) {
      const auto start = std::chrono::steady_clock::now();
      std::uint64_t head[2];
      MPI_Recv(head, 2, MPI_UINT64_T, from, kResultHead, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      std::vector<unsigned char> bytes(head[1]);
      for (std::size_t at = 0; at < bytes.size(); at += kChunk)
        MPI_Recv(bytes.data() + at, static_cast<int>(std::min(kChunk, bytes.size() - at)), MPI_BYTE, from, kResultData,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      receiver.result(head[0], bytes);
      s_->received.runs += 1;
      s_->received.bytes += static_cast<double>(bytes.size());
      s_->received.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } else if (st->MPI_TAG == kEnd) {
      const std::vector<unsigned char> bytes = receive_bytes(*st);
      BufferStateReader in(bytes);
      std::uint32_t how = 0;
      std::uint64_t run = 0;
      std::string message;
      in.read("ended", how);
      in.read("run", run);
      in.read("message", message);
      ++s_->ended;
      if (how == 1) s_->failures.push_back({run, "rank " + std::to_string(from) + ": " + message});
      if (how == 2) s_->others_interrupted = true;
      if (how != 0) stop.store(true);
    } else {
      receive_bytes(*st);  // nothing else is sent to rank 0
    }
  }
  if (stop.load() && !s_->stop_sent) {
    s_->stop_sent = true;
    for (int r = 1; r < size(); ++r) MPI_Send(nullptr, 0, MPI_BYTE, r, kStop, MPI_COMM_WORLD);
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
  while (s_->ended < size() - 1) {
    poll(stop, receiver);
    if (s_->ended < size() - 1) std::this_thread::sleep_for(kPause);
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

bool RunExchange::others_interrupted() const { return s_->others_interrupted; }
RunExchange::Received RunExchange::received() const { return s_->received; }

}  // namespace gdsmc::host::job
