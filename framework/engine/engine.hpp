// The DSMC step loop. Knows particles, cells, clocks and random streams; all physics lives in
// the plugins it calls.
#pragma once
#include <array>
#include <atomic>
#include <optional>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/physics/moments.hpp>
#include <gdsmc/plugin.hpp>

#include "config/pipeline.hpp"
#include "engine/adaptive_layers.hpp"
#include "engine/call_sites.hpp"
#include "engine/cells.hpp"
#include "engine/checked_plugins.hpp"
#include "engine/collision_stage.hpp"
#include "engine/decomposition.hpp"
#include "engine/diagnostic_slots.hpp"
#include "engine/interrupt.hpp"
#include "engine/particle_store.hpp"
#include "engine/run_tallies.hpp"
#include "engine/stage_clock.hpp"
#include "engine/streaming.hpp"
#include "engine/streams.hpp"
#include "engine/work_pool.hpp"
#include "output/diagnostic_output.hpp"
#include "output/particle_dump.hpp"
#include "output/records.hpp"

namespace gdsmc::host {

// Progress of a run, handed to the reporter about every `interval` seconds.
struct Progress {
  double fraction = 0;          // of the stop condition reached, in [0, 1]
  double time_tau0 = 0;
  double collisions_per_particle = 0;
  double temperature_over_T0 = 0;
  double elapsed_seconds = 0;
  double remaining_seconds = -1;  // estimate; < 0 when unknown
  std::uint64_t steps = 0;
  bool final = false;             // the report after the last step of the run
};

// The most energy a forcing may add in one step, in units of the gas's thermal energy 3/2 N T:
// above it the run is refused at that step, naming the forcing and the factor.
inline constexpr double kMaxForcingEnergyPerStep = 100;

class Engine;

// When a run writes its state (Engine::save) through `write`: every `every_seconds` of wall time
// and every `every_collisions_per_particle`, at a step boundary (0: not by that clock); at an
// interrupt, before Interrupted is thrown; and once finished.
struct CheckpointSchedule {
  double every_seconds = 0;
  double every_collisions_per_particle = 0;
  std::function<void(const Engine&)> write;
};

class Engine {
 public:
  // Builds every plugin object, allocates and fills the particles, lets diagnostics declare
  // their output. Throws std::runtime_error naming the plugin on any failure.
  // `threads`: the threads this run's stages are spread over (1: the caller alone; a system too
  // small to share, below two sub-populations or four mover blocks, uses 1). The output does not
  // depend on it.
  // The engine keeps a reference to `pipeline` (its plugins' libraries, parameters and
  // diagnostics): the pipeline must outlive the engine, so a temporary one is refused.
  explicit Engine(const Pipeline& pipeline, std::uint32_t realization = 0, unsigned threads = 1);
  explicit Engine(const Pipeline&& pipeline, std::uint32_t realization = 0, unsigned threads = 1) = delete;

  // What `gdsmc validate` checks: every plugin object constructs, declares its attributes,
  // publishes its quantities and (diagnostics) begins, for the pipeline's system; no particle
  // is allocated and no initial state is generated. Throws like the constructor. Returns what the
  // diagnostics wrote as they began (constant metadata: model numbers, theory values).
  static std::vector<DiagnosticOutput> check_setup(const Pipeline& pipeline);
  // A run continued from a checkpoint: set up as the constructor above, but with the state that
  // save() wrote instead of the initial state. Throws StateError on a state that does not fit.
  Engine(const Pipeline& pipeline, std::uint32_t realization, unsigned threads, StateReader& state);
  Engine(const Pipeline&& pipeline, std::uint32_t realization, unsigned threads, StateReader& state) = delete;
  // Everything the rest of the run depends on (particles, clocks, majorants, tallies, records,
  // every plugin's save_state): an engine restored from it continues with the same bits.
  void save(StateWriter& out) const;
  // The first entries of a state that save() wrote: whether the run had finished, its step, and
  // its clocks (time in reduced units, dt, collision energy change, initial energy). Reads only
  // those entries (load() begins with it).
  struct SavedProgress {
    bool finished = false;
    std::uint64_t step = 0;
    double clocks[5] = {0, 0, 0, 0, 0};  // t, dt, collision energy, E0, collision energy at the last moment update
  };
  static SavedProgress saved_progress(StateReader& in);

