// The host's random streams: the only place that knows the run's key. Each plugin instance gets
// Streams for its own (purpose, instance) at each step; the engine's own draws (collisions per
// cell, boundary hits per particle) use the same layout, so no result depends on the order in
// which cells or particles are processed.
#pragma once
#include <cstdint>

#include <gdsmc/random.hpp>

namespace gdsmc::host {

class StreamFactory {
 public:
  StreamFactory() = default;
  StreamFactory(std::uint64_t seed, std::uint32_t realization) : run_key_(stream_key(seed, realization)) { set_step(0); }

  // Called once at the start of every step: one Philox block mixes the step into the key.
  void set_step(std::uint64_t step) {
    step_ = step;
    step_key_ = step_stream_key(run_key_, step);
  }
  std::uint64_t step() const { return step_; }

  Streams streams(StreamPurpose purpose, std::uint32_t instance) const { return Streams(step_key_, purpose, instance); }
  Rng rng(StreamPurpose purpose, std::uint32_t instance, std::uint64_t unit) const {
    return Rng(step_key_, purpose, instance, unit);
  }
  // A stream outside any run (tests, benchmarks, conformance checks).
  static Rng standalone(std::uint64_t seed, std::uint64_t unit, StreamPurpose purpose = StreamPurpose::host,
                        std::uint64_t step = 0) {
    return Rng(step_stream_key(stream_key(seed, 0), step), purpose, 0, unit);
  }
  static Streams standalone_streams(std::uint64_t seed, StreamPurpose purpose, std::uint32_t instance,
                                    std::uint64_t step = 0) {
    return Streams(step_stream_key(stream_key(seed, 0), step), purpose, instance);
  }

  // Where a stream stands (its key, the counter of its next block, its current block and how many
  // of that block's four numbers it has used), for BulkRng (engine/bulk_rng.hpp), which draws the
  // same numbers ahead and then puts the stream where it left off.
  struct Position {
    PhiloxKey key;
    PhiloxCounter counter, block;
    unsigned used;
  };
  static Position position(const Rng& r) { return {r.key_, r.ctr_, r.block_, r.used_}; }
  static void set_position(Rng& r, const PhiloxCounter& counter, const PhiloxCounter& block, unsigned used) {
    r.ctr_ = counter;
    r.block_ = block;
    r.used_ = used;
  }

 private:
  PhiloxKey run_key_{0u, 0u};
  PhiloxKey step_key_{0u, 0u};
  std::uint64_t step_ = 0;
};

}  // namespace gdsmc::host
