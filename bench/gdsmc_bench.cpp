// gdsmc_bench: cost of the DSMC collision stage of inelastic hard spheres in one homogeneous cell,
// of the slab's streaming and layer collisions, and of Engine::step.
// (Over 600 lines on purpose: the hand-written reference loop, the plugin path and the engine
// paths stay in one file so the start-up bit-identity check compares exactly what is timed. The
// slab benchmarks are in slab_bench.cpp, the machine's own in memory_bench.cpp, what they share
// in bench_support.hpp.)
//
//   BM_PluginCollideCell  the IHS plugin (.so loaded at run time with gdsmc::host::load_plugin +
//                         create_object, bound once to the particles with CollisionRule::bind),
//                         driven by the host's scheme (host::CollisionStage, one cell): the host
//                         draws the candidates and hands them to the plugin's pair kernel in
//                         batches, one virtual collide_batch(PairBatch&) call per batch.
//   BM_StaticAdapter      the same, with the SDK's kernel (CollisionRuleAdapter) instantiated
//                         inside this executable with a copy of the IHS rule: separates "the
//                         kernel" from "loaded through a .so".
//   BM_HandLoop           one plain function of the same physics and the same algorithm (same
//                         candidate count, pairs drawn in prefetched batches of 32 and taken in
//                         order, acceptance |g|/w, impact direction normalize(g_hat + u), Eq. 2.8
//                         update) and the same generators (gdsmc::Rng, Philox4x32-10, from the
//                         host's StreamFactory: the cell's selection stream and its kernel
//                         stream) drawn in the same order. Started from the same state with the
//                         same streams it produces bit-identical velocities (checked at start-up;
//                         see verify_same_trajectory): where the host ends its batches changes
//                         nothing.
//   BM_EngineStep         Engine::step() of the HCS pipeline configs/hcs.yaml (collisions in
//                         sub-populations, moment updates every 4 steps, five diagnostics), dt
//                         set for ~N/100 collisions; (N, threads), real time.
//   BM_HomogeneousStage   the engine's collision stage alone on the same system (sub-populations,
//                         majorants, the thread pool): the denominator of Engine::step's overhead.
//   BM_SlabStreamSort     the slab mover (free flight, diffuse walls at both planes, layer index)
//                         plus the counting sort into 100 layers: particle moves per second.
//   BM_SlabStreamSortEdges  the same with 100 layers of different widths (11:1), placed by the
//                         lookup table (CellGrid::TableIndex): the cost of non-uniform layers.
//   BM_SlabCollideLayers  the collision stage of the same slab, layer by layer as Engine::collide
//                         drives it, elastic, ~N/100 collisions per call: compare with
//                         BM_PluginCollideCell/N/100 (one homogeneous cell, same rule).
//   BM_SlabEngineStep     Engine::step of that slab pipeline (flight, walls, sort, collisions);
//                         (N, threads), real time; with each stage's ms per step
//                         (Engine::stage_seconds: flight_ms, sort_ms, reorder_ms, ...).
//   BM_Memory{Read,Write,Flight}  six arrays of N doubles read, written, or moved as in free
//                         flight, on the WorkPool: the machine's own 1 -> 2 thread ceiling.
//   BM_MemoryPairs, BM_CoreCompute  random candidate pairs in three of those arrays, and
//                         arithmetic in registers: what random access and the cores gain.
//   BM_Rng*               the random-number primitives the loop uses.
//
// The cell benchmarks take N (particles) and alpha_pct (restitution x 100). With alpha < 1 the gas
// cools; the temperature is followed exactly from the declared energy changes and the velocities
// are rescaled to T0 (outside the timed region) whenever T < 0.8 T0, so the majorant, acceptance
// rate and dt stay those of a T0 Maxwellian-like state. alpha_pct = 100 is the pure-cost
// comparison without rescaling.
//
// Counters: collisions/s and candidates/s (rates over CPU time), accept = accepted / candidates.
// After the run a summary table gives, per N, the rates of every path and the cost ratio
// plugin / hand loop (= hand rate / plugin rate; 1.0 means the plugin path is free).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/collision.hpp>
#include <gdsmc/physics/moments.hpp>

#include "config/pipeline.hpp"
#include "engine/bulk_rng.hpp"
#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/engine.hpp"
#include "engine/majorant.hpp"
#include "engine/particle_store.hpp"
#include "engine/streams.hpp"
#include "plugins/loader.hpp"
#include "bench_support.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

// ---------------------------------------------------------------------------------------------
// The hand-written loop: one function, plain doubles, gdsmc::Rng drawn in the host scheme's order.

