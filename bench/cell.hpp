// The one homogeneous cell of the cell benchmarks (cell_bench.cpp) and of the start-up check
// (gdsmc_bench.cpp): the hand-written reference loop, the cell and the host side of its collision
// stage, and the IHS plugin loaded once. In one header, so that the check compares exactly what
// is timed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>

#include <gdsmc/collision.hpp>
#include <gdsmc/physics/moments.hpp>

#include "bench_support.hpp"
#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/majorant.hpp"
#include "engine/particle_store.hpp"
#include "engine/streams.hpp"
#include "plugins/loader.hpp"

namespace gdsmc::bench {

// ---------------------------------------------------------------------------------------------
// The hand-written loop: plain functions, plain doubles, gdsmc::Rng drawn in the host scheme's order.

struct HandStats {
  std::uint64_t candidates = 0, accepted = 0, exceeded = 0;
  double max_rate = 0, energy_change = 0;
};

// An accepted pair (i, j) of relative velocity g (|g| = gn): the impact direction sigma_hat ~
// Theta(g.s)(g.s), drawn as normalize(g_hat + e) with e uniform on the unit sphere (Marsaglia: a
// point uniform in the unit disc mapped to the sphere) from the kernel stream, then Eq. 2.8:
// v_i' = v_i - (1+alpha)/2 (g.s) s, v_j' = v_j + (1+alpha)/2 (g.s) s. Returns g.s.
inline double hand_pair(double* vx, double* vy, double* vz, std::size_t i, std::size_t j, double gx, double gy,
                        double gz, double gn, double half_one_plus_alpha, Rng& kernel) {
  double eu, ev, es;
  do {
    eu = 2.0 * kernel.uniform32() - 1.0;
    ev = 2.0 * kernel.uniform32() - 1.0;
    es = eu * eu + ev * ev;
  } while (es >= 1.0 || es == 0.0);
  const double ef = 2.0 * std::sqrt(1.0 - es);
  const double ig = 1.0 / gn;
  double sx = ig * gx + eu * ef, sy = ig * gy + ev * ef, sz = ig * gz + (1.0 - 2.0 * es);
  const double len = std::sqrt(sx * sx + sy * sy + sz * sz);
  if (len < 1e-300) {
    sx = ig * gx; sy = ig * gy; sz = ig * gz;
  } else {
    const double il = 1.0 / len;
    sx *= il; sy *= il; sz *= il;
  }
  const double gs = gx * sx + gy * sy + gz * sz;
  const double f = half_one_plus_alpha * gs;
  vx[i] -= f * sx; vy[i] -= f * sy; vz[i] -= f * sz;
  vx[j] += f * sx; vy[j] += f * sy; vz[j] += f * sz;
  return gs;
}

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
    const double gs = hand_pair(vx, vy, vz, i, j, gx, gy, gz, g, half_one_plus_alpha, kernel);
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

inline const host::LoadedPlugin& ihs_plugin() {
  static const host::LoadedPlugin plugin = [] {
    auto p = host::load_plugin(plugin_dir() + "/gdsmc_inelastic_hard_spheres.so");
    if (p.descriptor->kind != PluginKind::collision_rule)
      throw std::runtime_error("gdsmc_inelastic_hard_spheres.so is not a collision rule");
    return p;
  }();
  return plugin;
}

inline std::shared_ptr<PluginObject> make_ihs(double alpha) {
  Params params;
  params.set("alpha", alpha);
  return host::create_object(ihs_plugin(), params);
}

// The plugin's rule, bound once to the cell's particles (bind at set-up, then only const
// collide_batch calls). The descriptor says collision_rule, so the cast is exact (as in Engine).
inline CollisionRule* bound_rule(PluginObject* object, Cell& cell) {
  auto* rule = static_cast<CollisionRule*>(object);
  rule->bind(cell.span());
  return rule;
}

}  // namespace gdsmc::bench