  // Steps until the stop condition (or until *interrupt becomes true, then throws Interrupted: the
  // flag is also polled inside the collision stage, so a step of any size stops promptly).
  // With `checkpoints`, the state is written as the schedule says, and an interrupt is only
  // honoured between steps (after writing it). A finished run (restored) returns at once.
  void run(const std::function<void(const Progress&)>& report = {}, double report_interval_seconds = 1.0,
           const std::atomic<bool>* interrupt = nullptr, const CheckpointSchedule* checkpoints = nullptr);
  bool is_finished() const { return finished_; }
  // One step (exposed for tests and benchmarks).
  void step();
  // Reorder the particles in storage layer by layer (slab; done every kReorderEvery steps): each
  // layer becomes a contiguous range, so the collision stage touches compact memory.
  void reorder_by_layer();
  static constexpr std::uint64_t kReorderEvery = 16;
  // Process the collision cells in reverse order (tests: no result may depend on the order).
  void set_cells_reversed(bool reversed) { cells_reversed_ = reversed; }

  // This run's results (diagnostics copied), without the file-level provenance; with
  // output.particles, the final particles handed to `stage` (written into the output file) or,
  // without one, copied.
  CaseOutput output(const ParticleStager* stage = nullptr);
  bool reached_steady_state() const { return steady_; }
  const std::vector<std::string>& summary() const { return summary_; }
  const std::vector<DiagnosticOutput>& diagnostics() const { return diagnostics_.outputs(); }
  ParticleSpan particles() { return store_.span(); }
  const StepContext& context() const { return ctx_; }
  const SystemInfo& system() const { return system_; }
  double wall_seconds() const { return wall_seconds_; }
  // Where the steps' wall time went, stage by stage (engine/stage_clock.hpp): seconds over every
  // step, summed over the segments of a resumed run like wall_seconds; a stage the system does not
  // have stays 0.
  const StageSeconds& stage_seconds() const { return clock_.seconds(); }
  double stage_seconds(Stage s) const { return clock_.seconds()[static_cast<std::size_t>(s)]; }

  using Interrupted = host::Interrupted;

  // This slab run, set up (constructed or restored) on every rank of `ranks` alike, continues as
  // one run decomposed over them (engine/decomposition.hpp, engine/engine_ranks.cpp): each rank
  // keeps the particles of its block of layers. Every rank then calls run() (and output() on rank
  // 0); the output and the checkpoints rank 0 writes have the bits of the single-process run.
  // Throws std::runtime_error naming what a decomposed run does not serve yet (a homogeneous system,
  // plugin attributes, more ranks than layers).
  void decompose(Decomposition& ranks);
  // Why `pipeline` cannot be decomposed over `ranks` ranks ("--decompose: ...", the refusal's
  // message), or "" when it can (what decompose() refuses but for plugin attributes, which need the
  // plugin objects): before anything runs.
  static std::string why_not_decomposed(const Pipeline& pipeline, int ranks);
  bool decomposed() const { return ranks_ != nullptr; }
  // Of a decomposed run: particles that changed rank after streaming, summed over the steps and
  // the ranks, and the steps counted; the rebalancings of the blocks; the blocks now.
  struct DecompositionStats {
    std::uint64_t migrated = 0, steps = 0, rebalanced = 0;
    std::vector<std::uint32_t> bounds;
    // This rank's wall seconds in the migrations (collectives included: the wait for the slowest
    // rank's flight shows here) and in gathering the particles for rank 0.
    double migration_seconds = 0, gather_seconds = 0;
    // The gathers of every particle to rank 0: for the diagnostics that read particles (none for
    // those that read only ctx, MomentsRead::particles), forcings, checkpoints and the end.
    std::uint64_t gathers = 0;
  };
  DecompositionStats decomposition_stats() const;

 private:
  enum class Setup { full, objects_only, restore };
  Engine(const Pipeline& pipeline, std::uint32_t realization, Setup setup, unsigned threads,
         StateReader* state = nullptr);
  void load(StateReader& in);
  void load_moments(StateReader& in);
  // The stages of construction, in order.
  void build_objects();
  void refuse_one_species_plugins();
  void publish(const std::vector<AttributeSpec>& attributes, Setup setup);
  void generate_initial_state();
  void shuffle_subpopulations();
  void begin_diagnostics();

