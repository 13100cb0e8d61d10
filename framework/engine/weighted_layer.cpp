#include "engine/weighted_layer.hpp"

#include <array>

namespace gdsmc::host {

// The vectorized passes of the weighted layers. Compiled for AVX-512, AVX2 and the x86-64 baseline,
// chosen when the program loads (as the flight's pass, with the same flags on this file: no fused
// multiply-add, and sums in eight fixed lanes, so every version gives the bits of the baseline one).

// The sum of the n values s, lane k summing s[a] for a = k mod 8 in order, the lanes then added in
// order: the same bits in every version.
__attribute__((target_clones("avx512f", "avx2", "default"))) double lane_sum(const double* __restrict s,
                                                                            std::uint32_t n) {
  double lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const std::uint32_t whole = n & ~7u;
  for (std::uint32_t a = 0; a < whole; a += 8)
    for (int k = 0; k < 8; ++k) lane[k] += s[a + k];
  for (std::uint32_t a = whole; a < n; ++a) lane[a - whole] += s[a];
  double sum = 0;
  for (const double x : lane) sum += x;
  return sum;
}

// The squared peculiar speeds about u of the n members into s; returns their sum (lane_sum).
__attribute__((target_clones("avx512f", "avx2", "default"))) double peculiar_squares(
    const double* __restrict vx, const double* __restrict vy, const double* __restrict vz,
    const std::uint32_t* __restrict members, std::uint32_t n, double ux, double uy, double uz, double* __restrict s) {
  for (std::uint32_t a = 0; a < n; ++a) {
    const std::uint32_t i = members[a];
    const double dx = vx[i] - ux, dy = vy[i] - uy, dz = vz[i] - uz;
    s[a] = dx * dx + dy * dy + dz * dz;
  }
  return lane_sum(s, n);
}

// flag[a] = 1 where s[a] is not below `bulk` (NaN included), 0 elsewhere.
__attribute__((target_clones("avx512f", "avx2", "default"))) void mark_fast(const double* __restrict s,
                                                                           std::uint32_t n, double bulk,
                                                                           std::uint8_t* __restrict flag) {
  for (std::uint32_t a = 0; a < n; ++a) flag[a] = !(s[a] < bulk);
}

// The squared peculiar speeds about u of particles 0 .. n-1 into s, flag[a] = 1 where s[a] is not
// below `bulk` (NaN included): one pass, no gather. Returns their sum (lanes as lane_sum).
__attribute__((target_clones("avx512f", "avx2", "default"))) double peculiar_squares_marked(
    const double* __restrict vx, const double* __restrict vy, const double* __restrict vz, std::uint32_t n, double ux,
    double uy, double uz, double bulk, double* __restrict s, std::uint8_t* __restrict flag) {
  double lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const std::uint32_t whole = n & ~7u;
  for (std::uint32_t a = 0; a < whole; a += 8)
    for (int k = 0; k < 8; ++k) {
      const double dx = vx[a + k] - ux, dy = vy[a + k] - uy, dz = vz[a + k] - uz;
      const double q = dx * dx + dy * dy + dz * dz;
      s[a + k] = q;
      flag[a + k] = !(q < bulk);
      lane[k] += q;
    }
  for (std::uint32_t a = whole; a < n; ++a) {
    const double dx = vx[a] - ux, dy = vy[a] - uy, dz = vz[a] - uz;
    const double q = dx * dx + dy * dy + dz * dz;
    s[a] = q;
    flag[a] = !(q < bulk);
    lane[a - whole] += q;
  }
  double sum = 0;
  for (const double x : lane) sum += x;
  return sum;
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

void WeightedLayer::reset(std::uint32_t count, const double (&u)[3]) {
  std::copy(u, u + 3, u_);
  count_ = count;
  listed_.resize(count);
  pos_.resize(count);
  square_.resize(count);
  for (int k = 0; k < top_; ++k) list_[k].clear();  // classes from top_ up are empty (sum_envelope)
  top_ = 0;
}

void WeightedLayer::set_bulk(double bulk) {
  low_ = bulk;
  inverse_low_ = 1.0 / low_;
  low_square_ = low_ * low_;
  inverse_low_square_ = 1.0 / low_square_;
}

bool WeightedLayer::build(const ParticleSpan& p, const std::uint32_t* members, std::uint32_t count,
                          const double (&u)[3], double bulk_over_rms) {
  reset(count, u);
  double* const s = square_.data();
  const double sum = peculiar_squares(p.vx.data, p.vy.data, p.vz.data, members, count, u[0], u[1], u[2], s);
  // No relative motion (no pair can collide), or a broken velocity (the engine's checks name it).
  if (!(sum > 0) || !std::isfinite(sum)) return false;
  set_bulk(bulk_over_rms * std::sqrt(sum / count));
  // The few at or above B_0: flagged (vectorized), then found eight flags at a time and listed.
  mark_fast(s, count, low_square_, listed_.data());
  return list_fast();
}

bool WeightedLayer::build_contiguous(const ParticleSpan& p, std::uint32_t count, const double (&u)[3], double bulk) {
  reset(count, u);
  if (!(bulk > 0) || !std::isfinite(bulk)) return false;
  set_bulk(bulk);
  const double sum = peculiar_squares_marked(p.vx.data, p.vy.data, p.vz.data, count, u[0], u[1], u[2], low_square_,
                                             square_.data(), listed_.data());
  if (!(sum > 0) || !std::isfinite(sum)) return false;
  return list_fast();
}

bool WeightedLayer::list_fast() {
  const std::uint32_t count = count_;
  const double* const s = square_.data();
  std::uint8_t* const flags = listed_.data();
  const auto enlist = [&](std::uint32_t a) {
    const int k = class_of(s[a]);
    pos_[a] = static_cast<std::uint32_t>(list_[k].size());
    list_[k].push_back(a);
    flags[a] = static_cast<std::uint8_t>(k + 1);
  };
  const std::uint32_t whole = count & ~7u;
  for (std::uint32_t a0 = 0; a0 < whole; a0 += 8) {
    std::uint64_t word;
    std::memcpy(&word, flags + a0, sizeof word);
    while (word) {
      const int byte = __builtin_ctzll(word) >> 3;
      word &= ~(std::uint64_t{0xFF} << (8 * byte));
      enlist(a0 + static_cast<std::uint32_t>(byte));
    }
  }
  for (std::uint32_t a = whole; a < count; ++a)
    if (flags[a]) enlist(a);
  for (int k = 0; k < kClasses; ++k) bound_[k] = low_ * kClassScale[k];  // exact: powers of 2
  // The last class is open above: its bound is twice its largest speed.
  for (const std::uint32_t a : list_[kClasses - 1]) bound_[kClasses - 1] = std::max(bound_[kClasses - 1], 2.0 * std::sqrt(s[a]));
  for (int k = 0; k < kClasses; ++k) inverse_[k] = 1.0 / bound_[k];
  sum_envelope();
  return std::isfinite(envelope_);
}

}  // namespace gdsmc::host
