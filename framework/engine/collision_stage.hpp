// The collision stage of one step, the host's DSMC scheme: every cell with its own majorant w_I,
// candidate remainder and random streams (000 Eq. 4.13), so the cells are independent and their processing order does not
// change any result. The engine, the conformance harness and the benchmark all drive collisions
// through this one class.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include <gdsmc/plugin.hpp>

#include "config/system_info.hpp"
#include "engine/cells.hpp"
#include "engine/kept_speed_bounds.hpp"
#include "engine/streams.hpp"
#include "engine/work_pool.hpp"

namespace gdsmc::host {

class WeightedLayer;         // engine/weighted_layer.hpp
namespace candidates {
struct BatchScratch;         // engine/candidate_batch.hpp
}
struct WeightedSides;

// How many pairs a cell of N_c particles offers to the candidate count (CellCollision::pairs).
enum class PairCount : std::uint32_t {
  distinct = 0,  // N_c (N_c - 1) / 2: every distinct pair once; unbiased when N_c fluctuates
  squared = 1,   // N_c^2 / 2, as 000 Eq. 4.13 writes it: 1/<N_c> more collisions than Boltzmann
};
inline double pair_count(PairCount scheme, std::uint32_t n) {
  const double d = static_cast<double>(n);
  return scheme == PairCount::squared ? 0.5 * d * d : 0.5 * d * (d - 1.0);
}

// The collision groups of a homogeneous system of N particles: K = ceil(N / size) sub-populations
// of N/K particles each (size 0: one population), drawn afresh every step as strided subsets of
// storage (CollisionStage::make_groups): independent pieces of work whose number does not depend on
// the thread count.
std::size_t subpopulation_count(std::size_t particles, std::size_t size);

// How a layer of a slab, or a homogeneous system of one group, draws its candidate pairs
// (homogeneous sub-populations always draw uniform pairs against the group majorant: their
// particles are scattered over storage, and a pass over them would cost more than the candidates
// it saves).
enum class PairSelection : std::uint32_t {
  uniform = 0,   // every pair alike, against the layer majorant w_I (the class's default)
  weighted = 1,  // hard-sphere form: pairs weighted by the peculiar speeds, kept current through the
                 // step (WeightedLayer, collide_weighted); a pass over the layer every step
  // the pipeline's default: weighted in every slab layer (68-72 % of the candidates accepted in
  // every channel of paper 004 against 11-32 % uniform, for about 6 % of a clustered channel's run
  // time); in a homogeneous system of one group, weighted once its uniform majorant would accept
  // below kUniformAcceptanceFloor (engine/majorant.hpp), uniform before
  automatic = 2,
};
// The bulk bound B_0 of a weighted layer (WeightedLayer) over its members' root-mean-square peculiar
// speed: 2 sqrt(8 / (3 pi)), twice the mean speed of a Maxwellian, whose speeds exceed it with
// probability P(chi_3^2 > 32/pi) = 1.7 % (listed in classes); half of the bulk's envelope events are
// then candidates.
constexpr double kBulkSpeedBound = 1.8426354638471225;  // 2 sqrt(8 / (3 pi))

class CollisionStage {
 public:
  explicit CollisionStage(PairCount scheme = PairCount::distinct);
  ~CollisionStage();
  void set_pair_selection(PairSelection selection) { selection_ = selection; }
  void set_pair_count(PairCount scheme) { scheme_ = scheme; }
  // Particles per sub-population of a homogeneous system (Pipeline::subpopulation; 0, the default
  // here: one population).
  void set_subpopulation(std::size_t size) { subpopulation_ = size; }
  // The threads the groups are spread over (null: the caller alone).
  void set_pool(WorkPool* pool) { pool_ = pool; }
  // A homogeneous system whose velocities only this stage changes between two run() calls (no
  // forcing, no acceleration, no particle added, removed or moved in storage: Engine's
  // moments_follow_collisions_). Its uniform candidates of a hard-sphere rule are then tested
  // first against kept speed bounds (KeptSpeedBounds): the same pairs reach the rule, with the
  // same outcomes, bit for bit, but most rejected ones without a load of their velocities.
  void set_collisions_only(bool on) {
    collisions_only_ = on;
    kept_.invalidate();
  }
  // A mixture (engine/collision_species.cpp): the mass and diameter of each of `count` species in
  // reduced units (nullptr: one species, the scheme above). Every group then draws its candidates
  // per pair of species (a, b), each class with its own majorant ratio and remainder; the species'
  // temperatures of the last moment update (the grid's species_cell_moments, which run() reads) set
  // each class's speed scale, and its uniform candidates are tested against the class majorant; with
  // weighted pairs (run.pair_selection auto or weighted in a slab's layers, weighted in a
  // homogeneous group) each class draws its pairs from the envelopes of its species' peculiar
  // speeds instead (collide_class_weighted). The kept bounds serve one species.
  void set_species(const double* mass, const double* diameter, std::size_t count);
  // At a slab's moment update: every class's ratio from its species' largest peculiar speeds.
  void set_species_majorants(const CellGrid::SpeciesCellMoments* moments, const CellMoments* cells, double temperature);
  // Velocities were written outside the stage (a benchmark's rescaling): the kept bounds are rebuilt.
  void velocities_changed() { kept_.invalidate(); }
  struct Totals {
    std::uint64_t candidates = 0, accepted = 0, majorant_exceeded = 0;
    double energy_change = 0;  // summed in cell order, whatever the processing order
    const double* tallies = nullptr;  // this step's sum of each of the rule's tallies (cell order)
    double max_rate = 0;
    double missed = 0;  // collisions the bounds missed (PairBatch::missed), summed in cell order
    bool finite_remainders = true;
  };
  // A step whose candidate estimate is not finite or beyond kMaxCandidatesPerStep or
  // kMaxCandidatesPerParticle (engine/majorant.hpp): thrown before any pair is tested.
  struct Overload : std::runtime_error {
    Overload(const std::string& what, double candidates) : std::runtime_error(what), candidates(candidates) {}
    double candidates;
  };
  // Majorant ratios back to their initial value and remainders to 0, for `cells` cells.
  void reset(std::size_t cells);  // and the kept speed bounds rebuilt at the next run()
  // A homogeneous system's moment update: each group's majorant ratio decays by kMajorantDecay
  // towards kInitialMajorantRatio (as SPARTA lets its vremax come back down) while the collisions it
  // has missed since the start stay below kMissedCollisionsTolerance of those it made; beyond, it
  // keeps the ratio its exceedances raised (an anisotropic state such as strong shear, whose pairs
  // exceed 7 sqrt(T/m) often), so that the run's missed fraction stays near the tolerance.
  void reset_majorants();
  // Checkpoints: each group's majorant ratio and candidate remainder.
  void save(StateWriter& out) const {
    out.write("collisions.majorant_ratio", ratio_);
    out.write("collisions.remainder", remainder_);
    out.write("collisions.missed_so_far", missed_so_far_);
    out.write("collisions.collided_so_far", collided_so_far_);
    if (species_ > 1) {  // a mixture's classes
      out.write("collisions.class_majorant_ratio", class_ratio_);
      out.write("collisions.class_remainder", class_remainder_);
    }
  }
  void load(StateReader& in) {
    std::vector<double> ratio, remainder, missed, collided;
    in.read("collisions.majorant_ratio", ratio);
    in.read("collisions.remainder", remainder);
    in.read("collisions.missed_so_far", missed);
    in.read("collisions.collided_so_far", collided);
    if (remainder.size() != ratio.size() || missed.size() != ratio.size() || collided.size() != ratio.size() ||
        ratio.empty())
      throw StateError("checkpoint entries 'collisions.*': " + std::to_string(remainder.size()) + ", " +
                       std::to_string(missed.size()) + " and " + std::to_string(collided.size()) +
                       " groups where the majorants have " + std::to_string(ratio.size()));
    reset(ratio.size());
    ratio_ = std::move(ratio);
    remainder_ = std::move(remainder);
    missed_so_far_ = std::move(missed);
    collided_so_far_ = std::move(collided);
    if (species_ > 1) {
      std::vector<double> class_ratio, class_remainder;
      in.read("collisions.class_majorant_ratio", class_ratio);
      in.read("collisions.class_remainder", class_remainder);
      if (class_ratio.size() != class_ratio_.size() || class_remainder.size() != class_remainder_.size())
        throw StateError("checkpoint entries 'collisions.class_*': " + std::to_string(class_ratio.size()) +
                         " pair classes where this mixture has " + std::to_string(class_ratio_.size()));
      class_ratio_ = std::move(class_ratio);
      class_remainder_ = std::move(class_remainder);
    }
  }
  // At a moment update of a slab: ratio_I = max(kInitialMajorantRatio, kMajorantHeadroom 2 c_I /
  // sqrt(T_ref/m)) with c_I the largest peculiar speed in layer I (no two of its particles are
  // further apart than 2 c_I, so none of them exceeds w_I now). Before, the ratios only rose: a hot
  // particle crossing a cold dense layer left its w_I high for the rest of the run (Kn = 0.02,
  // e_n = 0.7: 0.8 % of the candidates accepted after 1500 tau0).
  void set_layer_majorants(const CellMoments* cells, const double* peculiar_speed_max, double temperature, double mass);
  // A decomposed slab (engine/decomposition.hpp): run() sees this rank's layers' members only, and
  // after its collisions every layer's results and state (counts, energy, tallies, remainder,
  // majorant ratio) come from the layer's owner, so that every rank holds the serial totals and
  // the same per-layer state. Null: one process.
  void set_exchange(const LayerExchange* exchange) { exchange_ = exchange; }
  // The candidates each group tested since the last call, summed over the run() calls (a
  // decomposed slab's measure of a layer's collision cost); the sums start again from zero.
  void take_candidates(std::vector<double>& per_group) {
    per_group.assign(candidates_since_.begin(), candidates_since_.end());
    std::fill(candidates_since_.begin(), candidates_since_.end(), 0.0);
  }
  // The number of tallies the rule keeps (CollisionRule::tallies().size()); allocates their buffers.
  void set_tally_count(std::size_t count);
  // The flag run() polls (every 64 cells and between the slices of a large cell); Interrupted
  // (engine/interrupt.hpp) is thrown once it is set. Null: never interrupted.
  void set_interrupt(const std::atomic<bool>* flag) { interrupt_ = flag; }
  // One step of collisions in every group: the layers of a slab `grid`, the sub-populations of a
  // homogeneous one (each with the candidate rate per particle of the whole system: volume
  // V P(N_c) N / (P(N) N_c), P the pair count). w_I = ratio_I sqrt(T_ref / m) with T_ref the
  // layer's own temperature T_I (`cells` null, or a layer of fewer than 2 particles or T_I = 0 at
  // the last moment update: the mean one); a candidate above w_I raises ratio_I
  // (kMajorantHeadroom), and set_layer_majorants re-sets the ratios at every moment update.
  // Group c draws its pairs and acceptance numbers from streams.rng(collisions, 0, c) and hands the
  // rule streams.rng(collisions, 2, c) (PairBatch::rng) at the factory's current step; the
  // rotation of the sub-populations is drawn from streams.rng(collisions, 1, 0).
  // Throws Overload if the step's work is unbounded or absurd; a cell with more candidates than
  // kCandidatesPerSlice is handed to the rule in slices of dt (its remainder and stream carried
  // from slice to slice), so that an interrupt is seen within milliseconds.
  //
  // `pending`: a slab whose member lists are still to be written (CellGrid::place_blocks done,
  // no scatter_block yet). run() then writes them itself, as one list of pieces: block b's
  // scatter, then every layer whose last block is b. The threads take the pieces in that order,
  // and a layer waits for its blocks to be done before it collides. A second thread thus collides
  // (arithmetic in cache) while the first scatters (memory-bound: the scatter gained 1.14x from a
  // second thread, alone). Same members, same streams: the same bits as scattering first.
  struct PendingMembers {
    CellGrid* grid = nullptr;
    const std::uint32_t* cell = nullptr;  // every particle's layer, as the mover wrote it
  };
  Totals run(const CollisionRule& rule, const ParticleSpan& particles, const CellGrid& grid, const CellMoments* cells,
             double temperature, double mass, double sigma, double dt, const StreamFactory& streams,
             bool reversed = false, const PendingMembers* pending = nullptr);