struct HandStats {
  std::uint64_t candidates = 0, accepted = 0, exceeded = 0;
  double max_rate = 0, energy_change = 0;
};

// S: the distance between one particle's velocity components and the next particle's: 1 for
// three separate arrays (the host's structure of arrays), 4 for velocities interleaved as
// (vx, vy, vz, pad) records of 32 bytes, one particle's velocity in one cache line.
template <std::size_t S>
void hand_collide(double* vx, double* vy, double* vz, std::uint32_t n, double pairs, double volume, double sigma,
                  double dt, double w, double alpha, double& remainder, Rng& select, Rng& kernel, HandStats& st) {
  if (n < 2 || w <= 0) {
    remainder = 0;
    return;
  }
  // 000 Eqs. 4.13 / 4.23: P sigma^2 pi w dt / V candidates with P the cell's pair count
  // (N (N - 1) / 2 by default; Omega_B = pi for hard spheres).
  const double expected = pairs * sigma * sigma * M_PI * w / volume * dt + remainder;
  const auto candidates = static_cast<std::uint64_t>(expected);
  remainder = expected - static_cast<double>(candidates);
  const double half_one_plus_alpha = 0.5 * (1.0 + alpha);
  const double loss = -0.25 * (1.0 - alpha * alpha);
  std::uint64_t accepted = 0, exceeded = 0;
  double max_rate = st.max_rate, energy = 0;
  // Batches of 32 candidates: pairs and acceptance numbers drawn first (selection stream) and their
  // velocities prefetched, then tested and collided in order, each on the current velocities,
  // the impact directions from the kernel stream.
  constexpr std::uint32_t kBatch = 32;
  std::uint32_t bi[kBatch], bj[kBatch];
  double bu[kBatch];
  for (std::uint64_t k0 = 0; k0 < candidates; k0 += kBatch) {
   const auto m = static_cast<std::uint32_t>(std::min<std::uint64_t>(kBatch, candidates - k0));
   for (std::uint32_t q = 0; q < m; ++q) {
    const std::uint32_t a = select.below(n);
    std::uint32_t b = select.below(n - 1);
    b += (b >= a);
    bi[q] = a;
    bj[q] = b;
    bu[q] = select.uniform32();
    if constexpr (S == 1) {
      for (const double* v : {vx, vy, vz}) {
        __builtin_prefetch(v + a, 1, 3);
        __builtin_prefetch(v + b, 1, 3);
      }
    } else {
      __builtin_prefetch(vx + S * a, 1, 3);
      __builtin_prefetch(vx + S * b, 1, 3);
    }
   }
   for (std::uint32_t q = 0; q < m; ++q) {
    const std::size_t i = S * bi[q], j = S * bj[q];
    const double gx = vx[i] - vx[j], gy = vy[i] - vy[j], gz = vz[i] - vz[j];
    const double g = std::sqrt(gx * gx + gy * gy + gz * gz);
    const double u = bu[q];
    if (g > w) {  // majorant exceeded: accept with probability 1, report the rate seen
      ++exceeded;
      max_rate = std::max(max_rate, g);
    } else if (u * w >= g) {
      continue;  // rejected: probability 1 - |g| / w
    }
    // sigma_hat ~ Theta(g.s)(g.s): normalize(g_hat + e), e uniform on the unit sphere
    // (Marsaglia: a point uniform in the unit disc mapped to the sphere).
    double eu, ev, es;
    do {
      eu = 2.0 * kernel.uniform32() - 1.0;
      ev = 2.0 * kernel.uniform32() - 1.0;
      es = eu * eu + ev * ev;
    } while (es >= 1.0 || es == 0.0);
    const double ef = 2.0 * std::sqrt(1.0 - es);
    const double ig = 1.0 / g;
    double sx = ig * gx + eu * ef, sy = ig * gy + ev * ef, sz = ig * gz + (1.0 - 2.0 * es);
    const double len = std::sqrt(sx * sx + sy * sy + sz * sz);
    if (len < 1e-300) {
      sx = ig * gx; sy = ig * gy; sz = ig * gz;
    } else {
      const double il = 1.0 / len;
      sx *= il; sy *= il; sz *= il;
    }
    // Eq. 2.8: v_i' = v_i - (1+alpha)/2 (g.s) s,  v_j' = v_j + (1+alpha)/2 (g.s) s.
    const double gs = gx * sx + gy * sy + gz * sz;
    const double f = half_one_plus_alpha * gs;
    vx[i] -= f * sx; vy[i] -= f * sy; vz[i] -= f * sz;
    vx[j] += f * sx; vy[j] += f * sy; vz[j] += f * sz;
    energy += loss * gs * gs;
    ++accepted;
   }
  }
  st.candidates += candidates;
  st.accepted += accepted;
  st.exceeded += exceeded;
  st.max_rate = max_rate;
  st.energy_change += energy;
}

