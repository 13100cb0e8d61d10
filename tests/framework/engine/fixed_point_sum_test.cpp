// FixedPointSum (framework/engine/fixed_point_sum.hpp): the same bits for any order and grouping
// of the terms, within the documented resolution of the exact sum, NaN for a term out of range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "engine/fixed_point_sum.hpp"

namespace {

using gdsmc::host::FixedPointSum;
using gdsmc::host::FixedPointUnit;

// 10^5 terms of both signs, magnitudes log-uniform over 10^-12 .. 10^6 times the scale.
std::vector<double> mixed_terms(double scale, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> exponent(-12.0, 6.0), coin(0.0, 1.0);
  std::vector<double> x(100000);
  for (double& v : x) v = (coin(engine) < 0.5 ? -1.0 : 1.0) * scale * std::pow(10.0, exponent(engine));
  return x;
}

FixedPointSum sum_of(const std::vector<double>& x, const FixedPointUnit& u) {
  FixedPointSum s;
  for (const double v : x) s.add(v, u);
  return s;
}

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// The sum of doubles to within an ulp or two of the result (Shewchuk's non-overlapping partials,
// as Python's math.fsum, the partials then added from the largest).
double reference_sum(const std::vector<double>& xs) {
  std::vector<double> partials;
  for (double x : xs) {
    std::size_t i = 0;
    for (double y : partials) {
      if (std::fabs(x) < std::fabs(y)) std::swap(x, y);
      const double hi = x + y, lo = y - (hi - x);
      if (lo != 0) partials[i++] = lo;
      x = hi;
    }
    partials.resize(i);
    partials.push_back(x);
  }
  double s = 0;
  for (auto it = partials.rbegin(); it != partials.rend(); ++it) s += *it;
  return s;
}

TEST(FixedPointSum, TheSameBitsInAnyOrderAndAnySplitIntoParts) {
  const double scale = 1.7;  // T0 not a power of two: u = 2^(0 - 64)
  const FixedPointUnit u = FixedPointUnit::of(scale);
  EXPECT_EQ(u.unit, 0x1p-64);
  std::vector<double> x = mixed_terms(scale, 3);
  const FixedPointSum in_order = sum_of(x, u);
  std::mt19937_64 engine(5);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(x.begin(), x.end(), engine);
    EXPECT_EQ(sum_of(x, u), in_order) << trial;
    // Parts of random sizes (some empty), each summed on its own, merged in a random order, a
    // part sent as words (as a rank would) and rebuilt.
    std::vector<std::size_t> cuts{0, x.size()};
    for (int c = 0; c < 9; ++c) cuts.push_back(std::uniform_int_distribution<std::size_t>(0, x.size())(engine));
    std::sort(cuts.begin(), cuts.end());
    std::vector<FixedPointSum> parts;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      FixedPointSum part;
      for (std::size_t i = cuts[k]; i < cuts[k + 1]; ++i) part.add(x[i], u);
      parts.push_back(FixedPointSum::from_words(part.words()));
    }
    std::shuffle(parts.begin(), parts.end(), engine);
    FixedPointSum merged;
    for (const FixedPointSum& p : parts) merged += p;
    EXPECT_EQ(merged, in_order) << trial;
    EXPECT_EQ(bits(merged.value(u)), bits(in_order.value(u))) << trial;
  }
  // Each term loses at most u/2 (rounding), the conversion back half an ulp of the result, the
  // reference an ulp or two: 10^5 u/2 = 2.7e-15 beside a sum of order 10^7.
  const double value = in_order.value(u), reference = reference_sum(x);
  const double ulp = std::nextafter(std::fabs(reference), INFINITY) - std::fabs(reference);
  EXPECT_LE(std::fabs(value - reference), 0.5 * static_cast<double>(x.size()) * u.unit + 2.5 * ulp)
      << value << " against " << reference;
  // The double fold in two of those orders does not agree to the bit: what the fixed point is for.
  double forward = 0, backward = 0;
  for (const double v : x) forward += v;
  for (auto it = x.rbegin(); it != x.rend(); ++it) backward += *it;
  EXPECT_NE(bits(forward), bits(backward));
}

