#include "engine/bulk_rng.hpp"

#include <algorithm>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "engine/streams.hpp"

namespace gdsmc::host {

namespace {

constexpr std::uint32_t kM0 = 0xD2511F53u, kM1 = 0xCD9E8D57u;
constexpr std::uint32_t kW0 = 0x9E3779B9u, kW1 = 0xBB67AE85u;

void sixteen_scalar(PhiloxKey key, std::uint32_t first, std::uint32_t c1, std::uint32_t c2, std::uint32_t c3,
                    std::uint32_t* out) {
  for (std::uint32_t l = 0; l < 16; ++l) {
    const PhiloxCounter w = philox4x32_10({first + l, c1, c2, c3}, key);
    for (int k = 0; k < 4; ++k) out[4 * l + k] = w[k];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// The lane code is one template, inlined whole (flatten) into a function compiled for AVX-512 and
// one for AVX2. GCC 12 warns that vector arguments of the template's helpers would change the ABI
// (none is ever called: all are inlined) and that _mm512_set1_epi64 reads an uninitialized
// variable (its own _mm512_undefined, GCC bug 105593).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#pragma GCC diagnostic ignored "-Wuninitialized"
// The sixteen blocks' words as four rows (a, b, c, d of block l at [l]) into out's block order.
void interleave(const std::uint32_t (&a)[16], const std::uint32_t (&b)[16], const std::uint32_t (&c)[16],
                const std::uint32_t (&d)[16], std::uint32_t* out) {
  for (int l = 0; l < 16; ++l) out[4 * l] = a[l], out[4 * l + 1] = b[l], out[4 * l + 2] = c[l], out[4 * l + 3] = d[l];
}

// Vectors of 32-bit words held in 64-bit lanes (zero above): one lane per counter, so that a round's
// two 32 x 32 -> 64-bit products are one vpmuludq each (the instruction multiplies the low halves).
// The arithmetic of philox4x32_10 lane by lane: integer operations only, the same words.
template <class V, int kLanes, class Ops>
void sixteen_lanes(PhiloxKey key, std::uint32_t first, std::uint32_t c1, std::uint32_t c2, std::uint32_t c3,
                   std::uint32_t* out) {
  constexpr int kSets = 16 / kLanes;
  V a[kSets], b[kSets], c[kSets], d[kSets];
  alignas(64) std::uint64_t lane[16];
  for (int l = 0; l < 16; ++l) lane[l] = static_cast<std::uint32_t>(first + static_cast<std::uint32_t>(l));
  for (int s = 0; s < kSets; ++s) {
    a[s] = Ops::load(lane + s * kLanes);
    b[s] = Ops::set(c1);
    c[s] = Ops::set(c2);
    d[s] = Ops::set(c3);
  }
  const V m0 = Ops::set(kM0), m1 = Ops::set(kM1), low = Ops::set(0xFFFFFFFFu);
  std::uint32_t k0 = key[0], k1 = key[1];
  for (int round = 0; round < 10; ++round) {
    const V key0 = Ops::set(k0), key1 = Ops::set(k1);
    for (int s = 0; s < kSets; ++s) {
      const V p0 = Ops::mul(a[s], m0), p1 = Ops::mul(c[s], m1);
      a[s] = Ops::xor3(Ops::high(p1), b[s], key0);
      c[s] = Ops::xor3(Ops::high(p0), d[s], key1);
      b[s] = Ops::and_(p1, low);
      d[s] = Ops::and_(p0, low);
    }
    k0 += kW0;
    k1 += kW1;
  }
  std::uint32_t ra[16], rb[16], rc[16], rd[16];
  alignas(64) std::uint64_t tmp[kLanes];
  const auto rows = [&](const V* v, std::uint32_t (&row)[16]) {
    for (int s = 0; s < kSets; ++s) {
      Ops::store(tmp, v[s]);
      for (int l = 0; l < kLanes; ++l) row[s * kLanes + l] = static_cast<std::uint32_t>(tmp[l]);
    }
  };
  rows(a, ra), rows(b, rb), rows(c, rc), rows(d, rd);
  interleave(ra, rb, rc, rd, out);
}

struct Avx512 {
  __attribute__((target("avx512f"))) static __m512i set(std::uint32_t x) { return _mm512_set1_epi64(x); }
  __attribute__((target("avx512f"))) static __m512i load(const std::uint64_t* p) { return _mm512_load_si512(p); }
  __attribute__((target("avx512f"))) static void store(std::uint64_t* p, __m512i v) { _mm512_store_si512(p, v); }
  __attribute__((target("avx512f"))) static __m512i mul(__m512i x, __m512i y) { return _mm512_mul_epu32(x, y); }
  __attribute__((target("avx512f"))) static __m512i high(__m512i x) { return _mm512_srli_epi64(x, 32); }
  __attribute__((target("avx512f"))) static __m512i and_(__m512i x, __m512i y) { return _mm512_and_si512(x, y); }
  __attribute__((target("avx512f"))) static __m512i xor3(__m512i x, __m512i y, __m512i z) {
    return _mm512_xor_si512(_mm512_xor_si512(x, y), z);
  }
};
struct Avx2 {
  __attribute__((target("avx2"))) static __m256i set(std::uint32_t x) {
    return _mm256_set1_epi64x(static_cast<long long>(x));
  }
  __attribute__((target("avx2"))) static __m256i load(const std::uint64_t* p) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
  }
  __attribute__((target("avx2"))) static void store(std::uint64_t* p, __m256i v) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(p), v);
  }
  __attribute__((target("avx2"))) static __m256i mul(__m256i x, __m256i y) { return _mm256_mul_epu32(x, y); }
  __attribute__((target("avx2"))) static __m256i high(__m256i x) { return _mm256_srli_epi64(x, 32); }
  __attribute__((target("avx2"))) static __m256i and_(__m256i x, __m256i y) { return _mm256_and_si256(x, y); }
  __attribute__((target("avx2"))) static __m256i xor3(__m256i x, __m256i y, __m256i z) {
    return _mm256_xor_si256(_mm256_xor_si256(x, y), z);
  }
};

__attribute__((target("avx512f"), flatten)) void sixteen_avx512(PhiloxKey key, std::uint32_t first, std::uint32_t c1,
                                                     std::uint32_t c2, std::uint32_t c3, std::uint32_t* out) {
  sixteen_lanes<__m512i, 8, Avx512>(key, first, c1, c2, c3, out);
}
__attribute__((target("avx2"), flatten)) void sixteen_avx2(PhiloxKey key, std::uint32_t first, std::uint32_t c1,
                                                 std::uint32_t c2, std::uint32_t c3, std::uint32_t* out) {
  sixteen_lanes<__m256i, 4, Avx2>(key, first, c1, c2, c3, out);
}
#pragma GCC diagnostic pop
#endif

}  // namespace

