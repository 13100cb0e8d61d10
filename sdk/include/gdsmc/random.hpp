// gdsmc SDK: counter-based random numbers (Philox4x32-10, Salmon et al., SC'11).
//
// Every piece of work draws from its own stream, identified by
//   key     = (run seed, realization)
//   counter = (purpose, unit, step, position in the stream)
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

// What a stream is for; the engine and plugins use distinct purposes so streams never overlap.
enum class StreamPurpose : std::uint32_t {
  initial_state = 1,
  collisions = 2,
  forcing = 3,  // unit = forcing index in the pipeline * 2^16 + block
  boundary = 4,
  diagnostic = 5,
  conformance = 6,
  user = 100,
};

// A stream of random numbers. Cheap to construct; copyable; never shared between threads.
class Rng {
 public:
  Rng() = default;
  Rng(PhiloxKey key, StreamPurpose purpose, std::uint32_t unit, std::uint64_t step)
      : key_(key),
        ctr_{0u, unit, static_cast<std::uint32_t>(step),
             (static_cast<std::uint32_t>(purpose) << 24) ^ static_cast<std::uint32_t>(step >> 32)} {}

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
  // Uniform integer in [0, n), n > 0, exactly unbiased (Lemire's multiply-shift with rejection;
  // the rejection happens with probability below n / 2^32).
  std::uint32_t below(std::uint32_t n) {
    std::uint64_t m = static_cast<std::uint64_t>(next_u32()) * n;
    auto low = static_cast<std::uint32_t>(m);
    if (low < n) {
      const std::uint32_t threshold = static_cast<std::uint32_t>(-n) % n;
      while (low < threshold) {
        m = static_cast<std::uint64_t>(next_u32()) * n;
        low = static_cast<std::uint32_t>(m);
      }
    }
    return static_cast<std::uint32_t>(m >> 32);
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

}  // namespace gdsmc