// A copy of plugins/collision/inelastic_hard_spheres for the statically instantiated SDK kernel.
struct BenchIHS {
  explicit BenchIHS(double a) : alpha(a), half_one_plus_alpha(0.5 * (1.0 + a)) {}
  double collide(Vec3& v1, Vec3& v2, const Vec3& s, PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const Vec3 dv = (half_one_plus_alpha * gs) * s;
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1.0 - alpha * alpha) * gs * gs;
  }
  double alpha, half_one_plus_alpha;
};

// ---------------------------------------------------------------------------------------------
// A homogeneous cell and the host side of its collision stage (as Engine::collide).

// Its arrays are allocated as the engine's store allocates them (huge pages), so that the hand
// loop, the plugin and the engine are compared on the same memory.
struct Cell {
  host::ParticleArray<std::uint32_t> id;    // particle identities 0..N-1 (ParticleSpan::id)
  host::ParticleArray<std::uint32_t> cell;  // all in cell 0 (ParticleSpan::cell)
  host::ParticleArray<double> vx, vy, vz;   // never reallocated: a rule bound to span() stays valid
  host::ParticleArray<double> interleaved;  // (vx, vy, vz, 0) records, for BM_HandLoopInterleaved only
  std::uint32_t n;
  double volume;
  double temperature = kT0;  // followed exactly from the declared energy changes (m = 1, u = 0)
  double majorant_ratio = gdsmc::host::kInitialMajorantRatio;  // the hand loop's (the host's stage keeps its own)
  double remainder = 0;
  host::CellGrid grid;            // one homogeneous cell
  host::CollisionStage scheme;    // the host's scheme, for the plugin paths
  host::StreamFactory streams;       // the run's streams, as the engine holds them
  std::uint64_t step = 0;
  std::uint64_t candidates = 0, accepted = 0, exceeded = 0, rescales = 0;

  explicit Cell(std::uint32_t particles, std::uint32_t realization = 0)
      : id(particles), cell(particles, 0u), vx(particles), vy(particles), vz(particles), n(particles),
        volume(particles / kDensity), streams(kSeed, realization) {
    grid.homogeneous(particles, volume);
    // Each particle from its own initial-state stream (as Streams::for_particle in a plugin).
    const Streams initial = streams.streams(StreamPurpose::initial_state, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
      id[i] = i;
      Rng rng = initial.for_particle(id[i]);
      vx[i] = rng.normal();
      vy[i] = rng.normal();
      vz[i] = rng.normal();
    }
    rescale();
  }
  ParticleSpan span() {
    ParticleSpan s;
    s.count = n;
    s.id = id.data();
    s.cell = cell.data();
    s.vx = vx.data(); s.vy = vy.data(); s.vz = vz.data();
    s.x = s.y = s.z = nullptr;
    return s;
  }
  // The velocities as interleaved records (BM_HandLoopInterleaved), from the arrays.
  void interleave() {
    interleaved.assign(4 * static_cast<std::size_t>(n), 0.0);
    for (std::uint32_t i = 0; i < n; ++i) {
      interleaved[4 * i] = vx[i];
      interleaved[4 * i + 1] = vy[i];
      interleaved[4 * i + 2] = vz[i];
    }
  }
  // Zero mean velocity, temperature exactly T0.
  void rescale() {
    if (!interleaved.empty())
      for (std::uint32_t i = 0; i < n; ++i) {
        vx[i] = interleaved[4 * i]; vy[i] = interleaved[4 * i + 1]; vz[i] = interleaved[4 * i + 2];
      }
    const VelocityMoments m = velocity_moments(span());
    const double f = std::sqrt(kT0 / m.temperature);
    for (std::uint32_t i = 0; i < n; ++i) {
      vx[i] = (vx[i] - m.mean[0]) * f;
      vy[i] = (vy[i] - m.mean[1]) * f;
      vz[i] = (vz[i] - m.mean[2]) * f;
    }
    temperature = kT0;
    ++rescales;
    if (!interleaved.empty()) interleave();
  }
  // dt for ~N/100 accepted collisions: a call accepts 0.5 N n pi sigma^2 <|g|> dt on average,
  // <|g|> = 4 sqrt(T / pi) for a Maxwellian (m = 1).
  double dt() const {
    const double mean_g = 4.0 * std::sqrt(temperature / M_PI);
    return 2.0 * kCollisionFractionPerCall / (kDensity * M_PI * kSigma * kSigma * mean_g);
  }
  // One collision stage of `rule` by the host's scheme, as Engine::collide drives it (the step's
  // key; the majorant from the cell's temperature).
  void collide_with(const CollisionRule& rule) {
    streams.set_step(step);
    const host::CollisionStage::Totals t = scheme.run(rule, span(), grid, nullptr, temperature, 1.0, kSigma, dt(), streams);
    account(t.candidates, t.accepted, t.majorant_exceeded, t.energy_change);
  }
  void account(std::uint64_t cand, std::uint64_t acc, std::uint64_t exc, double energy_change) {
    candidates += cand;
    accepted += acc;
    exceeded += exc;
    temperature += (2.0 / 3.0) * energy_change / n;  // E = 3/2 N T
    ++step;
  }
};

