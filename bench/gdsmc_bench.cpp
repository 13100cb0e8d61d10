// gdsmc_bench: cost of the DSMC collision stage of inelastic hard spheres in one homogeneous cell,
// of the slab's streaming and layer collisions, and of Engine::step.
// The benchmarks by stage: one homogeneous cell (cell_bench.cpp, on cell.hpp: the hand-written
// reference loop, the cell and the plugin path, which the start-up bit-identity check here uses
// too, so that it compares exactly what is timed), the engine (engine_bench.cpp), the random
// numbers (rng_bench.cpp), the slab (slab_bench.cpp) and the machine's own (memory_bench.cpp);
// what they share is in bench_support.hpp. This file: the start-up check, the summary table, the
// --profile mode and main.
//
//   BM_PluginCollideCell  the IHS plugin (.so loaded at run time with gdsmc::host::load_plugin +
//                         create_object, bound once to the particles with CollisionRule::bind),
//                         driven by the host's scheme (host::CollisionStage, one cell): the host
//                         draws the candidates and hands them to the plugin's pair kernel in
//                         batches, one virtual collide_batch(PairBatch&) call per batch.
//   BM_StaticAdapter      the same, with the SDK's kernel (CollisionRuleAdapter) instantiated
//                         inside this executable with a copy of the IHS rule: separates "the
//                         kernel" from "loaded through a .so".
//   BM_HandLoop           plain functions of the same physics and the same algorithm (same
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
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cell.hpp"

namespace {

using namespace gdsmc;
using namespace gdsmc::bench;

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