  void set_layers_from_profile();
  void begin_collision_rule();
  void check_boundaries();
  void update_moments();
  void set_layer_majorants();
  void write_species(CaseOutput& out) const;
  void permute_by_layer();
  void measure_sampled_moments();
  // A decomposed slab's sampled step needs no gather of the particles to rank 0 when no diagnostic
  // due reads them (`particles_due`) and the moments it shares are one species' (engine_ranks.cpp).
  bool samples_locally(bool particles_due) const { return !particles_due && !species_mass(); }
  // The particles the diagnostics are handed: none in a decomposed slab (samples_locally).
  ParticleSpan diagnostic_span() { return ranks_ ? ParticleSpan{} : store_.span(); }
  double time_step() const;
  void apply_forcings(const std::vector<std::pair<Forcing*, std::uint32_t>>& forcings);
  void stream(double dt);
  void sort_into_layers();
  void kick(double dt);
  void collide(double dt);
  void sample_and_record(bool force_record);
  void finish_diagnostics();
  void write_checkpoint_state(const CheckpointSchedule& checkpoints);
  // The bracketed diagnostics' samples just before or just after the collision stage (SamplePhase).
  void sample_bracketed(SamplePhase phase);
  std::string energy_balance_text();
  Progress progress(double elapsed_seconds) const;
  void check_streaming_tally(const StreamingTally& tally) const;  // stops the run on a NaN tally
  std::string now_text() const;  // "at step k (t = ... tau0, T/T0 = ...)", for errors during the run

  const Pipeline& pipeline_;
  // The collision rule as the collision stage calls it (marked, its velocities checked), and the
  // boundaries as the mover calls them (marked).
  CheckedCollisionRule checked_collision_;
  std::array<GuardedBoundary, 2> guarded_boundaries_;
  // A non-finite velocity or energy: which plugin, or which could have, produced it.
  [[noreturn]] void non_finite(const std::string& what) const;
  // What the host checked and what is left, for a bad velocity found after the plugins' calls: in
  // storage (temperature = false) or as the temperature of the moment update (true).
  std::string velocity_culprits(bool temperature) const;
  WorkPool pool_;
  SystemInfo system_;
  // A mixture's mass of each species (SystemInfo::species_mass); empty with one species, whose
  // host arithmetic then stays that of unit mass.
  std::vector<double> species_mass_;
  const double* species_mass() const { return species_mass_.empty() ? nullptr : species_mass_.data(); }
  ParticleStore store_;
  QuantityBoard board_;
  StepContext ctx_;
  // For the fatal-signal handler (engine/plugin_calls.hpp): one site per plugin entry
  // (after ctx_: they point at its step).
  CallSites sites_;
  const PluginCallSite& site_of(const PluginUse& use) const { return sites_.of(use); }
  StreamFactory streams_;
  CellGrid grid_;
  std::vector<CellMoments> cells_;  // per-cell moments as of the last update (ctx.cells)
  CellMoments global_;
  SampledMoments sampled_;
  std::uint64_t sampled_step_ = static_cast<std::uint64_t>(-1);  // the step sampled_ was measured at
  std::uint32_t sampled_parts_ = 0;                               // and its MomentsPart bits
  bool sampled_fresh() const { return sampled_step_ == ctx_.step && (moments_parts_ & ~sampled_parts_) == 0; }
  std::uint32_t moments_parts_ = moments_all;  // the MomentsPart bits sampled_ measures (begin_diagnostics)
  // A homogeneous system without forcings: only collisions change velocities, so between passes
  // the mean stays and T follows their declared energy (update_moments).
  bool moments_follow_collisions_ = false;
  double energy_at_update_ = 0;  // ctx.collision_energy_change at the last moment update
  std::vector<std::shared_ptr<PluginObject>> objects_;  // keeps every plugin object (and library) alive
  std::vector<const PluginUse*> object_uses_;           // what made each of objects_
  InitialState* initial_state_ = nullptr;
  CollisionRule* collision_ = nullptr;
  std::vector<std::pair<Forcing*, std::uint32_t>> forcings_before_, forcings_after_;
  std::vector<std::uint32_t> accelerations_;  // forcings that declare a constant acceleration
  Vec3 acceleration_{0, 0, 0};
  std::array<Boundary*, 2> boundaries_{nullptr, nullptr};
  std::optional<Mover> mover_;
  WallTallies walls_;
  CollisionTallies collision_tallies_;
  EnergyLedger ledger_;
  double initial_energy_ = 0;
  // Collisions the majorants missed since the start (CollisionStage::Totals::missed): candidates
  // whose rate exceeded their bound were accepted once where their rate asked for more.
  double missed_collisions_ = 0;
  DiagnosticSlots diagnostics_;
  std::vector<std::string> summary_;
  CollisionStage collisions_;            // per-cell majorants, remainders and streams
  std::vector<double> kick_energy_;      // per block: a homogeneous body acceleration's work this step
  double wall_seconds_ = 0;
  StageClock clock_;
  void lap(Stage s) { clock_.lap(s); }
  bool steady_ = false;
  bool finished_ = false;  // run() completed: finish() called, nothing left to step
  bool cells_reversed_ = false;
  // This step, the slab's member lists are placed by stream() and written by the collision stage
  // (every step but those that reorder storage, which need the lists first, and those whose
  // bracketed diagnostics sample before the collisions: the sampled moments read the lists).
  bool reorders_now() const { return ctx_.step % kReorderEvery == 0; }
  bool members_written_by_collisions() const {
    return mover_ && !ranks_ && !reorders_now() &&
           !(diagnostics_.any_bracketed() && diagnostics_.bracketed_due_at(ctx_.step + 1));
  }
  AdaptiveLayers layers_;  // system.layers: {mean_free_paths, after}

