// A sum of doubles kept exactly as an integer number of units, so that its bits do not depend on
// the order or the grouping of its terms: threads, blocks of particles or MPI ranks may each add
// their share and the shares be added in any order.
//
// Each term x is converted once to the integer nearest to x / u (ties to even; x / u is exact, u a
// power of two) and added into a 128-bit two's-complement integer; parts merge by integer addition
// (associative and commutative); value() converts the integer to the nearest double once and
// multiplies by u (exact). The unit u = 2^(ilogb(scale) - 64) lies in (2^-65, 2^-64] * scale:
//  - resolution: a term loses at most u/2 = 2.7e-20 scale; a sum of n terms at most n u/2, against
//    the ~2^-53 = 1.1e-16 of its own size that a double fold loses per addition;
//  - term range: |x| < 2^98 u, at least 2^33 scale = 8.6e9 scale; a term outside it, or not finite,
//    marks the sum invalid and value() is NaN (the integer part is then not added: no UB);
//  - sum range: |sum| < 2^127 u, at least 2^62 scale = 4.6e18 scale (1e9 terms of 1e6 scale each
//    are 2^114 u). A sum beyond wraps around (unsigned arithmetic: defined, but the value is then
//    wrong); it takes more than 2^29 = 5.4e8 terms at the term limit, 4.6e12 terms of 1e6 scale.
// The conversion's products are by powers of two (exact), so a fused multiply-add changes nothing.
#pragma once
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace gdsmc::host {

// The unit of a FixedPointSum: u and 1/u, both powers of two.
struct FixedPointUnit {
  static constexpr int kBits = 64;  // u = 2^(ilogb(scale) - kBits)
  double unit = 0x1p-64;
  double per_unit = 0x1p64;
  // The unit for terms of order `scale` (> 0 and finite; otherwise that of scale = 1).
  static FixedPointUnit of(double scale) {
    FixedPointUnit u;
    if (scale > 0 && std::isfinite(scale)) {
      const int e = std::ilogb(scale) - kBits;
      u.unit = std::ldexp(1.0, e);
      u.per_unit = std::ldexp(1.0, -e);
    }
    return u;
  }
  bool operator==(const FixedPointUnit&) const = default;
};

class FixedPointSum {
 public:
  static constexpr double kTermLimit = 0x1p98;  // |x / u| below this
  static constexpr int kSplit = 48;             // x / u = high 2^48 + low
  using Words = std::array<std::uint64_t, 3>;   // low and high 64 bits, then 1 if invalid

  // A term as the integer nearest to q = x / u (ties to even), in two parts: high = nearest(q 2^-48),
  // then low = nearest(q - high 2^48), so that high 2^48 + low = nearest(q). Double operations only
  // (a loop of them vectorizes): x / u is exact (u a power of two), adding 1.5 2^52 rounds a value
  // below 2^51 to an integer held in the low bits of the result, and q - high 2^48 is exact (it is
  // q's bits below 2^48, on q's own grid). |high| <= 2^50, |low| <= 2^47. A term out of range (or
  // NaN) gives out_of_range = 1 and parts 0.
  struct Parts {
    std::int64_t high, low, out_of_range;
  };
  static Parts split(double x, const FixedPointUnit& u) {
    constexpr double round = 0x1.8p52;
    double q = x * u.per_unit;
    const bool in_range = std::fabs(q) < kTermLimit;  // false for NaN and infinities
    q = in_range ? q : 0.0;
    const double high = q * 0x1p-48 + round;
    const double low = (q - (high - round) * 0x1p48) + round;
    return {std::bit_cast<std::int64_t>(high) - std::bit_cast<std::int64_t>(round),
            std::bit_cast<std::int64_t>(low) - std::bit_cast<std::int64_t>(round), in_range ? 0 : 1};
  }
  void add(double x, const FixedPointUnit& u) {
    const Parts p = split(x, u);
    add(p.high, p.low, p.out_of_range);
  }
  // Sums of Parts: sum of high, sum of low, sum (or or) of out_of_range. Integer sums, so a loop
  // may add its terms' parts in any order; below 2^12 terms they do not overflow.
  void add(std::int64_t high, std::int64_t low, std::int64_t out_of_range) {
    units_ += (static_cast<Integer>(static_cast<__int128>(high)) << kSplit) + static_cast<Integer>(static_cast<__int128>(low));
    invalid_ |= out_of_range != 0;
  }
  FixedPointSum& operator+=(const FixedPointSum& other) {
    units_ += other.units_;
    invalid_ |= other.invalid_;
    return *this;
  }
  // The sum in the units' scale: the integer rounded to the nearest double, times u; NaN if a
  // term was out of range or not finite.
  double value(const FixedPointUnit& u) const {
    if (invalid_) return std::numeric_limits<double>::quiet_NaN();
    return static_cast<double>(static_cast<__int128>(units_)) * u.unit;
  }
  bool invalid() const { return invalid_; }
  // The exact state, for sending elsewhere (another rank) and adding there with from_words().
  Words words() const {
    return {static_cast<std::uint64_t>(units_), static_cast<std::uint64_t>(units_ >> 64), invalid_ ? 1u : 0u};
  }
  static FixedPointSum from_words(const Words& w) {
    FixedPointSum s;
    s.units_ = (static_cast<Integer>(w[1]) << 64) | w[0];
    s.invalid_ = w[2] != 0;
    return s;
  }
  bool operator==(const FixedPointSum&) const = default;

 private:
  using Integer = unsigned __int128;  // two's complement, wrapping: no signed overflow
  Integer units_ = 0;
  bool invalid_ = false;
};

}  // namespace gdsmc::host
