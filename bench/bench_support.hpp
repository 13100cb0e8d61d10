// What the benchmark files share: the constants of the benchmarked systems, where the plugins and
// the HCS pipeline are, and the set-up cache that pays a 10^6-particle set-up once per benchmark.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <type_traits>

#include "config/pipeline.hpp"

namespace gdsmc::bench {

constexpr double kT0 = 1.0;
constexpr double kDensity = 1e-3;  // n sigma^3, as in configs/hcs.yaml (the cost does not depend on it)
constexpr double kSigma = 1.0;
constexpr double kCollisionFractionPerCall = 0.01;       // ~N/100 accepted collisions per call
constexpr double kRescaleBelow = 0.8;                    // rescale velocities when T < 0.8 T0
constexpr std::uint64_t kSeed = 2026;

inline std::string env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : std::string(fallback);
}
inline std::string plugin_dir() { return env_or("GDSMC_BENCH_PLUGIN_DIR", GDSMC_BENCH_PLUGIN_DIR); }
inline std::string pipeline_file() { return env_or("GDSMC_BENCH_PIPELINE", GDSMC_BENCH_PIPELINE); }

// State kept across the repeated calls Google Benchmark makes to one benchmark (iteration-count
// search, repetitions): the 1e6-particle set-up is paid once and the gas keeps evolving.
template <class T>
T& cached(const std::string& name, std::int64_t n, std::int64_t alpha_pct) {
  static std::map<std::tuple<std::string, std::int64_t, std::int64_t>, std::unique_ptr<T>> cache;
  auto& slot = cache[{name, n, alpha_pct}];
  if (!slot) {
    if constexpr (std::is_constructible_v<T, std::uint32_t, std::int64_t>)
      slot = std::make_unique<T>(static_cast<std::uint32_t>(n), alpha_pct);  // second key: threads
    else
      slot = std::make_unique<T>(static_cast<std::uint32_t>(n));
  }
  return *slot;
}

template <class T>
T* cached_or_skip(benchmark::State& state, const std::string& name) {
  try {
    return &cached<T>(name, state.range(0), state.range(1));
  } catch (const host::PipelineError& e) {
    std::string m;
    for (const auto& s : e.messages()) m += s + "; ";
    state.SkipWithError(m.c_str());
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  return nullptr;
}

}  // namespace gdsmc::bench
