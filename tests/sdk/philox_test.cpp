// Philox4x32-10 (Random123 known-answer vectors), the Rng built on it and the SDK 2.0 stream
// layout (StreamFactory, Streams).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <gdsmc/random.hpp>

#include "engine/bulk_rng.hpp"
#include "engine/streams.hpp"

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

// A stream outside any run, as tests and benchmarks get it (purpose host, instance 0, step 0).
Rng make_rng(std::uint64_t unit = 0) { return gdsmc::host::StreamFactory::standalone(12345, unit); }

std::vector<std::uint32_t> first8(Rng r) {
  std::vector<std::uint32_t> v;
  for (int k = 0; k < 8; ++k) v.push_back(r.next_u32());
  return v;
}

// The counter layout of SDK 2.0, checked block by block against the Philox function itself:
// key = step_stream_key(stream_key(seed, realization), step), counter = (block, unit low, unit
// high, purpose << 24 | instance). The first three blocks of a stream are blocks 0, 1, 2.
TEST(Rng, CounterLayoutIsTheDocumentedOne) {
  const std::uint64_t seed = 0x0123456789abcdefull, step = 0x500000007ull, unit = 0xfedcba9876543210ull;
  const std::uint32_t realization = 3, instance = 0x00abcdu;
  gdsmc::host::StreamFactory factory(seed, realization);
  factory.set_step(step);
  const PhiloxKey key = gdsmc::step_stream_key(gdsmc::stream_key(seed, realization), step);
  const std::uint32_t c3 = (static_cast<std::uint32_t>(StreamPurpose::boundary) << 24) | instance;
  Rng r = factory.rng(StreamPurpose::boundary, instance, unit);
  for (std::uint32_t block = 0; block < 3; ++block) {
    const PhiloxCounter expected = gdsmc::philox4x32_10({block, 0x76543210u, 0xfedcba98u, c3}, key);
    for (int w = 0; w < 4; ++w) EXPECT_EQ(r.next_u32(), expected[w]) << "block " << block << " word " << w;
  }
  // The standalone streams are realization 0 of the same layout, instance 0.
  const PhiloxKey standalone_key = gdsmc::step_stream_key(gdsmc::stream_key(seed, 0), 9);
  Rng s = gdsmc::host::StreamFactory::standalone(seed, unit, StreamPurpose::diagnostic, 9);
  const PhiloxCounter block0 = gdsmc::philox4x32_10(
      {0u, 0x76543210u, 0xfedcba98u, static_cast<std::uint32_t>(StreamPurpose::diagnostic) << 24}, standalone_key);
  for (int w = 0; w < 4; ++w) EXPECT_EQ(s.next_u32(), block0[w]) << "word " << w;
  // A plugin's Streams: for_particle(id) is (instance, id); for_unit(u) sets the top bit of the
  // 24-bit instance field (0x800000), so a unit never shares a counter with a particle.
  const gdsmc::Streams streams = factory.streams(StreamPurpose::boundary, instance);
  Rng p = streams.for_particle(unit);
  Rng u = streams.for_unit(unit);
  const PhiloxCounter particle0 = gdsmc::philox4x32_10({0u, 0x76543210u, 0xfedcba98u, c3}, key);
  const PhiloxCounter unit0 = gdsmc::philox4x32_10({0u, 0x76543210u, 0xfedcba98u, c3 | 0x800000u}, key);
  for (int w = 0; w < 4; ++w) {
    EXPECT_EQ(p.next_u32(), particle0[w]) << "word " << w;
    EXPECT_EQ(u.next_u32(), unit0[w]) << "word " << w;
  }
}

