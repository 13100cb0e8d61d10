// The collision stage of one homogeneous cell of inelastic hard spheres by three paths: the IHS
// plugin through the host's scheme, the SDK's kernel compiled in, and the hand-written loop
// (gdsmc_bench.cpp describes each).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <exception>
#include <memory>

#include "cell.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

struct PluginCell {
  Cell cell;
  std::shared_ptr<PluginObject> object;
  CollisionRule* rule = nullptr;  // object, bound to cell
  explicit PluginCell(std::uint32_t n) : cell(n) {}
};
struct AdapterCell {
  Cell cell;
  std::unique_ptr<CollisionRuleAdapter<BenchIHS>> rule;
  explicit AdapterCell(std::uint32_t n) : cell(n) {}
};

template <class Step>
void run_cell(benchmark::State& state, Cell& cell, Step&& one_stage) {
  const std::uint64_t c0 = cell.candidates, a0 = cell.accepted;
  for (auto _ : state) {
    one_stage();
    if (cell.temperature < kRescaleBelow * kT0) {
      state.PauseTiming();
      cell.rescale();
      state.ResumeTiming();
    }
  }
  const double cand = static_cast<double>(cell.candidates - c0), acc = static_cast<double>(cell.accepted - a0);
  state.counters["collisions/s"] = benchmark::Counter(acc, benchmark::Counter::kIsRate);
  state.counters["candidates/s"] = benchmark::Counter(cand, benchmark::Counter::kIsRate);
  state.counters["accept"] = cand > 0 ? acc / cand : 0.0;
  state.counters["coll/call"] = benchmark::Counter(acc, benchmark::Counter::kAvgIterations);
}

void BM_PluginCollideCell(benchmark::State& state) {
  const double alpha = static_cast<double>(state.range(1)) / 100.0;
  PluginCell* pc;
  try {
    pc = &cached<PluginCell>("plugin", state.range(0), state.range(1));
    if (!pc->object) {
      pc->object = make_ihs(alpha);
      pc->rule = bound_rule(pc->object.get(), pc->cell);
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const CollisionRule* rule = pc->rule;
  run_cell(state, pc->cell, [&] { pc->cell.collide_with(*rule); });
}

void BM_StaticAdapter(benchmark::State& state) {
  const double alpha = static_cast<double>(state.range(1)) / 100.0;
  auto& ac = cached<AdapterCell>("adapter", state.range(0), state.range(1));
  if (!ac.rule) {
    ac.rule = std::make_unique<CollisionRuleAdapter<BenchIHS>>(BenchIHS(alpha));
    ac.rule->bind(ac.cell.span());
  }
  const CollisionRule* rule = ac.rule.get();
  benchmark::DoNotOptimize(rule);  // keep the call virtual, as for the plugin
  run_cell(state, ac.cell, [&] { ac.cell.collide_with(*rule); });
}

void BM_HandLoop(benchmark::State& state) {
  const double alpha = static_cast<double>(state.range(1)) / 100.0;
  Cell& cell = cached<Cell>("hand", state.range(0), state.range(1));
  run_cell(state, cell, [&] { hand_stage<1>(cell, alpha); });
}

void cell_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "alpha_pct"});
  for (std::int64_t alpha_pct : {90, 100})
    for (std::int64_t n : {10000, 100000, 1000000}) b->Args({n, alpha_pct});
}
BENCHMARK(BM_PluginCollideCell)->Apply(cell_args);
BENCHMARK(BM_StaticAdapter)->Apply(cell_args);
// The hand loops also at 10^7 (240 MB of velocities: beyond every cache).
void hand_args(benchmark::internal::Benchmark* b) {
  cell_args(b);
  b->Args({10000000, 90});
}
BENCHMARK(BM_HandLoop)->Apply(hand_args);

// The hand loop on velocities interleaved as 32-byte records (SDK 6.0 item 1: structure of arrays
// against one cache line per particle): same draws, same arithmetic, the bits of BM_HandLoop.
void BM_HandLoopInterleaved(benchmark::State& state) {
  const double alpha = static_cast<double>(state.range(1)) / 100.0;
  Cell& cell = cached<Cell>("hand4", state.range(0), state.range(1));
  if (cell.interleaved.empty()) cell.interleave();
  run_cell(state, cell, [&] { hand_stage<4>(cell, alpha); });
}
BENCHMARK(BM_HandLoopInterleaved)->Apply(hand_args);

}  // namespace
