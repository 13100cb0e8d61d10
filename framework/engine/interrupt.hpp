// Stopping a run on SIGINT or SIGTERM: the flag the signal handler sets is polled between steps
// and inside the long stages of a step, so that every run ends promptly however large it is.
#pragma once
#include <atomic>
#include <stdexcept>

namespace gdsmc::host {

struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted") {}
};

// Throws Interrupted once *flag is set (a relaxed load: cheap enough to poll every few thousand
// candidates or cells). A null flag is never set.
inline void poll_interrupt(const std::atomic<bool>* flag) {
  if (flag && flag->load(std::memory_order_relaxed)) throw Interrupted();
}

}  // namespace gdsmc::host
