// gdsmc_bench's slab benchmarks (layers along y, walls, the mover): BM_SlabStreamSort,
// BM_SlabCollideLayers and BM_SlabEngineStep; see gdsmc_bench.cpp for the list of all.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/collision.hpp>

#include "bench_support.hpp"
#include "config/pipeline.hpp"
#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/engine.hpp"
#include "engine/streaming.hpp"
#include "engine/streams.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

// A slab of N particles: 100 layers across a gap of 20 lambda0 (delta y = 0.2 lambda0), diffuse
// walls at T0 on both planes, elastic hard spheres (no cooling, so the state is stationary), a
// Maxwellian at rest. dt = 0.05 tau0: a thermal particle flies a quarter of a layer per step and
// ~0.1 % of the particles hit a wall per step.
std::string slab_yaml(std::uint32_t n) {
  return "run: {seed: 2026, particles: " + std::to_string(n) +
         ", time_step: {value: 0.05, unit: tau0}, stop: {time: 1.0e9}, sample_every: 1000000, record_every: 1000000}\n"
         "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 20}, layers: 100}\n"
         "initial_state: maxwellian\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: 1.0}\n"
         "boundaries: {y: {plugin: diffuse_wall, temperature: 1.0}}\n"
         "diagnostics: []\noutput: {file: unused.h5}\n";
}

struct SlabRun {
  std::filesystem::path file;
  host::Pipeline pipeline;
  std::unique_ptr<host::Engine> engine;
  explicit SlabRun(std::uint32_t n, std::int64_t threads = 1) {
    file = std::filesystem::temp_directory_path() / ("gdsmc_bench_slab_" + std::to_string(n) + ".yaml");
    std::FILE* f = std::fopen(file.c_str(), "w");
    const std::string text = slab_yaml(n);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
    pipeline = host::load_pipeline(file, {}, {plugin_dir()}).pipeline;
    std::filesystem::remove(file);
    engine = std::make_unique<host::Engine>(pipeline, 0, static_cast<unsigned>(threads));
    // Untimed: the initial state lies in storage in no particular layer order until the first
    // reordering (step Engine::kReorderEvery); a long run spends all but those steps after it.
    for (std::uint64_t k = 0; k < 2 * host::Engine::kReorderEvery; ++k) engine->step();
  }
};

// The pieces of a slab step on their own: the mover (free flight, diffuse walls, layer index)
// plus the counting sort, and the collision stage over the 100 layers, driven as Engine drives them.
struct SlabPieces {
  SlabRun run;
  std::shared_ptr<PluginObject> wall, rule_object;
  CollisionRule* rule = nullptr;
  host::CellGrid grid;
  std::unique_ptr<host::Mover> mover;
  host::StreamFactory streams{kSeed, 0};
  host::CollisionStage stage;
  std::uint64_t step = 0, accepted = 0, candidates = 0, hits = 0;
  explicit SlabPieces(std::uint32_t n) : run(n) {
    const host::Pipeline& p = run.pipeline;
    wall = host::create_object(*p.boundaries[0].plugin, p.boundaries[0].params);
    rule_object = host::create_object(*p.collision.plugin, p.collision.params);
    rule = static_cast<CollisionRule*>(rule_object.get());
    const SystemInfo& sys = run.engine->system();
    const auto* b = static_cast<const Boundary*>(wall.get());
    mover = std::make_unique<host::Mover>(sys.box, Vec3{0, 0, 0},
                                          std::array<host::Mover::Side, 2>{host::Mover::Side{b, "y_min"}, host::Mover::Side{b, "y_max"}});
    grid.slab(sys.particles, sys.cells, sys.box[1], sys.cross_section());
    reorder();
    rule->bind(run.engine->particles());
    stage.reset(sys.cells);
  }
  double dt() const { return 0.05 * run.engine->system().time_unit0; }
  // Storage layer by layer, as the engine keeps it (Engine::kReorderEvery), and the layer lists.
  void reorder() {
    run.engine->reorder_by_layer();
    ParticleSpan span = run.engine->particles();
    grid.assign_and_sort(span.y.data, const_cast<std::uint32_t*>(span.cell), span.count);
  }
  void stream_and_sort() {
    ParticleSpan span = run.engine->particles();
    auto* cell = const_cast<std::uint32_t*>(span.cell);
    host::StreamingTally tally;
    streams.set_step(step++);
    mover->stream(span, cell, grid.block_counts(span.count), grid, 0.0, dt(), run.engine->context(), streams, tally);
    grid.sort_counted(cell, span.count);
    hits += tally.sides[0].hits + tally.sides[1].hits;
  }
  // dt_collide: chosen for ~N/100 collisions per call over all layers, as the homogeneous bench.
  // Driven by the engine's own CollisionStage; T_ref = T0 in every layer (elastic, stationary).
  void collide(double dt_collide) {
    streams.set_step(step++);
    const host::CollisionStage::Totals t =
        stage.run(*rule, run.engine->particles(), grid, nullptr, kT0, 1.0, kSigma, dt_collide, streams);
    accepted += t.accepted;
    candidates += t.candidates;
  }
};

