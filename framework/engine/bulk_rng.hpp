// A selection stream drawn ahead: the numbers of one gdsmc::Rng, made sixteen Philox4x32-10 blocks
// at a time side by side (one vectorized function, compiled for AVX-512, AVX2 and the x86-64
// baseline and chosen when the program loads) instead of one block per four numbers. The same
// 32-bit numbers in the same order, and below / uniform32 / uniform by the Rng's own arithmetic,
// so every result is the same to the bit; rng() hands back an Rng at the same place in the stream.
// For loops that draw many numbers from one stream (CollisionStage::collide_candidates): a
// refill computes 64 numbers, so a stream that needs a handful is better drawn by the Rng itself.
#pragma once
#include <cstdint>
#include <vector>

#include <gdsmc/random.hpp>

namespace gdsmc::host {

// Philox4x32-10 blocks of the counters (first + l, c1, c2, c3), l = 0 .. 15, under `key`: block l's
// four words at out[4l .. 4l+3], as philox4x32_10 gives them.
void philox_sixteen_blocks(PhiloxKey key, std::uint32_t first, std::uint32_t c1, std::uint32_t c2, std::uint32_t c3,
                           std::uint32_t* out);
// Every version of it this processor can run, the baseline first (philox_sixteen_blocks uses the
// last): for the tests, which hold each to philox4x32_10.
using PhiloxSixteen = void (*)(PhiloxKey, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t*);
std::vector<PhiloxSixteen> philox_sixteen_versions();
// Whether philox_sixteen_blocks runs a vector version here (else sixteen blocks cost sixteen).
bool philox_sixteen_vectorized();

class BulkRng {
 public:
  explicit BulkRng(const Rng& rng);
  std::uint32_t next_u32() {
    if (pos_ == kNumbers) refill();
    return buffer_[pos_++];
  }
  // As Rng::uniform32, Rng::uniform and Rng::below.
  double uniform32() { return static_cast<double>(next_u32()) * 0x1.0p-32; }
  double uniform() {
    const std::uint64_t hi = next_u32();
    return static_cast<double>(((hi << 32) | next_u32()) >> 11) * 0x1.0p-53;
  }
  std::uint32_t below(std::uint32_t n) {
    return uniform_below(n, [this] { return next_u32(); });
  }
  // The stream at this place: its next draws are the ones this object would make.
  Rng rng() const;

 private:
  static constexpr unsigned kBlocks = 16, kNumbers = 4 * kBlocks;
  void refill();
  Rng origin_;          // the stream as handed over (its key, unit and purpose; its spare normal)
  std::uint32_t base_;  // the counter of the buffer's first block
  unsigned pos_;
  alignas(64) std::uint32_t buffer_[kNumbers];
};

// body(draws) with draws giving the numbers of `stream`: a BulkRng of it when `ahead`, else a local
// copy (whose state stays in registers across the calls body makes, where a reference's would go to
// memory around each); then `stream` stands where body left it.
template <class Body>
void draw_from(Rng& stream, bool ahead, Body&& body) {
  if (ahead) {
    BulkRng draws(stream);
    body(draws);
    stream = draws.rng();
  } else {
    Rng draws = stream;
    body(draws);
    stream = draws;
  }
}

}  // namespace gdsmc::host
