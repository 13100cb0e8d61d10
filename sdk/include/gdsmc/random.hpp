// gdsmc SDK: counter-based random numbers (Philox4x32-10, Salmon et al., SC'11).
//
// Every piece of work draws from its own stream, identified by
//   key     = (run seed, realization, step)
//   counter = (purpose, plugin instance, 64-bit unit, position in the stream)
// so that results depend only on *what* is computed, never on which thread or process computes it.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "gdsmc/vec3.hpp"

namespace gdsmc {

using PhiloxCounter = std::array<std::uint32_t, 4>;
using PhiloxKey = std::array<std::uint32_t, 2>;

// One Philox4x32-10 block: 10 rounds of the bijection, as in Random123.
inline PhiloxCounter philox4x32_10(PhiloxCounter c, PhiloxKey k) {
  constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
  constexpr std::uint32_t W0 = 0x9E3779B9u, W1 = 0xBB67AE85u;
  for (int round = 0; round < 10; ++round) {
    const std::uint64_t p0 = static_cast<std::uint64_t>(M0) * c[0];
    const std::uint64_t p1 = static_cast<std::uint64_t>(M1) * c[2];
    c = {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k[0], static_cast<std::uint32_t>(p1),
         static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k[1], static_cast<std::uint32_t>(p0)};
    k[0] += W0;
    k[1] += W1;
  }
  return c;
}

// The key of a run: derived from (seed, realization) by one Philox block, so nearby seeds and
// realizations give unrelated streams.
inline PhiloxKey stream_key(std::uint64_t seed, std::uint32_t realization) {
  const PhiloxCounter c = philox4x32_10(
      {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), realization,
       0x67647363u /* "gdsc" */},
      {0x5EED5EEDu, 0xC0FFEE11u});
  return {c[0], c[1]};
}

// What a stream is for. Together with the plugin instance and a 64-bit unit (a particle's
// identity, a cell's index) it names a stream; distinct names never share a block.
enum class StreamPurpose : std::uint32_t {
  initial_state = 1,
  collisions = 2,
  forcing = 3,
  boundary = 4,
  diagnostic = 5,
  host = 6,  // the host's own draws (conformance checks, benchmarks, tests)
};

// The key of one step of a run: a second Philox block mixes the step into the run's key, so the
// 128-bit counter is free for (purpose, instance, unit, position).
inline PhiloxKey step_stream_key(PhiloxKey run_key, std::uint64_t step) {
  const PhiloxCounter c = philox4x32_10(
      {static_cast<std::uint32_t>(step), static_cast<std::uint32_t>(step >> 32), 0x73746570u /* "step" */,
       0x6b657973u /* "keys" */},
      run_key);
  return {c[0], c[1]};
}

namespace host {
class StreamFactory;  // the host's only way to make streams (framework/engine/streams.hpp)
}

class Streams;

// A uniform integer in [0, n), n > 0, from uniform 32-bit words next(), exactly unbiased (Lemire's
// multiply-shift with rejection; the rejection happens with probability below n / 2^32): Rng::below,
// and the host's streams drawn ahead, which must give the same numbers.
template <class Next>
inline std::uint32_t uniform_below(std::uint32_t n, Next&& next) {
  std::uint64_t m = static_cast<std::uint64_t>(next()) * n;
  auto low = static_cast<std::uint32_t>(m);
  if (low < n) {
    const std::uint32_t threshold = static_cast<std::uint32_t>(-n) % n;
    while (low < threshold) {
      m = static_cast<std::uint64_t>(next()) * n;
      low = static_cast<std::uint32_t>(m);
    }
  }
  return static_cast<std::uint32_t>(m >> 32);
}

// A stream of random numbers. Copyable; never shared between threads. Plugins receive streams
// from the host (Streams below, or as an argument); they cannot name another plugin's streams.
//
// Counter layout (SDK 2.0): c[0] = position in the stream (blocks of 4 x 32 bits), c[1], c[2] =
// the 64-bit unit, c[3] = purpose (8 bits) << 24 | plugin instance (24 bits); the step is in the
// key (step_stream_key).
class Rng {
 public:
  Rng() = default;

  std::uint32_t next_u32() {
    if (used_ == 4) refill();
    return block_[used_++];
  }
  std::uint64_t next_u64() {
    const std::uint64_t hi = next_u32();
    return (hi << 32) | next_u32();
  }
  // Uniform on [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  // Uniform on (0, 1]: safe for log().
  double uniform_open0() { return (static_cast<double>(next_u64() >> 11) + 1.0) * 0x1.0p-53; }
  // Uniform on [0, 1) with 32 random bits: enough for an acceptance test, half the cost.
  double uniform32() { return static_cast<double>(next_u32()) * 0x1.0p-32; }
  // Uniform integer in [0, n), n > 0, exactly unbiased (uniform_below).
  std::uint32_t below(std::uint32_t n) {
    return uniform_below(n, [this] { return next_u32(); });
  }
  // Standard normal deviate (Box-Muller; both values of a pair are used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double r = std::sqrt(-2.0 * std::log(uniform_open0()));
    const double phi = 2.0 * M_PI * uniform();
    spare_ = r * std::sin(phi);
    has_spare_ = true;
    return r * std::cos(phi);
  }
  // Direction uniformly distributed on the unit sphere (Marsaglia 1972: a point uniform in the
  // unit disc, (u, v) with s = u^2 + v^2 < 1, maps to (2u sqrt(1-s), 2v sqrt(1-s), 1 - 2s);
  // no trigonometric call).
  Vec3 unit_vector() {
    double u, v, s;
    do {
      u = 2.0 * uniform32() - 1.0;
      v = 2.0 * uniform32() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = 2.0 * std::sqrt(1.0 - s);
    return {u * f, v * f, 1.0 - 2.0 * s};
  }

 private:
  friend class Streams;
  friend class host::StreamFactory;
  Rng(PhiloxKey step_key, StreamPurpose purpose, std::uint32_t instance, std::uint64_t unit)
      : key_(step_key),
        ctr_{0u, static_cast<std::uint32_t>(unit), static_cast<std::uint32_t>(unit >> 32),
             (static_cast<std::uint32_t>(purpose) << 24) | (instance & 0xFFFFFFu)} {}
  void refill() {
    block_ = philox4x32_10(ctr_, key_);
    ++ctr_[0];
    used_ = 0;
  }
  PhiloxKey key_{0u, 0u};
  PhiloxCounter ctr_{0u, 0u, 0u, 0u};
  PhiloxCounter block_{0u, 0u, 0u, 0u};
  unsigned used_ = 4;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// The streams of one plugin instance at one step, handed to it by the host: one per particle
// (keyed by its identity, so that no result depends on storage order, threads or ranks) and one
// per unit the plugin chooses (a cell, a sub-task). Cheap to copy.
class Streams {
 public:
  Streams() = default;
  // The stream of particle `id` (ParticleSpan::id) for this plugin at this step.
  Rng for_particle(std::uint64_t id) const { return Rng(key_, purpose_, instance_, id); }
  // A stream for any other unit of work (a cell index, a sample number) at this step.
  Rng for_unit(std::uint64_t unit) const { return Rng(key_, purpose_, instance_ | 0x800000u, unit); }

 private:
  friend class host::StreamFactory;
  Streams(PhiloxKey step_key, StreamPurpose purpose, std::uint32_t instance)
      : key_(step_key), purpose_(purpose), instance_(instance & 0x7FFFFFu) {}
  PhiloxKey key_{0u, 0u};
  StreamPurpose purpose_ = StreamPurpose::host;
  std::uint32_t instance_ = 0;
};

}  // namespace gdsmc
