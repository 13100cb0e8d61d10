// gdsmc_bench's benchmarks of the machine itself: BM_MemoryRead, BM_MemoryWrite, BM_MemoryFlight,
// BM_MemoryPairs and BM_CoreCompute; see gdsmc_bench.cpp for the list of all.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/streaming.hpp"
#include "engine/work_pool.hpp"

namespace {

using namespace gdsmc;

// What this machine's memory gives one and two cores, as the slab step uses it: six arrays of N
// doubles (48 MB at 10^6: 48 bytes per particle, of the slab's 64) in blocks of Mover::kBlock on
// the engine's WorkPool. "read" sums them, "write" fills them, "flight" is x,y,z += v dt (reads
// 48 MB, writes 24 MB): streams, whose 2-thread speed-up is the ceiling for the memory-bound
// stages of a slab step (issue 13; on the 2-core machine here 1.4-1.7x). "pairs" tests N random
// candidate pairs in the three velocity arrays and writes 1 in 4, as collisions do: random
// access, latency-bound. "compute" is N turns of an xorshift and a multiply-add in registers.
// Those two show whether the cores themselves, or their random misses, gain less than 2x from a
// second thread (here they gain 1.9-2.0x). (N, threads), real time; bytes/s (streams) or items/s.
template <int Pattern>
void BM_MemoryStream(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  host::WorkPool pool(static_cast<unsigned>(state.range(1)));
  std::vector<std::vector<double>> a(6, std::vector<double>(n, 1.0));
  std::vector<double> sums((n + host::Mover::kBlock - 1) / host::Mover::kBlock);
  const double dt = 1e-3;
  for (auto _ : state) {
    pool.run(sums.size(), [&](std::size_t k) {
      const std::size_t b = k * host::Mover::kBlock, e = std::min(n, b + host::Mover::kBlock);
      double s = 0;
      std::uint64_t x = 0x9E3779B97F4A7C15ull * (k + 1);  // xorshift64 of the block (patterns 3, 4)
      for (std::size_t i = b; i < e; ++i) {
        if constexpr (Pattern >= 3) {
          x ^= x << 13;
          x ^= x >> 7;
          x ^= x << 17;
        }
        // A candidate pair anywhere in the velocities, 1 in 4 written (two blocks may write one
        // particle at once: the values are never used, only the traffic is measured).
        if constexpr (Pattern == 3) {
          const std::size_t p = ((x & 0xFFFFFFFFu) * n) >> 32, q = ((x >> 32) * n) >> 32;  // in [0, n)
          const double dx = a[3][p] - a[3][q], dy = a[4][p] - a[4][q], dz = a[5][p] - a[5][q];
          s += dx * dx + dy * dy + dz * dz;
          if ((x >> 62) == 0) {
            a[3][p] -= 1e-9 * dx;
            a[3][q] += 1e-9 * dx;
            a[4][p] -= 1e-9 * dy;
            a[4][q] += 1e-9 * dy;
            a[5][p] -= 1e-9 * dz;
            a[5][q] += 1e-9 * dz;
          }
        }
        if constexpr (Pattern == 4) s = s * 0.999999 + static_cast<double>(x >> 40) * 1e-9;  // registers only
        if constexpr (Pattern == 0) s += a[0][i] + a[1][i] + a[2][i] + a[3][i] + a[4][i] + a[5][i];
        if constexpr (Pattern == 1)
          for (int j = 0; j < 6; ++j) a[j][i] = static_cast<double>(i);
        if constexpr (Pattern == 2)
          for (int j = 0; j < 3; ++j) a[j][i] += a[j + 3][i] * dt;
      }
      sums[k] = s;
    });
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  if constexpr (Pattern <= 2) {
    const double bytes = (Pattern == 2 ? 72.0 : 48.0) * static_cast<double>(n);
    state.counters["bytes/s"] = benchmark::Counter(bytes * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  } else {
    state.counters["items/s"] = benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                   benchmark::Counter::kIsRate);
  }
}
void memory_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "threads"})->UseRealTime();
  for (std::int64_t threads : {1, 2})
    for (std::int64_t n : {100000, 1000000, 10000000}) b->Args({n, threads});
}
BENCHMARK_TEMPLATE(BM_MemoryStream, 0)->Name("BM_MemoryRead")->Apply(memory_args);
BENCHMARK_TEMPLATE(BM_MemoryStream, 1)->Name("BM_MemoryWrite")->Apply(memory_args);
BENCHMARK_TEMPLATE(BM_MemoryStream, 2)->Name("BM_MemoryFlight")->Apply(memory_args);
BENCHMARK_TEMPLATE(BM_MemoryStream, 3)->Name("BM_MemoryPairs")->Apply(memory_args);
BENCHMARK_TEMPLATE(BM_MemoryStream, 4)->Name("BM_CoreCompute")->Apply(memory_args);

}  // namespace
