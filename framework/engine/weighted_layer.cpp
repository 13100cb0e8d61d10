#include "engine/weighted_layer.hpp"

#include <array>

namespace gdsmc::host {

// The two vectorized passes of build(). Compiled for AVX-512, AVX2 and the x86-64 baseline, chosen
// when the program loads (as the flight's pass, with the same flags on this file: no fused
// multiply-add, and sums in eight fixed lanes, so every version gives the bits of the baseline one).

// The peculiar speeds about u of the n members into c; returns their sum, lane k summing the
// members a = k mod 8 in order, the lanes then added in order.
__attribute__((target_clones("avx512f", "avx2", "default"))) double peculiar_speeds(
    const double* __restrict vx, const double* __restrict vy, const double* __restrict vz,
    const std::uint32_t* __restrict members, std::uint32_t n, double ux, double uy, double uz, double* __restrict c) {
  for (std::uint32_t a = 0; a < n; ++a) {
    const std::uint32_t i = members[a];
    const double dx = vx[i] - ux, dy = vy[i] - uy, dz = vz[i] - uz;
    c[a] = std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  double lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const std::uint32_t whole = n & ~7u;
  for (std::uint32_t a = 0; a < whole; a += 8)
    for (int k = 0; k < 8; ++k) lane[k] += c[a + k];
  for (std::uint32_t a = whole; a < n; ++a) lane[a - whole] += c[a];
  double sum = 0;
  for (const double x : lane) sum += x;
  return sum;
}

// How many of the n speeds are not below `bulk` (NaN included).
__attribute__((target_clones("avx512f", "avx2", "default"))) std::uint64_t count_fast(const double* __restrict c,
                                                                                     std::uint32_t n, double bulk) {
  std::uint64_t fast = 0;
  for (std::uint32_t a = 0; a < n; ++a) fast += !(c[a] < bulk);
  return fast;
}

namespace {
// 2^(k+1), k < WeightedLayer::kClasses: the class bounds in units of B_0.
constexpr auto kClassScale = [] {
  std::array<double, WeightedLayer::kClasses> p{};
  double x = 1;
  for (auto& v : p) v = x *= 2;
  return p;
}();
}  // namespace

bool WeightedLayer::build(const ParticleSpan& p, const std::uint32_t* members, std::uint32_t count,
                          const double (&u)[3], double bulk_over_mean) {
  std::copy(u, u + 3, u_);
  count_ = count;
  speed_.resize(count);
  listed_.resize(count);
  pos_.resize(count);
  for (auto& l : list_) l.clear();
  double* const c = speed_.data();
  const double sum = peculiar_speeds(p.vx.data, p.vy.data, p.vz.data, members, count, u_[0], u_[1], u_[2], c);
  // No relative motion (no pair can collide), or a broken velocity (the engine's checks name it).
  if (!(sum > 0) || !std::isfinite(sum)) return false;
  low_ = bulk_over_mean * sum / count;
  inverse_low_ = 1.0 / low_;
  std::uint8_t* const flags = listed_.data();
  std::fill(flags, flags + count, std::uint8_t{0});
  // The few at or above B_0, chunk by chunk: counted (vectorized), then found and listed.
  constexpr std::uint32_t kChunk = 64;
  for (std::uint32_t a0 = 0; a0 < count; a0 += kChunk) {
    const std::uint32_t n = std::min(kChunk, count - a0);
    for (std::uint64_t fast = count_fast(c + a0, n, low_), a = a0; fast > 0; ++a) {
      if (c[a] < low_) continue;
      --fast;
      const int k = class_of(c[a]);
      pos_[a] = static_cast<std::uint32_t>(list_[k].size());
      list_[k].push_back(static_cast<std::uint32_t>(a));
      flags[a] = static_cast<std::uint8_t>(k + 1);
    }
  }
  for (int k = 0; k < kClasses; ++k) bound_[k] = low_ * kClassScale[k];  // exact: powers of 2
  for (int k = 0; k < kClasses; ++k) inverse_[k] = inverse_low_ / kClassScale[k];
  // The last class is open above: its bound is twice its largest speed.
  for (const std::uint32_t a : list_[kClasses - 1])
    if (2.0 * c[a] > bound_[kClasses - 1]) bound_[kClasses - 1] = 2.0 * c[a], inverse_[kClasses - 1] = 0.5 / c[a];
  sum_envelope();
  return std::isfinite(envelope_);
}

}  // namespace gdsmc::host
