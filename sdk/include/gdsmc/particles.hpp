// gdsmc SDK: the particles as structure-of-arrays spans. The host owns the storage; plugins see
// pointers to contiguous arrays and work on whole spans at once.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "gdsmc/params.hpp"
#include "gdsmc/vec3.hpp"

namespace gdsmc {

// An extra per-particle quantity a plugin declares (e.g. an angular velocity with 3 components).
// The host allocates it, keeps it with its particle through every reordering and writes it out.
struct AttributeSpec {
  std::string name;       // unique across the pipeline, e.g. "angular_velocity"
  int components = 1;     // stored component-major: component c of particle i at data[c*count + i]
  std::string unit;       // as written to the output, e.g. "sqrt(T0/m)/sigma"
  std::string doc;
};

struct ParticleSpan {
  std::size_t count = 0;
  // Each particle's identity, 0 .. N-1 (N < 2^32): fixed for the whole run whatever the storage
  // order (key of its random streams, Streams::for_particle). 32 bits since SDK 5.0.
  const std::uint32_t* id = nullptr;
  // The collision cell (slab: the layer along y, 000 Eq. 4.3) each particle sat in at the last
  // sort; all 0 in a homogeneous system.
  const std::uint32_t* cell = nullptr;
  // Positions (reduced length units). Slab: x in [0, Lx), y in [-Ly/2, Ly/2], z in [0, Lz).
  // Homogeneous systems do not move particles; positions are then only what the initial state
  // wrote.
  double* x = nullptr;
  double* y = nullptr;
  double* z = nullptr;
  // Velocities (reduced units, m = 1): laboratory velocities, or peculiar velocities in the
  // Lagrangian frame of a homogeneous system.
  double* vx = nullptr;
  double* vy = nullptr;
  double* vz = nullptr;
  // Extra attributes declared by plugins.
  std::size_t attribute_count = 0;
  const AttributeSpec* attribute_specs = nullptr;
  double* const* attribute_data = nullptr;

  Vec3 velocity(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
  void set_velocity(std::size_t i, const Vec3& v) const { vx[i] = v.x; vy[i] = v.y; vz[i] = v.z; }
  Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }

  // The data of an attribute, or nullptr if no plugin declared it. Look it up once per call, not
  // per particle.
  double* attribute(const char* name) const {
    for (std::size_t k = 0; k < attribute_count; ++k)
      if (attribute_specs[k].name == name) return attribute_data[k];
    return nullptr;
  }
};

}  // namespace gdsmc
