#include "engine/work_pool.hpp"

#include <chrono>
#include <stdexcept>

namespace gdsmc::host {

WorkPool::WorkPool(unsigned threads) {
  for (unsigned t = 1; t < threads; ++t) workers_.emplace_back([this] { work(); });
}

WorkPool::~WorkPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkPool::take_pieces() {
  for (;;) {
    if (failed_.load(std::memory_order_relaxed)) return;
    const std::size_t k = next_.fetch_add(1, std::memory_order_relaxed);
    if (k >= count_) return;
    try {
      call_(piece_, k);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_ || k < error_index_) {
        error_ = std::current_exception();
        error_index_ = k;
      }
      failed_.store(true, std::memory_order_relaxed);
    }
  }
}

namespace {
// Spin until done() or kSpinSeconds have passed; true if done() came true.
template <class Done>
bool spin_until(Done&& done, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  for (unsigned k = 1;; ++k) {
    if (done()) return true;
    cpu_relax();
    if (k % 64 == 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
      return done();
  }
}
}  // namespace

void WorkPool::work() {
  std::uint64_t seen = 0;
  for (;;) {
    if (!spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; }, kSpinSeconds)) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || generation_.load(std::memory_order_acquire) != seen; });
      if (quit_) return;
    }
    seen = generation_.load(std::memory_order_acquire);
    take_pieces();
    if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);  // the caller may be about to sleep: notify under the lock
      done_.notify_all();
    }
  }
}

void WorkPool::start(std::size_t count, Trampoline call, void* piece) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    call_ = call;
    piece_ = piece;
    count_ = count;
    next_.store(0);
    failed_.store(false);
    error_ = nullptr;
    busy_.store(static_cast<unsigned>(workers_.size()), std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
}

// Once every worker has reported back: the job's exception, if a piece threw.
std::exception_ptr WorkPool::end_job() {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return busy_.load(std::memory_order_acquire) == 0; });
  piece_ = nullptr;
  std::exception_ptr error = error_;
  error_ = nullptr;
  return error;
}

void WorkPool::run_erased(std::size_t count, Trampoline call, void* piece) {
  start(count, call, piece);
  take_pieces();
  spin_until([&] { return busy_.load(std::memory_order_acquire) == 0; }, kSpinSeconds);
  if (std::exception_ptr error = end_job()) std::rethrow_exception(error);
}

void WorkPool::run_beside(std::size_t count, const std::function<void(std::size_t)>& piece,
                          const std::function<void()>& beside, std::chrono::milliseconds period) {
  if (workers_.empty()) throw std::logic_error("WorkPool::run_beside needs a worker thread");
  using P = const std::function<void(std::size_t)>;
  start(count, [](void* f, std::size_t k) { (*static_cast<P*>(f))(k); },
        const_cast<void*>(static_cast<const void*>(&piece)));
  std::exception_ptr beside_error;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (done_.wait_for(lock, period, [&] { return busy_.load(std::memory_order_acquire) == 0; })) break;
    }
    try {
      beside();
    } catch (...) {
      beside_error = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);  // no further piece starts; the running ones end
      break;
    }
  }
  std::exception_ptr error = end_job();  // the workers are done with `piece` before it goes
  if (beside_error) std::rethrow_exception(beside_error);
  if (error) std::rethrow_exception(error);
}

}  // namespace gdsmc::host