// A stream is a pure function of (seed, realization, step, purpose, instance, unit); changing any
// one of them gives a different stream, including changes only in the upper 32 bits of the
// 64-bit unit and step. (Exact comparisons of 8 x 32 bits: a collision of two different streams
// has probability 2^-256.)
TEST(Rng, StreamsAreReproducibleAndDistinct) {
  using gdsmc::host::StreamFactory;
  auto stream = [](std::uint64_t seed, std::uint32_t realization, std::uint64_t step, StreamPurpose purpose,
                   std::uint32_t instance, std::uint64_t unit) {
    StreamFactory f(seed, realization);
    f.set_step(step);
    return first8(f.rng(purpose, instance, unit));
  };
  const auto P = StreamPurpose::collisions;
  const auto base = stream(12345, 0, 7, P, 2, 3);
  EXPECT_EQ(base, stream(12345, 0, 7, P, 2, 3));
  EXPECT_NE(base, stream(12345, 0, 7, P, 2, 4));                               // unit
  EXPECT_NE(base, stream(12345, 0, 7, P, 2, 3 + (std::uint64_t{1} << 32)));    // unit, upper half
  EXPECT_NE(base, stream(12345, 0, 7, StreamPurpose::forcing, 2, 3));          // purpose
  EXPECT_NE(base, stream(12345, 0, 7, P, 1, 3));                               // instance
  EXPECT_NE(base, stream(12345, 0, 8, P, 2, 3));                               // step
  EXPECT_NE(base, stream(12345, 0, 7 + (std::uint64_t{1} << 32), P, 2, 3));    // step, upper half
  EXPECT_NE(base, stream(12346, 0, 7, P, 2, 3));                               // seed
  EXPECT_NE(base, stream(12345 + (std::uint64_t{1} << 32), 0, 7, P, 2, 3));    // seed, upper half
  EXPECT_NE(base, stream(12345, 1, 7, P, 2, 3));                               // realization
  // set_step moves to another step and back: the stream depends on the step only.
  StreamFactory f(12345, 0);
  f.set_step(8);
  f.set_step(7);
  EXPECT_EQ(base, first8(f.rng(P, 2, 3)));
  // Standalone streams: the same (seed, unit, purpose, step) gives the same stream; each of them
  // changes it.
  const auto s = first8(StreamFactory::standalone(12345, 3, StreamPurpose::host, 7));
  EXPECT_EQ(s, first8(StreamFactory::standalone(12345, 3, StreamPurpose::host, 7)));
  EXPECT_NE(s, first8(StreamFactory::standalone(12346, 3, StreamPurpose::host, 7)));
  EXPECT_NE(s, first8(StreamFactory::standalone(12345, 4, StreamPurpose::host, 7)));
  EXPECT_NE(s, first8(StreamFactory::standalone(12345, 3, StreamPurpose::diagnostic, 7)));
  EXPECT_NE(s, first8(StreamFactory::standalone(12345, 3, StreamPurpose::host, 8)));
  // Copies continue identically (streams are values).
  Rng a = make_rng(1);
  (void)a.next_u32();
  Rng b = a;
  for (int k = 0; k < 10; ++k) EXPECT_EQ(a.next_u64(), b.next_u64());
}

