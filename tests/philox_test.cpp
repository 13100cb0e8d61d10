// Philox4x32-10 (Random123 known-answer vectors) and the Rng built on it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <gdsmc/random.hpp>

namespace {

using gdsmc::PhiloxCounter;
using gdsmc::PhiloxKey;
using gdsmc::Rng;
using gdsmc::StreamPurpose;

// Known-answer vectors of Random123 (kat_vectors, philox4x32 with 10 rounds): exact equality.
TEST(Philox, KnownAnswerZero) {
  const PhiloxCounter out = gdsmc::philox4x32_10({0u, 0u, 0u, 0u}, {0u, 0u});
  EXPECT_EQ(out, (PhiloxCounter{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
}

TEST(Philox, KnownAnswerAllOnes) {
  const PhiloxCounter out =
      gdsmc::philox4x32_10({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}, {0xffffffffu, 0xffffffffu});
  EXPECT_EQ(out, (PhiloxCounter{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
}

TEST(Philox, KnownAnswerPiDigits) {
  const PhiloxCounter out =
      gdsmc::philox4x32_10({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}, {0xa4093822u, 0x299f31d0u});
  EXPECT_EQ(out, (PhiloxCounter{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

Rng make_rng(std::uint32_t unit = 0, std::uint64_t step = 0) {
  return Rng(gdsmc::stream_key(12345, 0), StreamPurpose::user, unit, step);
}

// A stream is a pure function of (key, purpose, unit, step); different units, steps, purposes
// and keys give different streams. (Exact comparisons of 8 x 32 bits: a collision of two
// different streams has probability 2^-256.)
TEST(Rng, StreamsAreReproducibleAndDistinct) {
  auto first8 = [](Rng r) {
    std::vector<std::uint32_t> v;
    for (int k = 0; k < 8; ++k) v.push_back(r.next_u32());
    return v;
  };
  const auto base = first8(make_rng(3, 7));
  EXPECT_EQ(base, first8(make_rng(3, 7)));
  EXPECT_NE(base, first8(make_rng(4, 7)));
  EXPECT_NE(base, first8(make_rng(3, 8)));
  EXPECT_NE(base, first8(make_rng(3, 7 + (std::uint64_t{1} << 32))));
  EXPECT_NE(base, first8(Rng(gdsmc::stream_key(12345, 0), StreamPurpose::collisions, 3, 7)));
  EXPECT_NE(base, first8(Rng(gdsmc::stream_key(12346, 0), StreamPurpose::user, 3, 7)));
  EXPECT_NE(base, first8(Rng(gdsmc::stream_key(12345, 1), StreamPurpose::user, 3, 7)));
  // Copies continue identically (streams are values).
  Rng a = make_rng(1, 1);
  (void)a.next_u32();
  Rng b = a;
  for (int k = 0; k < 10; ++k) EXPECT_EQ(a.next_u64(), b.next_u64());
}

constexpr int kSamples = 1 << 20;

// uniform(): every value in [0, 1) (exact), mean 1/2 within 5 sigma, sigma = sqrt(1/12 / n),
// and uniform_open0() in (0, 1].
TEST(Rng, UniformInUnitInterval) {
  Rng r = make_rng();
  double sum = 0, lo = 1, hi = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  const double n = kSamples;
  EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
  // With 2^20 draws the extremes are within ~1e-5 of the ends (probability of a gap > 2e-5 at
  // either end: exp(-21) each).
  EXPECT_LT(lo, 2e-5);
  EXPECT_GT(hi, 1.0 - 2e-5);
  Rng o = make_rng(9);
  for (int k = 0; k < 100000; ++k) {
    const double u = o.uniform_open0();
    ASSERT_GT(u, 0.0);
    ASSERT_LE(u, 1.0);
  }
}

// below(n): in [0, n) (exact) and uniform: Pearson chi-square over the n bins against the
// 1 - 1e-6 quantile of the chi-square distribution with n - 1 degrees of freedom (so a correct
// generator fails with probability 1e-6; the seed is fixed, so the outcome is deterministic).
TEST(Rng, BelowInRangeAndUniform) {
  struct Case {
    std::uint32_t n;
    double critical;  // chi^2_{n-1} quantile at 1 - 1e-6 (mpmath)
  };
  for (const Case c : {Case{10, 44.8109}, Case{7, 38.2583}, Case{100, 180.7920}, Case{1000, 1226.0462}}) {
    Rng r = make_rng(c.n);
    std::vector<double> counts(c.n, 0.0);
    for (int k = 0; k < kSamples; ++k) {
      const std::uint32_t v = r.below(c.n);
      ASSERT_LT(v, c.n);
      counts[v] += 1;
    }
    const double expected = static_cast<double>(kSamples) / c.n;
    double chi2 = 0;
    for (double o : counts) chi2 += (o - expected) * (o - expected) / expected;
    EXPECT_LT(chi2, c.critical) << "n = " << c.n;
  }
  Rng r = make_rng(77);
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(r.below(1), 0u);
  for (int k = 0; k < 1000; ++k) ASSERT_LT(r.below(0xffffffffu), 0xffffffffu);
}

// normal(): mean 0 and variance 1 within 5 standard errors (Var(x) = 1, Var(x^2) = 2 for a
// standard normal), and kurtosis <x^4> = 3 within 5 standard errors (Var(x^4) = 105 - 9 = 96).
TEST(Rng, NormalMoments) {
  Rng r = make_rng(5);
  double s1 = 0, s2 = 0, s4 = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double x = r.normal();
    ASSERT_TRUE(std::isfinite(x));
    s1 += x;
    s2 += x * x;
    s4 += x * x * x * x;
  }
  const double n = kSamples;
  EXPECT_NEAR(s1 / n, 0.0, 5.0 * std::sqrt(1.0 / n));
  EXPECT_NEAR(s2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(s4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));
}

// unit_vector(): unit length to round-off (a few ulps: |u|^2 is a sum of three rounded
// products, so 1e-15 is ~ 8 ulps), every component's mean within 5 sigma of 0
// (Var(u_i) = 1/3) and <u_i^2> = 1/3 within 5 sigma (Var(u_i^2) = 1/5 - 1/9 = 4/45).
TEST(Rng, UnitVectorIsotropic) {
  Rng r = make_rng(11);
  double m[3] = {0, 0, 0}, q[3] = {0, 0, 0};
  for (int k = 0; k < kSamples; ++k) {
    const gdsmc::Vec3 u = r.unit_vector();
    ASSERT_NEAR(gdsmc::dot(u, u), 1.0, 1e-15);
    const double c[3] = {u.x, u.y, u.z};
    for (int a = 0; a < 3; ++a) {
      m[a] += c[a];
      q[a] += c[a] * c[a];
    }
  }
  const double n = kSamples;
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(m[a] / n, 0.0, 5.0 * std::sqrt(1.0 / 3.0 / n)) << "component " << a;
    EXPECT_NEAR(q[a] / n, 1.0 / 3.0, 5.0 * std::sqrt(4.0 / 45.0 / n)) << "component " << a;
  }
}

}  // namespace
