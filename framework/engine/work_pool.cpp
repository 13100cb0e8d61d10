#include "engine/work_pool.hpp"

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

void WorkPool::work() {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
    }
    take_pieces();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--busy_ == 0) done_.notify_all();
    }
  }
}

void WorkPool::run_erased(std::size_t count, Trampoline call, void* piece) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    call_ = call;
    piece_ = piece;
    count_ = count;
    next_.store(0);
    failed_.store(false);
    error_ = nullptr;
    busy_ = static_cast<unsigned>(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  take_pieces();
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0; });
    piece_ = nullptr;
    error = error_;
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace gdsmc::host
