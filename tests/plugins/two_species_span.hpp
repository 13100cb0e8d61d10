// Test support for the species-aware plugins (SDK 6.5): a hand-built two-species system and
// particle span (species 0 "light" of mass 1, species 1 "heavy" of mass m_heavy, the identities
// [0, N_light) light and [N_light, N) heavy, as the host numbers them), and a plugin object made
// from a pipeline entry (the host validates the parameters and fills the defaults).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>

#include "config/system_info.hpp"
#include "engine/streams.hpp"
#include "test_support.hpp"

namespace gdsmc::test {

struct TwoSpecies {
  std::vector<SpeciesInfo> species;
  SystemInfo sys;
  std::vector<std::uint32_t> id, cell, kind;
  std::vector<double> x, y, z, vx, vy, vz;
  ParticleSpan span;
  std::size_t light = 0, heavy = 0;

  // `base`: the system of a pipeline (box, density, T0); the species are written over it.
  TwoSpecies(const SystemInfo& base, std::size_t n_light, std::size_t n_heavy, double m_heavy, double d_heavy = 1.5)
      : sys(base), light(n_light), heavy(n_heavy) {
    const std::size_t n = n_light + n_heavy;
    const double N = static_cast<double>(n);
    species = {SpeciesInfo{"light", 1.0, 1.0, static_cast<double>(n_light) / N},
               SpeciesInfo{"heavy", m_heavy, d_heavy, static_cast<double>(n_heavy) / N}};
    sys.particles = n;
    sys.species_count = 2;
    sys.species = species.data();
    id.resize(n);
    cell.assign(n, 0);
    kind.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      id[i] = static_cast<std::uint32_t>(i);
      kind[i] = i < n_light ? 0u : 1u;
    }
    for (auto* c : {&x, &y, &z, &vx, &vy, &vz}) c->assign(n, 0.0);
    span.count = n;
    span.id = id.data();
    span.cell = cell.data();
    span.x = x.data();
    span.y = y.data();
    span.z = z.data();
    span.vx = vx.data();
    span.vy = vy.data();
    span.vz = vz.data();
    span.species = kind.data();
  }
  TwoSpecies(const TwoSpecies&) = delete;
  TwoSpecies& operator=(const TwoSpecies&) = delete;

  double mass(std::size_t i) const { return sys.species_mass(kind[i]); }
  // T_s = m_s sum (v - u_s)^2 / 3 N_s about the species' own mean velocity u_s.
  double temperature(std::uint32_t s) const {
    double n = 0, u[3] = {0, 0, 0};
    for (std::size_t i = 0; i < span.count; ++i)
      if (kind[i] == s) {
        n += 1;
        u[0] += vx[i];
        u[1] += vy[i];
        u[2] += vz[i];
      }
    for (double& c : u) c /= n;
    double sum = 0;
    for (std::size_t i = 0; i < span.count; ++i)
      if (kind[i] == s) {
        const double dx = vx[i] - u[0], dy = vy[i] - u[1], dz = vz[i] - u[2];
        sum += dx * dx + dy * dy + dz * dz;
      }
    return sys.species_mass(s) * sum / (3.0 * n);
  }
  // sum m_i v_i (component c) and sum m_i
  double momentum(int c) const {
    const auto& v = c == 0 ? vx : c == 1 ? vy : vz;
    double p = 0;
    for (std::size_t i = 0; i < span.count; ++i) p += mass(i) * v[i];
    return p;
  }
  double total_mass() const {
    double m = 0;
    for (std::size_t i = 0; i < span.count; ++i) m += mass(i);
    return m;
  }
  double kinetic_energy() const {
    double e = 0;
    for (std::size_t i = 0; i < span.count; ++i) e += 0.5 * mass(i) * (vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]);
    return e;
  }
};

// A plugin object as the pipeline entry `use` of `yaml` declares it ("initial_state",
// "boundaries.y_min", "forcings[0]"), with the pipeline's system of `particles` particles.
struct PluginFromPipeline {
  host::Pipeline pipeline;
  std::shared_ptr<PluginObject> object;
  SystemInfo sys;
  PluginFromPipeline(const TempDir& dir, const std::string& yaml, const std::string& use, std::size_t particles) {
    pipeline = load_yaml(dir, yaml);
    const host::PluginUse* entry = pipeline.use_at(use);
    // boundaries: {y: ...} is one entry for both planes, at boundaries[0] (y_min)
    if (!entry && use == "boundaries.y_min" && !pipeline.boundaries.empty()) entry = &pipeline.boundaries[0];
    if (!entry) throw std::runtime_error("no pipeline entry " + use);
    object = host::create_object(*entry->plugin, entry->params);
    sys = host::system_info(pipeline, particles, 0);
  }
  template <class T>
  T& as() {
    return *static_cast<T*>(object.get());  // the kind of the entry `use`
  }
};

inline Streams streams_at(StreamPurpose purpose, std::uint64_t step, std::uint64_t seed = 7) {
  return host::StreamFactory::standalone_streams(seed, purpose, 1, step);
}

}  // namespace gdsmc::test