 private:
  PairCount scheme_;
  std::vector<double> ratio_, remainder_, energy_;
  std::size_t tally_count_ = 0;
  std::vector<double> cell_tallies_, step_tallies_;  // [cell * tally_count_ + k], [k]
  std::vector<double> speed_, estimate_;  // this step's sqrt(T_ref/m) and candidate estimate per cell
  std::vector<double> max_rate_, missed_;  // per group, this step
  std::vector<double> missed_so_far_, collided_so_far_;  // per group, since the start of the run
  PairSelection selection_ = PairSelection::uniform;
  const CellMoments* cells_ = nullptr;  // this step's layer moments (run()'s `cells`)
  bool weighted_ = false;  // this step: weighted pairs in the layers
  // T_ref of group c: its own temperature if it had >= 2 particles and T > 0, else `temperature`.
  static double reference_temperature(const CellMoments* cells, std::size_t c, double temperature);
  std::vector<std::uint64_t> counts_;     // per group: candidates, accepted, exceeded
  struct Group {
    const std::uint32_t* members = nullptr;
    std::uint32_t first = 0;
    std::uint64_t stride = 1;
    std::uint32_t count = 0;
    double volume = 0;
  };
  std::vector<Group> groups_;
  std::vector<std::uint32_t> identity_;  // 0 .. N-1: the member list of a homogeneous system of one group
  std::size_t subpopulation_ = 0;
  WorkPool* pool_ = nullptr;
  void make_groups(const CellGrid& grid, std::size_t particles, const StreamFactory& streams);
  // The collisions of group c: its streams, majorant, remainder and slices (run()'s piece).
  void collide_group(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c, double sigma, double dt,
                     const StreamFactory& streams);
  // `candidates` candidate pairs of group c drawn from `select`, handed to the rule in batches
  // (those the kept bounds reject first, when `kept`, never reach it).
  void collide_candidates(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                          std::uint64_t candidates, Rng& select, PairBatch& batch, bool kept);
  KeptSpeedBounds kept_;  // engine/kept_speed_bounds.hpp
  bool collisions_only_ = false, kept_this_step_ = false;
  // The velocity u the envelopes of group c are built about: its cell's mean velocity at the last
  // moment update (any u bounds |g| by c_a + c_b; one near the mean keeps the speeds small), or,
  // below 2 particles there, the mean of the `count` members now.
  void envelope_velocity(const ParticleSpan& particles, std::size_t c, const std::uint32_t* members,
                         std::uint32_t count, double (&u)[3]) const;
  // Group c's step with weighted pairs: its envelope built, then collide_weighted.
  void collide_group_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c, double dt,
                              Rng& select, PairBatch& batch);
  // Group c's step with weighted pairs (a slab layer, the hard-sphere form): returns the time
  // counter's credit at dt.
  double collide_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                          const WeightedSides& sides, double credit, double dt, Rng& select, PairBatch& batch);
  // Its events and candidates drawn from `select` (a copy of the stream, or a BulkRng of it).
  template <class Draws>
  double weighted_step(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                       const WeightedSides& sides, double credit, double dt, Draws& select, PairBatch& batch);
  double solid_angle_ = M_PI;  // Omega_B of the rule's kernel form (pi: hard sphere; 4 pi: general)
  // run() with pending members: the pieces in order (block b < blocks, or blocks + layer), and
  // each block's stamp once it is scattered (the run's number: nothing to clear between steps).
  void scatter_and_collide(const CollisionRule& rule, const ParticleSpan& particles, const PendingMembers& pending,
                           double sigma, double dt, const StreamFactory& streams);
  std::vector<std::uint32_t> pieces_, key_start_, key_next_, by_key_;  // the pieces; layers by last block
  static constexpr std::size_t kScatterLead = 2;  // blocks scattered ahead of the layers that wait for them
  std::unique_ptr<std::atomic<std::uint64_t>[]> scattered_;
  std::size_t scattered_size_ = 0;
  std::uint64_t stamp_ = 0;
  const std::atomic<bool>* interrupt_ = nullptr;
  const LayerExchange* exchange_ = nullptr;
  std::vector<double> shared_;  // per layer: the values share_layers() sends
  std::vector<double> candidates_since_;  // per group: candidates since take_candidates()
  void share_layers(std::size_t layers);
  // A mixture's (collision_species.cpp): species, their masses and diameters, and per group and
  // class (a <= b, in order (0,0), (0,1), ..., (1,1), ...) the majorant ratio w_ab / scale_ab and
  // the candidate remainder.
  std::size_t species_ = 1;
  double species_mass_[kMaxSpecies] = {}, species_diameter_[kMaxSpecies] = {};
  std::vector<double> class_ratio_, class_remainder_;
  const CellGrid::SpeciesCellMoments* species_cells_ = nullptr;
  bool slab_ = false;          // this step's grid
  double temperature_ = 0;     // this step's mean temperature (run()'s `temperature`)
  std::size_t class_count() const { return species_ * (species_ + 1) / 2; }
  double class_scale(std::size_t c, std::size_t a, std::size_t b) const;
  // Group c's hard-sphere candidate estimate for the step, bounded above (every pair at the
  // largest diameter and the largest class majorant): the overload check and the slices.
  double species_estimate(const CollisionRule& rule, std::size_t c, double dt) const;
  void collide_group_species(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c, double dt,
                             Rng& select, PairBatch& batch);
  // Class (a, b), the k-th, of group c, its species' members at sorted[start[s] ..]: uniform
  // candidates against the class majorant (returns how many), or weighted pairs (the envelopes of
  // both species built about one velocity, then weighted_step over them).
  std::uint64_t collide_class_uniform(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c,
                                      std::size_t a, std::size_t b, std::size_t k, const std::uint32_t* sorted,
                                      const std::uint32_t* start, double dt, Rng& select,
                                      candidates::BatchScratch& s, PairBatch& batch);
  // False (nothing done) when a species has no envelope: the class then draws uniform candidates.
  bool collide_class_weighted(const CollisionRule& rule, const ParticleSpan& particles, std::size_t c, std::size_t a,
                              std::size_t b, std::size_t k, const std::uint32_t* sorted, const std::uint32_t* start,
                              double dt, Rng& select, PairBatch& batch);
};

}  // namespace gdsmc::host