TEST(FixedPointSum, TermsAreRoundedToTheUnitAndTheIntegerRoundedOnceToNearest) {
  const FixedPointUnit u = FixedPointUnit::of(1.0);
  FixedPointSum s;
  s.add(0x1p-66, u);      // a quarter of the unit: 0
  s.add(-0x1.8p-64, u);   // -1.5 units: to the even -2
  s.add(0x1.4p-63, u);    // 2.5 units: to the even 2
  s.add(-0x1.fp-65, u);   // -0.97 units: -1
  s.add(0x1.cp-63, u);    // 3.5 units: 4
  EXPECT_EQ(s.value(u), 0x1.8p-63);
  EXPECT_EQ(FixedPointSum::from_words(s.words()).words(), (FixedPointSum::Words{3, 0, 0}));
  // A term with bits on both sides of the split (2^48 units), its high part rounded up and its low
  // part negative: 2^20 - 2^-32 is 2^84 - 2^32 units, every bit kept.
  FixedPointSum wide;
  wide.add(0x1p20 - 0x1p-32, u);
  EXPECT_EQ(wide.value(u), 0x1p20 - 0x1p-32);
  EXPECT_EQ(wide.words(), (FixedPointSum::Words{0xFFFFFFFF00000000ull, (1ull << 20) - 1, 0}));
  // 2^64 + 2^11 + 1 units: above the half-way point to the next double (2^64 + 2^12), so up.
  FixedPointSum big = FixedPointSum::from_words({(1ull << 11) + 1, 1, 0});
  EXPECT_EQ(big.value(u), 1.0 + 0x1p-52);
  // The range: 2^126 units either side is 2^62 (4.6e18) in the scale's units.
  EXPECT_EQ(FixedPointSum::from_words({0, 1ull << 62, 0}).value(u), 0x1p62);
  EXPECT_EQ(FixedPointSum::from_words({0, 0xC000000000000000ull, 0}).value(u), -0x1p62);
  // Many negative terms: two's complement across both words.
  FixedPointSum negative;
  for (int k = 0; k < 1000; ++k) negative.add(-1.25e6, u);
  EXPECT_EQ(negative.value(u), -1.25e9);
}

TEST(FixedPointSum, ANonFiniteOrOutOfRangeTermMakesTheSumNaNInAnyOrder) {
  const FixedPointUnit u = FixedPointUnit::of(1.0);  // terms below 2^34 in magnitude
  const double inside = std::nextafter(0x1p34, 0.0);
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 0x1p34, -0x1p34, 1e300}) {
    FixedPointSum ok, broken;
    ok.add(inside, u);
    ok.add(-inside, u);
    ok.add(1.0, u);
    EXPECT_EQ(ok.value(u), 1.0);
    broken.add(bad, u);
    EXPECT_TRUE(std::isnan(broken.value(u))) << bad;
    FixedPointSum a = ok, b = broken;
    a += broken;
    b += ok;
    EXPECT_TRUE(std::isnan(a.value(u)) && std::isnan(b.value(u))) << bad;
    EXPECT_EQ(a, b);
    EXPECT_TRUE(std::isnan(FixedPointSum::from_words(a.words()).value(u)));
  }
}

TEST(FixedPointSum, TheUnitFollowsTheScale) {
  EXPECT_EQ(FixedPointUnit::of(1.0).unit, 0x1p-64);
  EXPECT_EQ(FixedPointUnit::of(1024.0).unit, 0x1p-54);
  EXPECT_EQ(FixedPointUnit::of(1023.0).unit, 0x1p-55);
  EXPECT_EQ(FixedPointUnit::of(3e-3).unit * FixedPointUnit::of(3e-3).per_unit, 1.0);
  EXPECT_EQ(FixedPointUnit::of(0.0), FixedPointUnit::of(1.0));  // no scale: that of 1
  // A sum at scale 10^-3: terms of 10^3 scale are exact to 2^-64 of the scale.
  const FixedPointUnit u = FixedPointUnit::of(1e-3);
  FixedPointSum s;
  s.add(1.0, u);
  s.add(-0.25, u);
  EXPECT_EQ(s.value(u), 0.75);
}

}  // namespace
