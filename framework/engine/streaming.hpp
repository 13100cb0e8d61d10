// Free flight of a slab's particles over one step, exact for a constant body acceleration
// (x += v t + g t^2/2, v += g t), with every crossing of y = +-Ly/2 handed to that side's boundary
// plugin at the exact crossing time and the rest of the step streamed afterwards (004 Eqs. 6-12;
// several hits per step when the gap is small). x and z are periodic. The mover also writes each
// particle's layer for the counting sort and tallies what every boundary exchanges with the gas.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include <gdsmc/plugin.hpp>

#include <vector>

#include "config/system_info.hpp"
#include "engine/cells.hpp"
#include "engine/fixed_point_sum.hpp"
#include "engine/streams.hpp"
#include "engine/work_pool.hpp"

namespace gdsmc::host {

// The units of the mover's tallies: energy in T0, momentum in sqrt(m T0) (Mover::set_tally_units).
struct TallyUnits {
  FixedPointUnit energy, momentum;
  static TallyUnits of(double temperature, double mass) {
    return {FixedPointUnit::of(temperature), FixedPointUnit::of(std::sqrt(mass * temperature))};
  }
};

// A BoundaryTally with its sums in fixed point (engine/fixed_point_sum.hpp).
struct ExactBoundaryTally {
  std::uint64_t hits = 0;
  FixedPointSum momentum[3];
  FixedPointSum energy;
  ExactBoundaryTally& operator+=(const ExactBoundaryTally& other);
  BoundaryTally value(const TallyUnits& units) const;
  bool operator==(const ExactBoundaryTally&) const = default;
};

// What streaming added to the gas: per boundary (0: y_min, 1: y_max) and by the body acceleration
// during flight, each sum exact in fixed point: the same bits however the particles are split into
// blocks, threads or ranks and in whatever order the parts are added (+=).
struct ExactStreamingTally {
  static constexpr std::size_t kMaxSpecies = host::kMaxSpecies;  // config/system_info.hpp
  std::array<ExactBoundaryTally, 2> sides{};
  FixedPointSum acceleration_energy;  // sum of (m_i/2)(v'^2 - v^2) from g during flight
  // A mixture's sides per species: [side * kMaxSpecies + s] (Mover::set_species).
  std::array<ExactBoundaryTally, 2 * kMaxSpecies> species_sides{};
  ExactStreamingTally& operator+=(const ExactStreamingTally& other);
  bool operator==(const ExactStreamingTally&) const = default;
};

// The tallies as doubles for the caller (engine, conformance, benchmarks): the values of `exact`,
// written by Mover::stream after it has added a step to `exact` (so a tally streamed into over
// several steps is their exact sum). The wall tallies and the body force's work are summed exactly
// in fixed point, in units of at most 2^-64 T0 (energy) and 2^-64 sqrt(m T0) (momentum), terms up
// to 2^33 and sums up to 2^62 of those scales (a term beyond, or not finite, makes its sum NaN):
// they do not depend on threads, blocks or ranks. Ranks add their `exact` (ExactStreamingTally +=,
// each FixedPointSum sent as its words()) before one to_values() with the mover's tally_units().
struct StreamingTally {
  static constexpr std::size_t kMaxSpecies = host::kMaxSpecies;
  std::array<BoundaryTally, 2> sides{};
  double acceleration_energy = 0;  // sum of (m_i/2)(v'^2 - v^2) from g during flight
  // A mixture's sides per species: [side * kMaxSpecies + s] (Mover::set_species).
  std::array<BoundaryTally, 2 * kMaxSpecies> species_sides{};
  ExactStreamingTally exact;
  // The doubles from `exact` (the first `species` species of species_sides; 0: none).
  void to_values(const TallyUnits& units, std::size_t species);
};

class Mover {
 public:
  struct Side {
    const Boundary* boundary = nullptr;
    std::string name;  // for messages: "boundaries.y_min (plugin 'diffuse_wall', file:line)"
  };
  // box: Lx, Ly, Lz; g: the summed body acceleration; sides[0] y_min, sides[1] y_max.
  Mover(const double box[3], const Vec3& g, std::array<Side, 2> sides);

  // Streams every particle over dt from time t0, writes cell[] from the final y, and adds to
  // `tally`. With layer_counts (CellGrid::block_counts) it also counts each block's layers, for
  // CellGrid::place_blocks (or sort_counted): the sort then does not read cell[] a second time. ctx is what
  // boundaries see (time, dt, system). Throws std::runtime_error naming the boundary when a plugin
  // returns an impossible state or a particle cannot leave the walls.
  // Blocks of kBlock particles run on the pool's threads (boundaries' interact() concurrently);
  // their tallies, exact in fixed point, are added to tally.exact, then tally's doubles are its values.
  void stream(const ParticleSpan& p, std::uint32_t* cell, std::uint32_t* layer_counts, const CellGrid& grid,
              double t0, double dt, const StepContext& ctx, const StreamFactory& streams, StreamingTally& tally,
              WorkPool* pool = nullptr) const;
  // A mixture: the mass of each of `count` species (nullptr: one species of unit mass). The
  // tallies then weigh every particle by its mass and are kept per species too, and every hit
  // names its species (WallHit::species).
  void set_species(const double* mass, std::size_t count) {
    mass_ = mass;
    species_count_ = mass ? count : 1;
  }
  // The scales of the tallies' fixed-point units: the temperature T0 and the mass m (default 1, 1).
  void set_tally_units(double temperature, double mass) { units_ = TallyUnits::of(temperature, mass); }
  const TallyUnits& tally_units() const { return units_; }
  static constexpr std::size_t kBlock = CellGrid::kSortBlock;  // a block's layer counts are a sort block's

  static constexpr int max_hits_per_step = 100000;
  static constexpr std::size_t kHitBuffer = 256;  // wall-bound particles held back, then flown

 private:
  // layer_of: CellGrid::LayerIndex (equal widths) or CellGrid::TableIndex (edges), by value so
  // that the loop keeps it in registers.
  template <bool Accelerated, class LayerOf>
  void stream_block(const ParticleSpan& p, std::uint32_t* cell, std::uint32_t* counts, LayerOf layer_of,
                    std::size_t layers, std::size_t begin, std::size_t end, double t0, double dt, const StepContext& ctx,
                    const StreamFactory& streams, ExactStreamingTally& tally) const;
  // The flight of one particle that leaves [-Ly/2, Ly/2] during the step, hit by hit.
  void fly_with_hits(const ParticleSpan& p, std::size_t i, double t0, double dt, const StepContext& ctx,
                     const StreamFactory& streams, ExactStreamingTally& tally) const;
  double lx_, ly_, lz_, half_;
  Vec3 g_;
  std::array<Side, 2> sides_;
  const double* mass_ = nullptr;
  std::size_t species_count_ = 1;
  TallyUnits units_ = TallyUnits::of(1.0, 1.0);
  mutable std::vector<ExactStreamingTally> blocks_;  // per block, this step
};

// The first time t in (0, t_max] at which y0 + v t + g t^2/2 reaches `plane`, or a negative value
// if it does not within t_max. A start exactly on the plane does not count as a crossing at t = 0.
double first_crossing(double y0, double v, double g, double plane, double t_max);

}  // namespace gdsmc::host