// One collision stage by the hand loop, on the streams and with the majorant bookkeeping of the
// host's scheme (host::CollisionStage) for one cell.
template <std::size_t S = 1>
void hand_stage(Cell& cell, double alpha) {
  cell.streams.set_step(cell.step);
  Rng select = cell.streams.rng(StreamPurpose::collisions, 0, 0);
  Rng kernel = cell.streams.rng(StreamPurpose::collisions, 2, 0);
  const double thermal_speed = std::sqrt(cell.temperature / 1.0);
  const double w = cell.majorant_ratio * thermal_speed;
  HandStats st;
  double* v = S == 1 ? cell.vx.data() : cell.interleaved.data();
  hand_collide<S>(v, S == 1 ? cell.vy.data() : v + 1, S == 1 ? cell.vz.data() : v + 2, cell.n,
                  host::pair_count(host::PairCount::distinct, cell.n),
               cell.volume, kSigma, cell.dt(), w, alpha, cell.remainder, select, kernel, st);
  if (st.max_rate > w) cell.majorant_ratio = gdsmc::host::kMajorantHeadroom * st.max_rate / thermal_speed;
  cell.account(st.candidates, st.accepted, st.exceeded, st.energy_change);
}

// ---------------------------------------------------------------------------------------------
// The plugin, loaded once.

const host::LoadedPlugin& ihs_plugin() {
  static const host::LoadedPlugin plugin = [] {
    auto p = host::load_plugin(plugin_dir() + "/gdsmc_inelastic_hard_spheres.so");
    if (p.descriptor->kind != PluginKind::collision_rule)
      throw std::runtime_error("gdsmc_inelastic_hard_spheres.so is not a collision rule");
    return p;
  }();
  return plugin;
}

std::shared_ptr<PluginObject> make_ihs(double alpha) {
  Params params;
  params.set("alpha", alpha);
  return host::create_object(ihs_plugin(), params);
}

// The plugin's rule, bound once to the cell's particles (bind at set-up, then only const
// collide_batch calls). The descriptor says collision_rule, so the cast is exact (as in Engine).
CollisionRule* bound_rule(PluginObject* object, Cell& cell) {
  auto* rule = static_cast<CollisionRule*>(object);
  rule->bind(cell.span());
  return rule;
}

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

// ---------------------------------------------------------------------------------------------
// Start-up check: the plugin and the hand loop are the same algorithm on the same streams.

void verify_same_trajectory() {
  constexpr std::uint32_t n = 10000;
  constexpr int calls = 300;  // ~30 collisions per particle, with rescales
  Cell a(n), b(n);
  std::shared_ptr<PluginObject> obj;
  try {
    obj = make_ihs(0.9);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "check: cannot load the plugin: %s\n", e.what());
    return;
  }
  const CollisionRule* rule = bound_rule(obj.get(), a);
  for (int k = 0; k < calls; ++k) {
    a.collide_with(*rule);
    hand_stage(b, 0.9);
    if (a.temperature < kRescaleBelow * kT0) a.rescale();
    if (b.temperature < kRescaleBelow * kT0) b.rescale();
  }
  double max_diff = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    max_diff = std::max({max_diff, std::abs(a.vx[i] - b.vx[i]), std::abs(a.vy[i] - b.vy[i]), std::abs(a.vz[i] - b.vz[i])});
  const bool same = max_diff == 0 && a.accepted == b.accepted && a.candidates == b.candidates;
  std::fprintf(stderr,
               "check: plugin vs hand loop, N = %u, alpha = 0.9, %d calls: candidates %llu / %llu, accepted %llu / %llu, "
               "rescales %llu / %llu, max |dv| = %g -> %s\n",
               n, calls, static_cast<unsigned long long>(a.candidates), static_cast<unsigned long long>(b.candidates),
               static_cast<unsigned long long>(a.accepted), static_cast<unsigned long long>(b.accepted),
               static_cast<unsigned long long>(a.rescales), static_cast<unsigned long long>(b.rescales), max_diff,
               same ? "bit-identical" : "DIFFERENT (the two loops are not the same algorithm)");
}

