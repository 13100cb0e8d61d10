// A small engine-like harness for direct calls on plugin objects: particles, moments and one
// collision stage of the configured rule, with snapshots to replay states.
#pragma once
#include <algorithm>
#include <memory>
#include <vector>

#include <gdsmc/moments.hpp>
#include <gdsmc/plugin.hpp>

#include "config/pipeline.hpp"
#include "engine/majorant.hpp"
#include "engine/particle_store.hpp"

namespace gdsmc::host::conformance {

struct Snapshot {
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::vector<double>> attributes;
};

struct Harness {
  std::unique_ptr<Pipeline> pipeline;
  const PluginUse* use = nullptr;
  std::shared_ptr<PluginObject> initial, collision, subject;
  std::vector<AttributeSpec> attributes;
  SystemInfo sys;
  QuantityBoard board;
  CellMoments global;
  StepContext ctx;
  ParticleStore store;
  double remainder = 0;

  ParticleSpan span() { return store.span(); }
  void update_moments() {
    const VelocityMoments m = velocity_moments(store.span());
    global.count = m.count;
    global.number_density = sys.number_density;
    for (int a = 0; a < 3; ++a) global.mean_velocity[a] = m.mean[a];
    global.temperature = m.temperature;
  }
  std::shared_ptr<PluginObject> fresh_subject() const { return create_object(*use->plugin, use->params); }

  Snapshot save() {
    const ParticleSpan p = span();
    Snapshot s;
    auto copy = [&](const double* d) { return std::vector<double>(d, d + p.count); };
    s.x = copy(p.x); s.y = copy(p.y); s.z = copy(p.z);
    s.vx = copy(p.vx); s.vy = copy(p.vy); s.vz = copy(p.vz);
    for (std::size_t a = 0; a < p.attribute_count; ++a)
      s.attributes.emplace_back(p.attribute_data[a], p.attribute_data[a] + p.count * p.attribute_specs[a].components);
    return s;
  }
  // Restore a snapshot; with `perm`, particle k of the span is particle perm[k] of the snapshot.
  void restore(const Snapshot& s, const std::vector<std::uint32_t>* perm = nullptr) {
    const ParticleSpan p = span();
    for (std::size_t k = 0; k < p.count; ++k) {
      const std::size_t i = perm ? (*perm)[k] : k;
      p.x[k] = s.x[i]; p.y[k] = s.y[i]; p.z[k] = s.z[i];
      p.vx[k] = s.vx[i]; p.vy[k] = s.vy[i]; p.vz[k] = s.vz[i];
      for (std::size_t a = 0; a < p.attribute_count; ++a) {
        const std::size_t comps = static_cast<std::size_t>(p.attribute_specs[a].components);
        for (std::size_t c = 0; c < comps; ++c) p.attribute_data[a][c * p.count + k] = s.attributes[a][c * p.count + i];
      }
    }
    update_moments();
  }
  // Attributes that the initial state left at zero get random values (so that rules and
  // diagnostics that use them see something to work on).
  void randomize_zero_attributes(Rng& rng) {
    const ParticleSpan p = span();
    for (std::size_t a = 0; a < p.attribute_count; ++a) {
      const std::size_t n = p.count * static_cast<std::size_t>(p.attribute_specs[a].components);
      double* d = p.attribute_data[a];
      if (std::all_of(d, d + n, [](double v) { return v == 0.0; }))
        for (std::size_t k = 0; k < n; ++k) d[k] = rng.normal();
    }
  }
  // One collision stage of the filler (or tested) collision rule over the whole population.
  CellCollision collide(double dt, Rng& rng) {
    auto* rule = static_cast<CollisionRule*>(collision.get());
    CellCollision cell;
    cell.particles = span();
    cell.count = static_cast<std::uint32_t>(cell.particles.count);
    cell.volume = sys.volume;
    cell.sigma = sys.sigma;
    cell.dt = dt;
    cell.majorant = kInitialMajorantRatio * std::sqrt(global.temperature);
    cell.remainder = remainder;
    cell.rng = &rng;
    rule->collide_cell(cell);
    remainder = cell.remainder;
    ctx.collisions += static_cast<double>(cell.accepted);
    ctx.candidates += static_cast<double>(cell.candidates);
    ctx.collision_energy_change += cell.energy_change;
    update_moments();
    return cell;
  }
};

}  // namespace gdsmc::host::conformance
