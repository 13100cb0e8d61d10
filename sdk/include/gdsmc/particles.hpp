// gdsmc SDK: the particles as the host hands them over. The host owns the storage and its layout;
// plugins index columns and work on whole spans at once.
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

// One per-particle quantity in the host's storage: element i is data[i * stride]. The host chooses
// the layout (separate arrays, stride 1, or the components of one particle side by side, stride
// > 1) and may change it without an ABI change, so index through the column, never through a raw
// pointer taken from it.
template <class T>
struct Column {
  T* data = nullptr;
  std::size_t stride = 1;
  Column() = default;
  Column(T* d, std::size_t s = 1) : data(d), stride(s) {}  // NOLINT: a plain array is a column of stride 1
  T& operator[](std::size_t i) const { return data[i * stride]; }
  explicit operator bool() const { return data != nullptr; }
};

// The particles as the host hands them to plugins (SDK 6.0). Like every struct the host hands
// over, it grows only at its end within a major version: read the fields you know.
struct ParticleSpan {
  std::size_t count = 0;
  // Each particle's identity, 0 .. N-1 (N < 2^32): fixed for the whole run whatever the storage
  // order (key of its random streams, Streams::for_particle).
  const std::uint32_t* id = nullptr;
  // The collision cell (slab: the layer along y, 000 Eq. 4.3) each particle sat in at the last
  // sort; all 0 in a homogeneous system.
  const std::uint32_t* cell = nullptr;
  // Positions (reduced length units). Slab: x in [0, Lx), y in [-Ly/2, Ly/2], z in [0, Lz).
  // Homogeneous systems do not move particles and may store none (the columns are then empty).
  Column<double> x, y, z;
  // Velocities (reduced units, m = 1): laboratory velocities, or peculiar velocities in the
  // Lagrangian frame of a homogeneous system.
  Column<double> vx, vy, vz;
  // The species of each particle (SystemInfo::species), owned by the host; nullptr while the run
  // has a single species. Read it through species_of().
  const std::uint32_t* species = nullptr;
  // Extra attributes declared by plugins: component c of particle i of attribute k at
  // attribute_data[k][c * count + i].
  std::size_t attribute_count = 0;
  const AttributeSpec* attribute_specs = nullptr;
  double* const* attribute_data = nullptr;

  Vec3 velocity(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
  void set_velocity(std::size_t i, const Vec3& v) const { vx[i] = v.x; vy[i] = v.y; vz[i] = v.z; }
  Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  std::uint32_t species_of(std::size_t i) const { return species ? species[i] : 0u; }

  // The data of an attribute, or nullptr if no plugin declared it. Look it up once per call, not
  // per particle.
  double* attribute(const char* name) const {
    for (std::size_t k = 0; k < attribute_count; ++k)
      if (attribute_specs[k].name == name) return attribute_data[k];
    return nullptr;
  }
};

}  // namespace gdsmc