// ---------------------------------------------------------------------------------------------
// A console reporter that also remembers the counters, for the summary table.

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  using benchmark::ConsoleReporter::ConsoleReporter;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs) {
      if (r.error_occurred) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type == Run::RT_Aggregate && !median) continue;
      auto it = r.counters.find("collisions/s");
      if (it == r.counters.end()) continue;
      Entry& e = results_[{r.run_name.function_name, r.run_name.args}];
      if (e.from_median && !median) continue;
      e.collisions = it->second.value;
      const auto cand = r.counters.find("candidates/s");
      e.candidates = cand == r.counters.end() ? 0.0 : cand->second.value;
      e.from_median = median;
    }
    benchmark::ConsoleReporter::ReportRuns(runs);
  }
  void PrintSummary() const {
    std::vector<std::string> args;
    for (const auto& [key, e] : results_)
      if (key.first == "BM_HandLoop") args.push_back(key.second);
    if (args.empty()) return;
    std::printf("\nSummary (collisions/s on one core; cost ratio = hand rate / path rate, 1.00 = as fast as the hand loop)\n");
    std::printf("%-24s %12s %12s %12s %12s %10s %10s %10s\n", "cell", "hand", "plugin", "static", "engine.step",
                "plug/hand", "stat/hand", "eng/hand");
    auto rate = [&](const char* fn, const std::string& a) {
      auto it = results_.find({fn, a});
      return it == results_.end() ? 0.0 : it->second.collisions;
    };
    for (const auto& a : args) {
      const double hand = rate("BM_HandLoop", a), plugin = rate("BM_PluginCollideCell", a),
                   stat = rate("BM_StaticAdapter", a);
      const bool hcs = a.find("alpha_pct:90") != std::string::npos;
      const double engine = hcs ? rate("BM_EngineStep", a.substr(0, a.find('/')) + "/threads:1") : 0.0;
      auto ratio = [&](double x) { return x > 0 ? hand / x : 0.0; };
      std::printf("%-24s %12.4g %12.4g %12.4g %12.4g %10.3f %10.3f %10.3f\n", a.c_str(), hand, plugin, stat, engine,
                  ratio(plugin), ratio(stat), ratio(engine));
    }
  }

 private:
  struct Entry {
    double collisions = 0, candidates = 0;
    bool from_median = false;
  };
  std::map<std::pair<std::string, std::string>, Entry> results_;
};

// Fixed-work mode for instruction-counting profilers (valgrind --tool=callgrind), no timing:
//   gdsmc_bench --profile {plugin|adapter|hand} N CALLS [ALPHA_PCT]
int profile(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: gdsmc_bench --profile {plugin|adapter|hand} N CALLS [ALPHA_PCT]\n");
    return 2;
  }
  const std::string path = argv[2];
  const auto n = static_cast<std::uint32_t>(std::stoul(argv[3]));
  const long calls = std::stol(argv[4]);
  const double alpha = (argc > 5 ? std::stod(argv[5]) : 100.0) / 100.0;
  Cell cell(n);
  std::shared_ptr<PluginObject> object;
  std::unique_ptr<CollisionRuleAdapter<BenchIHS>> adapter;
  const CollisionRule* rule = nullptr;
  if (path == "plugin") {
    object = make_ihs(alpha);
    rule = bound_rule(object.get(), cell);
  } else if (path == "adapter") {
    adapter = std::make_unique<CollisionRuleAdapter<BenchIHS>>(BenchIHS(alpha));
    adapter->bind(cell.span());
    rule = adapter.get();
    benchmark::DoNotOptimize(rule);
  } else if (path != "hand") {
    std::fprintf(stderr, "unknown path '%s'\n", path.c_str());
    return 2;
  }
  for (long k = 0; k < calls; ++k) {
    if (rule) cell.collide_with(*rule);
    else hand_stage(cell, alpha);
    if (cell.temperature < kRescaleBelow * kT0) cell.rescale();
  }
  std::printf("%s N=%u calls=%ld candidates=%llu accepted=%llu T=%.6f\n", path.c_str(), n, calls,
              static_cast<unsigned long long>(cell.candidates), static_cast<unsigned long long>(cell.accepted),
              cell.temperature);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--profile") return profile(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  verify_same_trajectory();
  SummaryReporter reporter(benchmark::ConsoleReporter::OO_Tabular);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintSummary();
  benchmark::Shutdown();
  return 0;
}
