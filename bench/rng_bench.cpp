// The random-number primitives: Philox4x32-10 blocks and the gdsmc::Rng draws the loops use.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "bench_support.hpp"
#include "engine/bulk_rng.hpp"
#include "engine/streams.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

// ---------------------------------------------------------------------------------------------
// The random-number primitives (per call; items/s = calls per second).

void BM_Philox4x32_10(benchmark::State& state) {
  PhiloxCounter c{1, 2, 3, 4};
  const PhiloxKey k = stream_key(kSeed, 0);
  for (auto _ : state) {
    c = philox4x32_10(c, k);
    benchmark::DoNotOptimize(c);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Philox4x32_10);

// Sixteen blocks of consecutive counters side by side (host::BulkRng's refill): items/s = blocks.
void BM_PhiloxSixteenBlocks(benchmark::State& state) {
  const PhiloxKey k = stream_key(kSeed, 0);
  alignas(64) std::uint32_t out[64];
  std::uint32_t first = 1;
  for (auto _ : state) {
    host::philox_sixteen_blocks(k, first, 2, 3, 4, out);
    benchmark::DoNotOptimize(out);
    first += 16;
  }
  state.SetItemsProcessed(16 * state.iterations());
}
BENCHMARK(BM_PhiloxSixteenBlocks);

template <class F>
void rng_bench(benchmark::State& state, F&& draw) {
  Rng rng = host::StreamFactory::standalone(kSeed, 0);
  for (auto _ : state) {
    for (int r = 0; r < 64; ++r) benchmark::DoNotOptimize(draw(rng));
  }
  state.SetItemsProcessed(64 * state.iterations());
}
void BM_RngNextU32(benchmark::State& s) { rng_bench(s, [](Rng& r) { return r.next_u32(); }); }
void BM_RngUniform(benchmark::State& s) { rng_bench(s, [](Rng& r) { return r.uniform(); }); }
void BM_RngBelow(benchmark::State& s) { rng_bench(s, [](Rng& r) { return r.below(999983u); }); }
void BM_RngUnitVector(benchmark::State& s) { rng_bench(s, [](Rng& r) { return r.unit_vector().z; }); }
BENCHMARK(BM_RngNextU32);
BENCHMARK(BM_RngUniform);
BENCHMARK(BM_RngBelow);
BENCHMARK(BM_RngUnitVector);

}  // namespace