  // A decomposed slab (engine_ranks.cpp): the ranks, this rank's migrants, and on rank 0 the
  // particles gathered into key order (whole_, the single-process run's storage) with their grid.
  Decomposition* ranks_ = nullptr;
  ParticleStore whole_;
  CellGrid whole_grid_;
  std::vector<std::vector<Migrant>> outgoing_;
  std::vector<Migrant> incoming_, packed_, gathered_;
  std::vector<std::size_t> gathered_counts_;
  std::vector<double> layer_values_;
  mutable std::vector<std::uint64_t> merged_words_;  // every rank's exact tallies (merge_tally)
  std::uint64_t migrated_ = 0, migration_steps_ = 0, rebalanced_ = 0;
  double migration_seconds_ = 0, gather_seconds_ = 0;
  std::uint64_t gathers_ = 0;
  void sort_members_by_key();
  // The end of the transient of system.layers: rank 0 sets the edges from its profile on the
  // gathered particles and reorders them (as the single-process run does); every rank then takes
  // the edges, new blocks and its new layers' particles.
  void set_layers_decomposed();
  void set_bounds(const std::vector<double>& cost);
  void keep_own_layers();
  void migrate(bool count = true);  // count: into the migration statistics (not a rebalancing's)
  void merge_tally(StreamingTally& tally) const;
  void renumber_keys();
  void rebalance();
  std::vector<double> layer_costs();  // right after renumber_keys (rebalance)
  // Rank 0: every rank's particles in whole_, in key order, its grid sorted (every rank calls it).
  void gather_whole();
  // After gather_whole, rank 0 runs f as the single-process run would: whole_ and its grid as the
  // store and the grid, and no ranks.
  template <class F>
  void on_whole_serial(F&& f) {
    Decomposition* ranks = ranks_;
    const auto swap_in = [&] {
      std::swap(store_, whole_);
      std::swap(grid_, whole_grid_);
    };
    swap_in();
    ranks_ = nullptr;
    try {
      f();
    } catch (...) {
      ranks_ = ranks;
      swap_in();
      throw;
    }
    ranks_ = ranks;
    swap_in();
  }
  // After a stage rank 0 ran on whole_ that changed velocities (forcings): every rank's back.
  void return_whole();
  // Every rank's flags (interrupt, checkpoint due) or'ed, on every rank.
  bool any_rank(bool flag) const;
  // Rank 0's `value` on every rank: what rank 0 alone knows (the steady flag, whether the diagnostics
  // it drives will read the particles).
  bool root_says(bool value) const;
};

}  // namespace gdsmc::host
