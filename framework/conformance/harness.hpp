// The conformance harness: the engine's own pieces (ParticleStore, CellGrid, StreamFactory, Mover)
// around one plugin object, for direct calls with controlled input. Two shapes: a homogeneous
// population (collision rules, forcings, initial states, diagnostics) with one collision stage of
// the configured rule, and a small slab streamed by the host's Mover with the boundary under test
// on both planes (boundaries), with every hit recorded.
#pragma once
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/physics/moments.hpp>
#include <gdsmc/plugin.hpp>

#include "config/pipeline.hpp"
#include "engine/cells.hpp"
#include "engine/collision_stage.hpp"
#include "engine/majorant.hpp"
#include "engine/particle_store.hpp"
#include "engine/streaming.hpp"
#include "engine/streams.hpp"

namespace gdsmc::host::conformance {

struct Snapshot {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::vector<double>> attributes;
};

// Particles in the host's storage (with the identities and cells SDK 2.0 spans carry).
struct Particles {
  ParticleStore store;

  // positions: as the engine allocates them (a slab only), so that a plugin which writes positions
  // in a homogeneous system fails here as it would in a run.
  void allocate(std::size_t n, const std::vector<AttributeSpec>& attributes, bool positions = true) {
    store.allocate(n, attributes, positions);
  }
  ParticleSpan span() { return store.span(); }
  std::uint32_t* cells() { return store.cells(); }
  std::vector<std::uint32_t> ids() { return {store.ids(), store.ids() + store.size()}; }
  Snapshot save();
  // Restore a snapshot; with `perm`, particle k of the span is particle perm[k] of the snapshot
  // (identity included, so per-particle streams follow the particle).
  void restore(const Snapshot& s, const std::vector<std::uint32_t>* perm = nullptr);
};

struct Harness {
  std::unique_ptr<Pipeline> pipeline;
  const PluginUse* use = nullptr;
  std::shared_ptr<PluginObject> initial, collision, subject;
  std::vector<AttributeSpec> attributes;
  SystemInfo sys;
  QuantityBoard board;
  CellGrid grid;
  std::vector<CellMoments> cells;
  CellMoments global;
  SampledMoments moments;
  StreamFactory factory;
  Streams plugin_streams;  // what ctx.streams points to
  StepContext ctx;
  Particles particles;
  std::array<BoundaryTally, 2> tallies{};  // a slab's (zero) boundary tallies
  CollisionStage stage;                    // per-cell majorants, remainders and streams, as the engine

  ParticleSpan span() { return particles.span(); }
  // The per-cell and global moments of the current state (StepContext::cells / global).
  void update_moments() { grid.cell_moments(span(), sys.number_density, cells, global); }
  // The shared sampled moments (StepContext::moments) of the current state: the MomentsPart
  // `parts`, the others NaN, as the engine measures them.
  void sample_moments(std::uint32_t parts = moments_known) {
    grid.sampled_moments(span(), sys.number_density, moments, nullptr, nullptr, parts);
    ctx.moments = &moments;
  }
  // Key the streams to ctx.step and hand the plugin of `purpose` its streams through ctx.streams.
  void plugin_streams_for(StreamPurpose purpose, const StreamFactory* other = nullptr) {
    StreamFactory f = other ? *other : factory;
    f.set_step(ctx.step);
    plugin_streams = f.streams(purpose, 0);
    ctx.streams = &plugin_streams;
  }
  // A host stream (the harness's own draws) at the current step.
  Rng host_rng(std::uint64_t unit) {
    factory.set_step(ctx.step);
    return factory.rng(StreamPurpose::host, 0, unit);
  }
  std::shared_ptr<PluginObject> fresh_subject() const;

  Snapshot save() { return particles.save(); }
  void restore(const Snapshot& s, const std::vector<std::uint32_t>* perm = nullptr) {
    particles.restore(s, perm);
    grid.assign_and_sort(span().y.data, particles.cells(), span().count);  // cells follow the particles
    update_moments();
  }
  // Attributes that the initial state left at zero get random values (so that rules and
  // diagnostics that use them see something to work on).
  void randomize_zero_attributes(Rng& rng);
  // One collision stage of the filler (or tested) collision rule in every cell (the whole
  // population, or each layer of a slab; particles do not move), on the cells' collision streams
  // of the current step; `sigma` overrides the system's diameter. Returns the cells' sums.
  CollisionStage::Totals collide(double dt, double sigma = 0);
};

// A boundary under test, wrapped so that every hit it serves is recorded (the Mover does not
// show the plugin's returned position.y: it puts the particle on the plane itself).
struct HitRecord {
  WallHit in, out;
  HitResult result = HitResult::reflected;
};
class RecordingBoundary final : public Boundary {
 public:
  explicit RecordingBoundary(const Boundary* inner) : inner_(inner) {}
  bool transfers() const override { return inner_->transfers(); }
  HitResult interact(const StepContext& ctx, WallHit& hit, Rng& rng) const override {
    HitRecord r;
    r.in = hit;
    r.result = inner_->interact(ctx, hit, rng);
    r.out = hit;
    if (record) log.push_back(r);
    return r.result;
  }
  bool record = true;
  mutable std::vector<HitRecord> log;

 private:
  const Boundary* inner_;
};

// A small slab (Lx = Ly = Lz = 1, 10 layers) with a Maxwellian at T = 1, the boundary under test
// on both planes, streamed by the host's Mover.
struct SlabHarness {
  static constexpr double kEdge = 1.0;
  static constexpr double kTemperature = 1.0;
  std::unique_ptr<Pipeline> pipeline;
  const PluginUse* use = nullptr;
  std::shared_ptr<PluginObject> object;
  Boundary* boundary = nullptr;
  std::unique_ptr<RecordingBoundary> recorder;
  QuantityBoard board;
  SystemInfo sys;
  StepContext ctx;
  CellGrid grid;
  StreamFactory factory;
  Particles particles;
  StreamingTally tally;
  std::string refusal;  // begin() refused the system (a ParameterError): the message
  // Threads inside the run (the threads check): the mover's blocks on this pool, and the plugin
  // called directly (the recorder keeps one list of hits, for one thread).
  WorkPool* pool = nullptr;

  ParticleSpan span() { return particles.span(); }
  std::string side_name(int side) const;
  // `steps` steps of dt from the current time; throws what the Mover throws.
  void stream(int steps, double dt);
  double time = 0;
  std::uint64_t step = 0;
};

}  // namespace gdsmc::host::conformance