template <class Fn>
void slab_bench(benchmark::State& state, Fn&& body) {
  SlabPieces* s;
  try {
    s = &cached<SlabPieces>("slab", state.range(0), 100);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  body(state, *s);
}

// Free flight with diffuse walls plus the counting sort into 100 layers: particle moves per second.
void BM_SlabStreamSort(benchmark::State& state) {
  slab_bench(state, [](benchmark::State& st, SlabPieces& s) {
    const std::uint64_t h0 = s.hits;
    std::uint64_t calls = 0;
    for (auto _ : st) {
      s.stream_and_sort();
      if (++calls % host::Engine::kReorderEvery == 0) s.reorder();  // timed: part of the cost of moving
    }
    const double n = static_cast<double>(s.run.engine->system().particles);
    st.counters["moves/s"] = benchmark::Counter(n * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
    st.counters["hits/call"] = benchmark::Counter(static_cast<double>(s.hits - h0), benchmark::Counter::kAvgIterations);
  });
}
BENCHMARK(BM_SlabStreamSort)->ArgName("N")->Arg(100000)->Arg(1000000);

// The flight alone, with the walls and a body force along x (a Poiseuille channel's, 004 Eq. 4:
// every particle accelerated, g dt = 10^-3 thermal speeds per step), and the layer counts the
// sort needs, in cache (10^4 particles: 0.5 MB) and beyond: particle moves per second. SDK 6.0's
// target is 300 M moves/s in cache. No reordering: the flight's cost does not depend on the order.
void BM_SlabFlight(benchmark::State& state) {
  slab_bench(state, [](benchmark::State& st, SlabPieces& s) {
    const SystemInfo& sys = s.run.engine->system();
    const auto* b = static_cast<const Boundary*>(s.wall.get());
    const double dt = s.dt(), g = 1e-3 * std::sqrt(kT0) / dt;
    const std::array<host::Mover::Side, 2> sides{host::Mover::Side{b, "y_min"}, host::Mover::Side{b, "y_max"}};
    // The force points along +x and -x in alternate steps, so the flow it drives stays below 10^-3
    // thermal speeds however long the benchmark runs.
    const host::Mover forward(sys.box, Vec3{g, 0, 0}, sides), backward(sys.box, Vec3{-g, 0, 0}, sides);
    ParticleSpan span = s.run.engine->particles();
    auto* cell = const_cast<std::uint32_t*>(span.cell);
    std::uint64_t hits = 0;
    for (auto _ : st) {
      host::StreamingTally tally;
      s.streams.set_step(s.step++);
      (s.step % 2 ? forward : backward)
          .stream(span, cell, s.grid.block_counts(span.count), s.grid, 0.0, dt, s.run.engine->context(), s.streams, tally);
      hits += tally.sides[0].hits + tally.sides[1].hits;
    }
    s.reorder();
    const double n = static_cast<double>(span.count);
    st.counters["moves/s"] = benchmark::Counter(n * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
    st.counters["hits/call"] = benchmark::Counter(static_cast<double>(hits), benchmark::Counter::kAvgIterations);
  });
}
BENCHMARK(BM_SlabFlight)->ArgName("N")->Arg(10000)->Arg(100000)->Arg(1000000);

// The same with layers of different widths (system.layers: {mean_free_paths, after} after its
// transient): 100 layers 11 times narrower at the centre than at the walls, as a clustered channel's;
// each particle placed by CellGrid::TableIndex (a lookup and one compare) instead of the uniform
// arithmetic. The ratio to BM_SlabStreamSort is the cost of placing by edges.
void BM_SlabStreamSortEdges(benchmark::State& state) {
  slab_bench(state, [](benchmark::State& st, SlabPieces& s) {
    const std::size_t m = s.grid.count();
    const double ly = s.run.engine->system().box[1];
    std::vector<double> widths(m), edges(m + 1);
    double total = 0;
    for (std::size_t I = 0; I < m; ++I) {
      const double u = static_cast<double>(I) / static_cast<double>(m - 1) - 0.5;
      total += widths[I] = 0.1 + 4.0 * u * u;
    }
    double sum = 0;
    edges[0] = -0.5 * ly;
    for (std::size_t I = 1; I < m; ++I) edges[I] = -0.5 * ly + ly * (sum += widths[I - 1]) / total;
    edges[m] = 0.5 * ly;
    s.grid.set_edges(edges);
    const std::size_t bins = s.grid.table_bins();
    const std::uint64_t h0 = s.hits;
    std::uint64_t calls = 0;
    for (auto _ : st) {
      s.stream_and_sort();
      if (++calls % host::Engine::kReorderEvery == 0) s.reorder();
    }
    s.grid.set_edges({});  // back to the equal layers the other benchmarks share
    s.reorder();
    const double n = static_cast<double>(s.run.engine->system().particles);
    st.counters["moves/s"] = benchmark::Counter(n * static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
    st.counters["hits/call"] = benchmark::Counter(static_cast<double>(s.hits - h0), benchmark::Counter::kAvgIterations);
    st.counters["table_bins"] = static_cast<double>(bins);
  });
}
BENCHMARK(BM_SlabStreamSortEdges)->ArgName("N")->Arg(100000)->Arg(1000000);

// The collision stage of the slab, layer by layer (per-layer majorant, remainder and stream), with
// ~N/100 collisions per call as BM_PluginCollideCell/N/100 (the same rule, elastic) in one cell.
void BM_SlabCollideLayers(benchmark::State& state) {
  slab_bench(state, [](benchmark::State& st, SlabPieces& s) {
    const SystemInfo& sys = s.run.engine->system();
    // N_I^2 pi w dt / (2 V_I) candidates per layer with acceptance <|g|>/w: ~N/100 collisions for
    // dt = 0.01 * 2 V_I / (N_I <|g|> pi) with N_I = N/M, <|g|> = 4 sqrt(T/pi) (000 Eq. 2.15).
    const double n_layer = static_cast<double>(sys.particles) / static_cast<double>(sys.cells);
    const double mean_g = 4.0 * std::sqrt(kT0 / M_PI);
    const double dt = 2.0 * kCollisionFractionPerCall * s.grid.cell_volume() / (n_layer * mean_g * M_PI * kSigma * kSigma);
    s.reorder();  // untimed: the collision stage sees storage as the engine keeps it
    const std::uint64_t a0 = s.accepted, c0 = s.candidates;
    for (auto _ : st) s.collide(dt);
    const double acc = static_cast<double>(s.accepted - a0), cand = static_cast<double>(s.candidates - c0);
    st.counters["collisions/s"] = benchmark::Counter(acc, benchmark::Counter::kIsRate);
    st.counters["candidates/s"] = benchmark::Counter(cand, benchmark::Counter::kIsRate);
    st.counters["coll/call"] = benchmark::Counter(acc, benchmark::Counter::kAvgIterations);
  });
}
BENCHMARK(BM_SlabCollideLayers)->ArgName("N")->Arg(100000)->Arg(1000000);

// Engine::step of the slab pipeline: forcings (none), flight and walls, sort, collisions, moments.
// (N, threads), real time.
void BM_SlabEngineStep(benchmark::State& state) {
  SlabRun* run = cached_or_skip<SlabRun>(state, "slab_engine");
  if (!run) return;
  const std::uint64_t c0 = run->engine->context().collisions;
  using Stage = host::Stage;
  const host::StageSeconds before = run->engine->stage_seconds();
  for (auto _ : state) run->engine->step();
  // Where a step's time goes (Engine::stage_seconds), in ms per step: what limits the figure.
  for (Stage s : {Stage::flight, Stage::sort, Stage::reorder, Stage::collisions, Stage::moments})
    state.counters[std::string(host::stage_name(s)) + "_ms"] =
        1e3 * (run->engine->stage_seconds(s) - before[static_cast<std::size_t>(s)]) / static_cast<double>(state.iterations());
  const double n = static_cast<double>(run->engine->system().particles);
  state.counters["moves/s"] = benchmark::Counter(n * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["collisions/s"] =
      benchmark::Counter(static_cast<double>(run->engine->context().collisions - c0), benchmark::Counter::kIsRate);
}
void slab_engine_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"N", "threads"})->UseRealTime();
  for (std::int64_t threads : {1, 2})
    for (std::int64_t n : {10000, 100000, 1000000, 10000000}) b->Args({n, threads});
}
BENCHMARK(BM_SlabEngineStep)->Apply(slab_engine_args);

}  // namespace