// Streams (what a plugin gets): for_particle(id) is the stream of (purpose, instance, id), the
// same the host's factory gives; for_unit(u) is a different stream from for_particle(u), so a
// plugin's per-cell streams never repeat its per-particle ones; instances and purposes separate
// plugins; the step and seed reach them.
TEST(Rng, PluginStreamsSeparateParticlesUnitsAndPlugins) {
  using gdsmc::host::StreamFactory;
  StreamFactory f(2024, 1);
  f.set_step(11);
  const gdsmc::Streams s = f.streams(StreamPurpose::forcing, 5);
  EXPECT_EQ(first8(s.for_particle(42)), first8(f.rng(StreamPurpose::forcing, 5, 42)));
  EXPECT_NE(first8(s.for_particle(42)), first8(s.for_unit(42)));
  EXPECT_NE(first8(s.for_particle(0)), first8(s.for_unit(0)));
  EXPECT_EQ(first8(s.for_unit(42)), first8(f.streams(StreamPurpose::forcing, 5).for_unit(42)));
  EXPECT_NE(first8(s.for_particle(42)), first8(s.for_particle(43)));
  EXPECT_NE(first8(s.for_unit(42)), first8(s.for_unit(43)));
  EXPECT_NE(first8(s.for_particle(42)), first8(f.streams(StreamPurpose::forcing, 6).for_particle(42)));
  EXPECT_NE(first8(s.for_unit(42)), first8(f.streams(StreamPurpose::forcing, 6).for_unit(42)));
  EXPECT_NE(first8(s.for_particle(42)), first8(f.streams(StreamPurpose::diagnostic, 5).for_particle(42)));
  // A copy of Streams names the same streams.
  const gdsmc::Streams copy = s;
  EXPECT_EQ(first8(copy.for_particle(7)), first8(s.for_particle(7)));
  // Another step, another seed: other streams.
  StreamFactory g(2024, 1);
  g.set_step(12);
  EXPECT_NE(first8(s.for_particle(42)), first8(g.streams(StreamPurpose::forcing, 5).for_particle(42)));
  const gdsmc::Streams t = StreamFactory::standalone_streams(2024, StreamPurpose::forcing, 5, 11);
  EXPECT_EQ(first8(t.for_particle(42)),
            first8(StreamFactory::standalone_streams(2024, StreamPurpose::forcing, 5, 11).for_particle(42)));
  EXPECT_NE(first8(t.for_particle(42)), first8(s.for_particle(42)));  // realization 0 vs 1
  EXPECT_NE(first8(t.for_particle(42)),
            first8(StreamFactory::standalone_streams(2025, StreamPurpose::forcing, 5, 11).for_particle(42)));
  EXPECT_NE(first8(t.for_particle(42)),
            first8(StreamFactory::standalone_streams(2024, StreamPurpose::forcing, 5, 12).for_particle(42)));
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

// Every version of the sixteen-block Philox this processor runs (baseline, AVX2, AVX-512) gives
// the blocks of philox4x32_10, across the wrap of the counter word.
TEST(Philox, SixteenBlocksSideBySideAreTheBlocksOneAtATime) {
  const auto versions = gdsmc::host::philox_sixteen_versions();
  ASSERT_GE(versions.size(), 1u);
  const PhiloxKey key{0x243F6A88u, 0x85A308D3u};
  for (const std::uint32_t first : {0u, 12345u, 0xFFFFFFF8u}) {
    std::uint32_t out[64];
    for (std::size_t v = 0; v < versions.size(); ++v) {
      versions[v](key, first, 7u, 0xDEADBEEFu, 0x02000001u, out);
      for (std::uint32_t l = 0; l < 16; ++l) {
        const PhiloxCounter w = gdsmc::philox4x32_10({first + l, 7u, 0xDEADBEEFu, 0x02000001u}, key);
        for (int k = 0; k < 4; ++k) ASSERT_EQ(out[4 * l + k], w[k]) << "version " << v << ", block " << l;
      }
    }
  }
}

// The host's BulkRng (sixteen blocks at a time, vectorized) draws the numbers of the Rng it is
// made from, whatever number of that Rng's block was used; the Rng it hands back continues where it
// stopped. Mixed draws (below with rejections near 2^32, uniform, uniform32) at every stopping
// point over four refills, and the all-ones counter word, where the next counter wraps to 0.
TEST(Rng, BulkRngDrawsTheSameNumbersAndHandsBackTheStreamWhereItStopped) {
  const gdsmc::host::StreamFactory factory(7, 3);
  for (const std::uint32_t unit : {0u, 5u}) {
    for (unsigned already = 0; already < 6; ++already) {
      for (unsigned taken = 0; taken < 260; taken += 7) {
        Rng plain = factory.rng(StreamPurpose::collisions, 0, unit);
        if (unit == 5) {  // start four numbers before the counter word wraps
          const auto p = gdsmc::host::StreamFactory::position(plain);
          gdsmc::host::StreamFactory::set_position(plain, {0xFFFFFFFEu, p.counter[1], p.counter[2], p.counter[3]},
                                                   p.block, 4);
        }
        for (unsigned k = 0; k < already; ++k) plain.next_u32();
        gdsmc::host::BulkRng bulk(plain);
        for (unsigned k = 0; k < taken; ++k) {
          switch (k % 4) {
            case 0: ASSERT_EQ(bulk.below(0xFFFFFFF0u), plain.below(0xFFFFFFF0u)) << k; break;
            case 1: ASSERT_EQ(bulk.uniform(), plain.uniform()) << k; break;
            case 2: ASSERT_EQ(bulk.below(37), plain.below(37)) << k; break;
            default: ASSERT_EQ(bulk.uniform32(), plain.uniform32()) << k;
          }
        }
        Rng back = bulk.rng();
        for (unsigned k = 0; k < 9; ++k) ASSERT_EQ(back.next_u32(), plain.next_u32()) << already << " " << taken;
      }
    }
  }
}

}  // namespace