std::vector<PhiloxSixteen> philox_sixteen_versions() {
  std::vector<PhiloxSixteen> versions{sixteen_scalar};
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) versions.push_back(sixteen_avx2);
  if (__builtin_cpu_supports("avx512f")) versions.push_back(sixteen_avx512);
#endif
  return versions;
}

bool philox_sixteen_vectorized() {
  static const bool vectorized = philox_sixteen_versions().size() > 1;
  return vectorized;
}

// The version for this processor, chosen once: AVX-512 (two sets of eight lanes), AVX2 (four of
// four), or one block after the other.
void philox_sixteen_blocks(PhiloxKey key, std::uint32_t first, std::uint32_t c1, std::uint32_t c2, std::uint32_t c3,
                           std::uint32_t* out) {
  static const PhiloxSixteen version = philox_sixteen_versions().back();
  version(key, first, c1, c2, c3, out);
}

// The buffer starts at the stream's current block (recomputed: the stream's block is the Philox
// block of the counter before its next one) at the number it would draw next.
BulkRng::BulkRng(const Rng& rng) : origin_(rng) {
  const StreamFactory::Position p = StreamFactory::position(rng);
  base_ = p.used < 4 ? p.counter[0] - 1 : p.counter[0];
  pos_ = p.used < 4 ? p.used : 0;
  philox_sixteen_blocks(p.key, base_, p.counter[1], p.counter[2], p.counter[3], buffer_);
}

void BulkRng::refill() {
  const StreamFactory::Position p = StreamFactory::position(origin_);
  base_ += kBlocks;
  philox_sixteen_blocks(p.key, base_, p.counter[1], p.counter[2], p.counter[3], buffer_);
  pos_ = 0;
}

// Rng::refill computes the block of its counter and then steps the counter: a stream inside block
// b has block b in hand and the counter b + 1; one at a block's start has the counter b and draws
// the block when it next needs a number.
Rng BulkRng::rng() const {
  const StreamFactory::Position p = StreamFactory::position(origin_);
  Rng r = origin_;
  const unsigned block = pos_ / 4, used = pos_ % 4;
  PhiloxCounter counter = p.counter, words = p.block;
  if (used == 0) {
    counter[0] = base_ + block;
    if (block > 0) std::copy(buffer_ + 4 * (block - 1), buffer_ + 4 * block, words.begin());
    StreamFactory::set_position(r, counter, words, 4);
  } else {
    counter[0] = base_ + block + 1;
    std::copy(buffer_ + 4 * block, buffer_ + 4 * block + 4, words.begin());
    StreamFactory::set_position(r, counter, words, used);
  }
  return r;
}

}  // namespace gdsmc::host
