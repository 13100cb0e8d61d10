// Engine::step of the HCS pipeline, and the engine's collision stage alone on the same system
// (gdsmc_bench.cpp describes each).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include <gdsmc/collision.hpp>
#include <gdsmc/physics/moments.hpp>

#include "bench_support.hpp"
#include "config/pipeline.hpp"
#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/engine.hpp"
#include "engine/streams.hpp"
#include "engine/work_pool.hpp"
#include "plugins/loader.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

// ---------------------------------------------------------------------------------------------
// Engine::step of the HCS pipeline.

struct EngineRun {
  host::Pipeline pipeline;
  unsigned threads = 1;
  std::unique_ptr<host::Engine> engine;
  // The cache's second key is the thread count here.
  EngineRun(std::uint32_t n, std::int64_t threads_arg) : threads(static_cast<unsigned>(threads_arg)) {
    // dt = c tau0 sqrt(T0/T); a particle collides 2/sqrt(pi) times per tau0 in a Maxwellian, so
    // c = 0.02 sqrt(pi) / 2 gives ~N/100 collisions per step.
    const double c = 2.0 * kCollisionFractionPerCall * std::sqrt(M_PI) / 2.0;
    pipeline = host::load_pipeline(pipeline_file(),
                                   {"run.particles=" + std::to_string(n), "run.time_step.value=" + std::to_string(c)},
                                   {plugin_dir()})
                   .pipeline;
    engine = std::make_unique<host::Engine>(pipeline, 0, threads);
  }
  void restart() { engine = std::make_unique<host::Engine>(pipeline, 0, threads); }
};

// Engine::step of the HCS pipeline (N, threads): collisions in sub-populations of 32768, the
// moment update every 4 steps, the five diagnostics of configs/hcs.yaml sampled every 20 steps.
// Real time (threads).
void BM_EngineStep(benchmark::State& state) {
  EngineRun* run = cached_or_skip<EngineRun>(state, "engine");
  if (!run) return;
  // The HCS cools without bound (T/T0 ~ 1e-23 after a few seconds at N = 1e4); the engine is
  // rebuilt (untimed) when T/T0 < 1e-3, long before velocities could reach subnormal numbers.
  std::uint64_t acc_n = 0, cand_n = 0;
  std::uint64_t c0 = run->engine->context().collisions, k0 = run->engine->context().candidates;
  for (auto _ : state) {
    run->engine->step();
    const host::Engine& e = *run->engine;
    if (e.context().global->temperature < 1e-3 * e.system().initial_temperature) {
      state.PauseTiming();
      acc_n += e.context().collisions - c0;
      cand_n += e.context().candidates - k0;
      run->restart();
      c0 = run->engine->context().collisions;
      k0 = run->engine->context().candidates;
      state.ResumeTiming();
    }
  }
  const host::Engine& engine = *run->engine;
  acc_n += engine.context().collisions - c0;
  cand_n += engine.context().candidates - k0;
  const double acc = static_cast<double>(acc_n), cand = static_cast<double>(cand_n);
  state.counters["collisions/s"] = benchmark::Counter(acc, benchmark::Counter::kIsRate);
  state.counters["candidates/s"] = benchmark::Counter(cand, benchmark::Counter::kIsRate);
  state.counters["accept"] = cand > 0 ? acc / cand : 0.0;
  state.counters["coll/call"] = benchmark::Counter(acc, benchmark::Counter::kAvgIterations);
  state.counters["T/T0"] = engine.context().global->temperature / engine.system().initial_temperature;
}

void engine_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "threads"})->UseRealTime();
  for (std::int64_t threads : {1, 2})
    for (std::int64_t n : {10000, 100000, 1000000, 10000000}) b->Args({n, threads});
}
BENCHMARK(BM_EngineStep)->Apply(engine_args);

// The bare collision stage of the same homogeneous system, as Engine::collide drives it (the
// sub-populations, their majorants, the pool), without streaming, moments or diagnostics: the
// denominator of the engine's overhead. IHS alpha = 0.9, velocities rescaled (untimed) below 0.8 T0.
struct StageRun {
  EngineRun run;
  std::unique_ptr<host::WorkPool> pool;
  host::CellGrid grid;
  host::CollisionStage stage;
  host::StreamFactory streams{kSeed, 0};
  std::shared_ptr<PluginObject> rule_object;
  CollisionRule* rule = nullptr;
  std::uint64_t step = 0;
  StageRun(std::uint32_t n, std::int64_t threads) : run(n, threads) {
    const host::Pipeline& p = run.pipeline;
    rule_object = host::create_object(*p.collision.plugin, p.collision.params);
    rule = static_cast<CollisionRule*>(rule_object.get());
    rule->bind(run.engine->particles());
    pool = std::make_unique<host::WorkPool>(static_cast<unsigned>(threads));
    grid.homogeneous(n, run.engine->system().volume);
    stage.set_subpopulation(run.pipeline.subpopulation);
    stage.set_pool(pool.get());
    stage.set_collisions_only(true);  // as the engine's HCS: only collisions change the velocities
  }
};

void BM_HomogeneousStage(benchmark::State& state) {
  StageRun* s = cached_or_skip<StageRun>(state, "stage");
  if (!s) return;
  host::Engine& e = *s->run.engine;
  const ParticleSpan span = e.particles();
  const SystemInfo& sys = e.system();
  const double dt = 2.0 * kCollisionFractionPerCall * std::sqrt(M_PI) / 2.0 * sys.time_unit0;
  // The temperature from the declared energy changes (m = 1: E = 3/2 N T of the peculiar velocities).
  double temperature = velocity_moments(span).temperature;
  double energy = 1.5 * static_cast<double>(span.count) * temperature;
  std::uint64_t acc = 0, cand = 0;
  for (auto _ : state) {
    s->streams.set_step(s->step++);
    const host::CollisionStage::Totals t = s->stage.run(*s->rule, span, s->grid, nullptr, temperature,
                                                        1.0, sys.sigma, dt * std::sqrt(kT0 / temperature), s->streams);
    acc += t.accepted;
    cand += t.candidates;
    energy += t.energy_change;
    temperature = energy / (1.5 * static_cast<double>(span.count));
    if (temperature < kRescaleBelow * kT0) {  // as Cell::rescale: zero mean, exactly T0
      state.PauseTiming();
      impose_exact_moments(span, kT0);
      s->stage.velocities_changed();
      energy = 1.5 * static_cast<double>(span.count) * kT0;
      temperature = kT0;
      state.ResumeTiming();
    }
  }
  state.counters["collisions/s"] = benchmark::Counter(static_cast<double>(acc), benchmark::Counter::kIsRate);
  state.counters["candidates/s"] = benchmark::Counter(static_cast<double>(cand), benchmark::Counter::kIsRate);
  state.counters["accept"] = cand > 0 ? static_cast<double>(acc) / static_cast<double>(cand) : 0.0;
  state.counters["coll/call"] = benchmark::Counter(static_cast<double>(acc), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_HomogeneousStage)->Apply(engine_args);

}  // namespace
