// gdsmc SDK: what plugins may read about the system and the current step.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "gdsmc/random.hpp"

namespace gdsmc {

enum class Geometry : std::uint32_t { homogeneous = 0, slab = 1 };

// Fixed for a run. Reduced units: m = 1, k_B = 1, lengths in the same unit as sigma.
struct SystemInfo {
  std::size_t particles = 0;
  double number_density = 0;       // n (mean)
  double sigma = 1;                // diameter
  double mass = 1;                 // m (always 1 in this version)
  double initial_temperature = 1;  // T0
  double mean_free_path0 = 0;      // lambda0 = 1 / (sqrt(2) pi n sigma^2)   (000 Eq. 4.1)
  double time_unit0 = 0;           // tau0 = lambda0 / sqrt(2 T0 / m)         (000 Eq. 4.1)
  double volume = 0;               // Omega = N / n
  Geometry geometry = Geometry::homogeneous;
  double box[3] = {0, 0, 0};       // box edges (slab: box[1] is the gap along y)
  std::size_t cells = 1;           // collision cells (layers in y for a slab)
  std::uint64_t seed = 0;
  std::uint32_t realization = 0;
};

// Moments of the particles in one cell (or of the whole system, cell 0 of a homogeneous run).
struct CellMoments {
  std::size_t count = 0;
  double number_density = 0;
  double mean_velocity[3] = {0, 0, 0};
  double temperature = 0;  // (m / 3N) sum (v - u)^2
};

// Named scalars that plugins publish for each other (e.g. the collision rule publishes
// "restitution"), so that a diagnostic or a forcing can use a model parameter without the user
// repeating it and without the host knowing what it means.
class QuantityBoard {
 public:
  void publish(const std::string& name, double value) { values_[name] = value; }
  const double* find(const std::string& name) const {
    auto it = values_.find(name);
    return it == values_.end() ? nullptr : &it->second;
  }
  const std::map<std::string, double>& all() const { return values_; }

 private:
  std::map<std::string, double> values_;
};

// Read-only view of the current step, handed to every plugin call.
struct StepContext {
  const SystemInfo* system = nullptr;
  std::uint64_t step = 0;       // steps completed before this call
  double time = 0;              // reduced units; time / system->time_unit0 is t / tau0
  double dt = 0;                // the step being taken (reduced units)
  double collisions = 0;        // accepted collisions so far
  double candidates = 0;        // candidate pairs tested so far
  double majorant_exceeded = 0; // candidates whose rate exceeded the cell majorant so far
  double collision_energy_change = 0;  // sum of the kinetic-energy change of every collision so far
  const CellMoments* cells = nullptr;  // per-cell moments as of the last update
  std::size_t cell_count = 0;
  const CellMoments* global = nullptr;  // moments of all particles as of the last update
  QuantityBoard* quantities = nullptr;
  PhiloxKey key{0u, 0u};        // the run's stream key

  // s(t): accepted collisions divided by the number of particles (000, text after Fig. 4).
  double collisions_per_particle() const {
    return system->particles ? collisions / static_cast<double>(system->particles) : 0.0;
  }
  double time_in_tau0() const { return time / system->time_unit0; }
  // The stream for (purpose, unit) at this step.
  Rng rng(StreamPurpose purpose, std::uint32_t unit) const { return Rng(key, purpose, unit, step); }
};

}  // namespace gdsmc
