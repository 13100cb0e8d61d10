// The threads of one run: the caller and threads - 1 workers that stay parked between the parallel
// stages of a step. Work is always cut into the same pieces (cells, fixed blocks of particles),
// whatever the thread count, and every piece writes only its own results; the engine then adds
// them in piece order, so a run gives the same bits with 1, 2 or more threads.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <type_traits>
#include <mutex>
#include <thread>
#include <vector>

namespace gdsmc::host {

class WorkPool {
 public:
  // threads >= 1; 1 runs every piece on the caller, with no worker thread.
  explicit WorkPool(unsigned threads = 1);
  ~WorkPool();
  WorkPool(const WorkPool&) = delete;
  WorkPool& operator=(const WorkPool&) = delete;

  unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // piece(k) for every k in [0, count), each exactly once, on the caller and the workers; returns
  // when all have returned. Pieces start in increasing k, and a piece that was taken always runs,
  // so a piece may wait for an earlier one (CollisionStage: a layer for its blocks' scatter).
  // Once a piece throws, no further piece starts, and the exception of the lowest-numbered piece
  // that threw is rethrown here.
  template <class F>
  void run(std::size_t count, F&& piece) {
    if (workers_.empty() || count < 2) {
      for (std::size_t k = 0; k < count; ++k) piece(k);
      return;
    }
    using P = std::remove_reference_t<F>;
    run_erased(count, [](void* f, std::size_t k) { (*static_cast<P*>(f))(k); },
               const_cast<void*>(static_cast<const void*>(&piece)));
  }

  // piece(k) for every k in [0, count) on the workers only (threads() >= 2), as run() takes them,
  // while the caller calls beside() about every `period` until all have returned (the study's runs
  // on the workers, the main thread polling the interrupt and the MPI exchange, which only it may
  // call). Exceptions as run(); when beside() throws, no further piece starts, and its exception
  // is rethrown once the pieces begun have returned.
  void run_beside(std::size_t count, const std::function<void(std::size_t)>& piece,
                  const std::function<void()>& beside, std::chrono::milliseconds period);

 private:
  using Trampoline = void (*)(void*, std::size_t);
  void run_erased(std::size_t count, Trampoline call, void* piece);
  void start(std::size_t count, Trampoline call, void* piece);
  std::exception_ptr end_job();
  void work();
  void take_pieces();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  // A new job (generation_) and the end of one (busy_ = 0) are watched by spinning for up to
  // kSpinSeconds before sleeping on the condition variables: a sleeping thread took ~24 us to
  // wake and report back on this machine, ~5 % of a 2-thread step of 1e6 homogeneous particles.
  static constexpr double kSpinSeconds = 50e-6;
  std::atomic<std::uint64_t> generation_{0};
  bool quit_ = false;
  std::atomic<unsigned> busy_{0};
  // The current job (valid while busy_ > 0 or the caller is inside run()).
  Trampoline call_ = nullptr;
  void* piece_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::size_t> next_{0};
  std::atomic<bool> failed_{false};
  std::size_t error_index_ = 0;
  std::exception_ptr error_;
};

// One turn of a spin-wait: the processor's pause hint (or a yield where there is none).
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

// piece(k) for k in [0, count): on the pool, or on the caller when there is none.
template <class F>
void for_pieces(WorkPool* pool, std::size_t count, F&& piece) {
  if (pool) pool->run(count, piece);
  else
    for (std::size_t k = 0; k < count; ++k) piece(k);
}

}  // namespace gdsmc::host
