#include "engine/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "engine/majorant.hpp"
#include "engine/memory_estimate.hpp"
#include "engine/stop.hpp"
#include "output/particle_dump.hpp"
#include "output/provenance.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {
// The threads a run's stages are spread over: `threads` when there is enough independent work,
// else 1. Handing a stage to a second thread costs some microseconds per stage, as much as the
// whole stage of a small system: at N = 1e4 two threads ran a homogeneous HCS at 5.3 M collisions/s
// against 7.0 M on one (one sub-population: nothing to share but the moment sums) and a slab at
// 40 M moves/s against 52 M. So: a homogeneous system with at least two sub-populations, a slab of at
// least 16384 particles (one mover block; its layers are shared too). The output does not depend on it.
unsigned run_threads(const Pipeline& p, unsigned threads) {
  if (threads <= 1) return 1;
  const bool enough = p.geometry == Geometry::slab ? p.particles >= Mover::kBlock
                                                   : subpopulation_count(p.particles, p.subpopulation) >= 2;
  return enough ? threads : 1;
}
std::string params_text(const PluginUse& u) {
  std::string t;
  for (const auto& [k, e] : u.params.entries()) t += k + "=" + value_text(e.value) + ";";
  return t;
}
}  // namespace

Engine::Engine(const Pipeline& p, std::uint32_t realization, unsigned threads)
    : Engine(p, realization, Setup::full, threads) {}

Engine::Engine(const Pipeline& p, std::uint32_t realization, unsigned threads, StateReader& state)
    : Engine(p, realization, Setup::restore, threads, &state) {}

std::vector<DiagnosticOutput> Engine::check_setup(const Pipeline& p) {
  Engine check(p, 0, Setup::objects_only, 1);
  return std::move(check.outputs_);
}

Engine::Engine(const Pipeline& p, std::uint32_t realization, Setup setup, unsigned threads, StateReader* state)
    : pipeline_(p), pool_(run_threads(p, threads)), sites_(p, &ctx_.step), streams_(p.seed, realization) {
  system_ = p.system_info(p.particles, realization);
  layers_.open(p, system_);
  build_objects();
  std::vector<AttributeSpec> attributes;
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    PluginCall call(site_of(*object_uses_[k]), "attributes");
    for (auto& a : objects_[k]->attributes()) attributes.push_back(std::move(a));
  }
  publish(attributes, setup == Setup::objects_only ? Setup::objects_only : Setup::full);
  begin_collision_rule();
  ctx_.system = &system_;
  ctx_.quantities = &board_;
  ctx_.body_acceleration = acceleration_;
  check_boundaries();
  {
    std::vector<std::string> forcings;
    for (const auto& u : p.forcings) forcings.push_back(u.instance_name);
    ledger_.open(forcings, system_.geometry == Geometry::slab);
  }
  const std::size_t cells = system_.cells;
  collisions_.reset(cells);
  collisions_.set_pair_count(p.candidate_pairs_squared ? PairCount::squared : PairCount::distinct);
  collisions_.set_pair_selection(p.pair_selection == 0   ? PairSelection::uniform
                                 : p.pair_selection == 1 ? PairSelection::weighted
                                                         : PairSelection::automatic);
  collisions_.set_tally_count(collision_tallies_.size());
  collisions_.set_subpopulation(p.subpopulation);
  collisions_.set_pool(&pool_);
  cells_.assign(cells, CellMoments{});
  moments_follow_collisions_ = system_.geometry != Geometry::slab && forcings_before_.empty() &&
                               forcings_after_.empty() && accelerations_.empty();
  collisions_.set_collisions_only(moments_follow_collisions_);
  if (setup != Setup::objects_only) {
    if (system_.geometry == Geometry::slab) {
      grid_.slab(system_.particles, cells, system_.box[1], system_.cross_section());
      if (layers_.enabled()) grid_.set_edges(layers_.edges());
    } else {
      grid_.homogeneous(system_.particles, system_.volume);
    }
    checked_collision_.bind(store_.span());
    if (setup == Setup::full) generate_initial_state();
  }
  ctx_.cells = cells_.data();
  ctx_.cell_count = cells_.size();
  ctx_.global = &global_;
  ctx_.boundaries = walls_.data();
  ctx_.boundary_count = system_.geometry == Geometry::slab ? 2 : 0;
  ctx_.energy_ledger = ledger_.data();
  ctx_.energy_ledger_size = ledger_.size();
  ctx_.collision_tallies = collision_tallies_.data();
  ctx_.collision_tally_count = collision_tallies_.size();
  begin_diagnostics();
  report_layout(attributes, outputs_);  // what the memory estimate counts (validate)
  if (setup == Setup::full) sample_and_record(true);  // the initial state is the first record of every diagnostic
  if (setup == Setup::restore) load(*state);
}

// The end of the transient: the edges from the density profile, and then frozen.
void Engine::set_layers_from_profile() {
  layers_.sample_profile(store_.span());  // the state at the end of the transient is one sample (the only one of a short one)
  std::vector<double> edges = layers_.edges_from_profile();
  try {
    grid_.set_edges(edges);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(now_text() + ": system.layers: the layers sized from the density profile cannot be used: " +
                             e.what());
  }
  const std::string line = layers_.adopt(std::move(edges), ctx_.time_in_tau0());
  // Every particle into its new layer, storage in the new layer order, and the new layers' moments
  // and majorants now (forcings and diagnostics read ctx.cells before the next moment update).
  reorder_by_layer();
  grid_.cell_moments(store_.span(), system_.number_density, cells_, global_, &pool_);
  collisions_.set_layer_majorants(cells_.data(), grid_.peculiar_speed_max(), global_.temperature, system_.mass);
  sampled_step_ = static_cast<std::uint64_t>(-1);
  summary_.push_back(line);
  if (system_.realization == 0) std::fprintf(stderr, "%s\n", line.c_str());
}

void Engine::build_objects() {
  const Pipeline& p = pipeline_;
  auto make = [&](const PluginUse& u) -> PluginObject* {
    try {
      PluginCall call(site_of(u), "its constructor");
      objects_.push_back(create_object(*u.plugin, u.params));
      object_uses_.push_back(&u);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(u) + " failed to construct: " + e.what());
    }
    return objects_.back().get();
  };
  // The descriptor's kind was checked when the pipeline was loaded, so these casts are exact.
  initial_state_ = static_cast<InitialState*>(make(p.initial_state));
  collision_ = static_cast<CollisionRule*>(make(p.collision));
  for (std::size_t k = 0; k < p.forcings.size(); ++k) {
    auto* f = static_cast<Forcing*>(make(p.forcings[k]));
    Vec3 g{0, 0, 0};
    PluginCall call(site_of(p.forcings[k]), "acceleration");
    if (f->acceleration(g)) {
      accelerations_.push_back(static_cast<std::uint32_t>(k));
      acceleration_ = acceleration_ + g;
      continue;  // integrated by the host during flight, never applied
    }
    (f->stage() == Forcing::Stage::before_streaming ? forcings_before_ : forcings_after_)
        .emplace_back(f, static_cast<std::uint32_t>(k));
  }
  for (std::size_t s = 0; s < p.boundaries.size() && s < 2; ++s) {
    guarded_boundaries_[s].set(static_cast<Boundary*>(make(p.boundaries[s])), &site_of(p.boundaries[s]));
    boundaries_[s] = &guarded_boundaries_[s];
  }
  for (const auto& u : p.diagnostics) slots_.push_back(DiagnosticSlot{static_cast<Diagnostic*>(make(u)), &u, &site_of(u)});
  checked_collision_.set(collision_, &site_of(p.collision));
}

// The collision rule reads what it needs from the system and the published quantities (after
// every publish) and names its tallies.
void Engine::begin_collision_rule() {
  const PluginUse& u = pipeline_.collision;
  try {
    PluginCall call(site_of(u), "begin");
    collision_->begin(system_, board_);
    collision_tallies_.open(collision_->tallies());
  } catch (const ParameterError& e) {
    throw std::runtime_error(where_text(u) + ": parameter '" + e.parameter() + "': " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(where_text(u) + ": " + e.what());
  }
}

// Both y planes of a slab: transferring boundaries (periodic, Lees-Edwards) come in identical
// pairs, and every boundary may refuse the run in begin().
void Engine::check_boundaries() {
  if (system_.geometry != Geometry::slab) return;
  const PluginUse& low = pipeline_.boundaries.at(0);
  const PluginUse& high = pipeline_.boundaries.at(1);
  for (int s = 0; s < 2; ++s) {
    const PluginUse& u = pipeline_.boundaries[s];
    const PluginUse& other = pipeline_.boundaries[1 - s];
    if (boundaries_[s]->transfers() &&
        (u.plugin->descriptor->name != other.plugin->descriptor->name || params_text(u) != params_text(other)))
      throw std::runtime_error(where_text(u) + " transfers particles to the opposite plane, so both y boundaries must be '" +
                               u.plugin->descriptor->name + "' with the same parameters; " + other.path + " is '" +
                               other.plugin->descriptor->name + "'" +
                               (u.plugin->descriptor->name == other.plugin->descriptor->name ? " with other parameters" : "") +
                               " (write boundaries: {y: ...} to give both at once)");
    try {
      boundaries_[s]->begin(system_, board_, acceleration_);
    } catch (const ParameterError& e) {
      throw std::runtime_error(where_text(u) + ": parameter '" + e.parameter() + "': " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(u) + ": " + e.what());
    }
  }
  const std::string names[2] = {"boundaries.y_min (plugin '" + low.plugin->descriptor->name + "', " + low.where.str() + ")",
                                "boundaries.y_max (plugin '" + high.plugin->descriptor->name + "', " + high.where.str() + ")"};
  mover_.emplace(system_.box, acceleration_,
                 std::array<Mover::Side, 2>{Mover::Side{boundaries_[0], names[0]}, Mover::Side{boundaries_[1], names[1]}});
}

// Particles (full setup only) and the attributes, then every object publishes its quantities.
void Engine::publish(const std::vector<AttributeSpec>& attributes, Setup setup) {
  if (setup == Setup::full) store_.allocate(pipeline_.particles, attributes, system_.geometry == Geometry::slab);
  else ParticleStore::check_attributes(attributes);
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    PluginCall call(site_of(*object_uses_[k]), "publish");
    objects_[k]->publish(board_);
  }
}

void Engine::generate_initial_state() {
  const ParticleSpan span = store_.span();
  try {
    PluginCall call(site_of(pipeline_.initial_state), "generate");
    initial_state_->generate(system_, board_, span, streams_.streams(StreamPurpose::initial_state, 0));
  } catch (const ParameterError& e) {
    throw std::runtime_error(where_text(pipeline_.initial_state) + ": parameter '" + e.parameter() + "': " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(where_text(pipeline_.initial_state) + ": " + e.what());
  }
  if (system_.geometry == Geometry::slab) {
    const double h = 0.5 * system_.box[1];
    for (std::size_t i = 0; i < span.count; ++i)
      if (!(span.y[i] >= -h && span.y[i] <= h) || !(span.x[i] >= 0 && span.x[i] < system_.box[0]) ||
          !(span.z[i] >= 0 && span.z[i] < system_.box[2]))
        throw std::runtime_error(where_text(pipeline_.initial_state) + " placed particle " + std::to_string(i) +
                                 " at (" + std::to_string(span.x[i]) + ", " + std::to_string(span.y[i]) + ", " +
                                 std::to_string(span.z[i]) + "), outside the slab [0, Lx) x [-Ly/2, Ly/2] x [0, Lz)");
  }
  if (system_.geometry == Geometry::slab) grid_.assign_and_sort(span.y.data, store_.cells(), span.count);
  else shuffle_subpopulations();
  grid_.cell_moments(span, system_.number_density, cells_, global_, &pool_);
  grid_.sampled_moments(span, system_.number_density, sampled_, &pool_);
  sampled_step_ = ctx_.step;
  initial_energy_ = sampled_.kinetic_energy;
  if (!(global_.temperature > 0) || !std::isfinite(global_.temperature))
    throw std::runtime_error(where_text(pipeline_.initial_state) + " produced a state with temperature " +
                             fmt("%.6g", global_.temperature) + "; a positive finite temperature is needed");
}

// The sub-populations of a homogeneous system are strided subsets of storage (CollisionStage): put
// the particles in a random order first, so that no order the initial state made (say, hot
// particles first, or alternating) can line up with a stride. Fisher-Yates on the stored particles (no
// scratch memory), identities travelling with them.
void Engine::shuffle_subpopulations() {
  const std::size_t n = store_.size();
  if (subpopulation_count(n, pipeline_.subpopulation) < 2) return;
  Rng rng = streams_.rng(StreamPurpose::initial_state, 1, 0);
  for (std::size_t i = n - 1; i > 0; --i) {
    const std::size_t j = rng.below(static_cast<std::uint32_t>(i + 1));
    if (j != i) store_.swap(i, j);
  }
}

void Engine::begin_diagnostics() {
  const Pipeline& p = pipeline_;
  if (p.stop_steady)
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].use->instance_name == p.stop_steady->group) steady_slot_ = static_cast<int>(k);
  const std::vector<double> centres = bin_centres_lambda0(system_);
  // The parts of the sampled moments that some diagnostic reads (MomentsRead); the host's own use
  // of them (update_moments) when only the collisions change the velocities.
  moments_parts_ = moments_follow_collisions_ ? static_cast<std::uint32_t>(moments_all) : 0u;
  outputs_.reserve(slots_.size());
  for (auto& slot : slots_) {
    outputs_.emplace_back(slot.use->instance_name, &summary_);
    outputs_.back().set_bins(centres);
    try {
      PluginCall call(*slot.site, "begin");
      slot.object->begin(system_, board_, outputs_.back());
      PluginCall query(*slot.site, "extension");
      // With the collisions as the only process (moments_follow_collisions_: the HCS) the state after
      // the step is exact at t + dt and the one before it is the state at t: the sample is taken alone.
      slot.bracketed = p.sampling_bracketed && !moments_follow_collisions_ &&
                       slot.object->extension(bracketed_sampling_id) != nullptr;
      const auto* read = static_cast<const MomentsRead*>(slot.object->extension(moments_read_id));
      moments_parts_ |= read ? read->parts : static_cast<std::uint32_t>(moments_all);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slot.use) + ": " + e.what());
    }
    outputs_.back().attribute("sampling", slot.bracketed ? "bracketed: the state just before and just after the collision stage "
                                                           "of each sampled step, at t + dt (run.sampling)"
                                                         : "after_step: the state after each sampled step");
    any_bracketed_ = any_bracketed_ || slot.bracketed;
  }
}

// Every run.moments_every steps. A homogeneous system without forcings changes its velocities only
// in collisions, which conserve momentum and declare their kinetic-energy change (conformance
// checks both to round-off): its mean stays and T += 2 dE / (3 N) (m = 1; Eq. 4.15 differenced),
// without the pass over every particle (1.3 ms at N = 1e6, a step's collisions 1.6 ms). A step
// that samples measures both afresh, in the one pass it makes anyway; a rule that declares a
// non-finite change (which conformance refuses) gets the pass.
void Engine::update_moments() {
  const double declared = ctx_.collision_energy_change - energy_at_update_;
  energy_at_update_ = ctx_.collision_energy_change;
  if (moments_follow_collisions_ && samples_at(ctx_.step)) {
    measure_sampled_moments();
    for (int a = 0; a < 3; ++a) global_.mean_velocity[a] = sampled_.local.mean[a];
    global_.temperature = sampled_.local.temperature;
    cells_[0] = global_;
  } else if (moments_follow_collisions_ && std::isfinite(declared)) {
    global_.temperature += 2.0 * declared / (3.0 * static_cast<double>(global_.count));
    cells_[0] = global_;
  } else {
    grid_.cell_moments(store_.span(), system_.number_density, cells_, global_, &pool_);
    if (grid_.is_slab())
      collisions_.set_layer_majorants(cells_.data(), grid_.peculiar_speed_max(), global_.temperature, system_.mass);
  }
  if (!grid_.is_slab()) collisions_.reset_majorants();
}

void Engine::measure_sampled_moments() {
  grid_.sampled_moments(store_.span(), system_.number_density, sampled_, &pool_,
                        moments_follow_collisions_ ? global_.mean_velocity : nullptr, moments_parts_);
  sampled_step_ = ctx_.step;
}

// Whether some diagnostic samples or records after step `step`.
bool Engine::samples_at(std::uint64_t step) const {
  return std::any_of(slots_.begin(), slots_.end(), [&](const DiagnosticSlot& slot) { return slot.samples_at(step); });
}

// dt = c tau0, or c tau0 sqrt(T0/T) so that it follows the mean free time (000 Sec. IV.B; in a
// slab T is T-bar, Eq. 4.8, as in Sec. IV.A).
double Engine::time_step() const {
  double dt = pipeline_.time_step_tau0 * system_.time_unit0;
  if (pipeline_.time_step_follows_temperature) dt *= std::sqrt(system_.initial_temperature / global_.temperature);
  return dt;
}

std::string Engine::now_text() const {
  return fmt("at step %llu (t = %.6g tau0, T/T0 = %.3g)", static_cast<unsigned long long>(ctx_.step),
             ctx_.time_in_tau0(), global_.temperature / system_.initial_temperature);
}

void Engine::step() {
  const double dt = time_step();
  // A step that does not move the clock (or moves it by more than can be represented) would repeat
  // forever; one that leaves the stop time out of reach as good as so.
  const char* follows =
      pipeline_.time_step_follows_temperature ? " (dt follows the temperature: run.time_step sqrt(T0/T))" : "";
  if (!(ctx_.time + dt > ctx_.time) || !std::isfinite(dt))
    throw std::runtime_error(now_text() + fmt(": the time step dt = %.3g tau0 no longer advances the clock%s",
                                              dt / system_.time_unit0, follows));
  if (pipeline_.stop_time_tau0 && !pipeline_.stop_collisions_per_particle) {
    const double left = (*pipeline_.stop_time_tau0 - ctx_.time_in_tau0()) * system_.time_unit0 / dt;
    if (left > kMaxSteps)
      throw std::runtime_error(now_text() + fmt(": the stop time %.6g tau0 is %.3g steps of dt = %.3g tau0 away (more "
                                                "than %.0e), so the run would not end%s; use a larger run.time_step or "
                                                "an earlier run.stop.time",
                                                *pipeline_.stop_time_tau0, left, dt / system_.time_unit0, kMaxSteps,
                                                follows));
  }
  ctx_.dt = dt;
  streams_.set_step(ctx_.step);
  const auto& s = ctx_;
  ctx_.in_average_window =
      (pipeline_.average_after_collisions_per_particle && s.collisions_per_particle() >= *pipeline_.average_after_collisions_per_particle) ||
      (pipeline_.average_after_time_tau0 && s.time_in_tau0() >= *pipeline_.average_after_time_tau0);
  clock_.start();
  if (!forcings_before_.empty()) {
    apply_forcings(forcings_before_);
    lap(Stage::forcings);
  }
  stream(dt);
  if (any_bracketed_) {
    sample_bracketed(SamplePhase::before_collisions);
    lap(Stage::diagnostics);
  }
  collide(dt);
  lap(Stage::collisions);
  if (any_bracketed_) {
    sample_bracketed(SamplePhase::after_collisions);
    lap(Stage::diagnostics);
  }
  if (!forcings_after_.empty()) {
    apply_forcings(forcings_after_);
    lap(Stage::forcings);
  }
  ctx_.time += dt;
  ++ctx_.step;
  if (layers_.enabled() && !layers_.set()) {
    const double t = ctx_.time_in_tau0();
    if (layers_.due(t)) {
      set_layers_from_profile();  // with this step's positions, and new moments for the new layers
      lap(Stage::reorder);
    } else if (layers_.profiling(t) && ctx_.step % pipeline_.moments_every == 0) {
      layers_.sample_profile(store_.span());
      lap(Stage::moments);
    }
  }
  if (ctx_.step % pipeline_.moments_every == 0) {
    update_moments();
    if (layers_.set()) layers_.tally(cells_.data());
    lap(Stage::moments);
  }
  sample_and_record(false);
  lap(Stage::diagnostics);
}

void Engine::apply_forcings(const std::vector<std::pair<Forcing*, std::uint32_t>>& forcings) {
  const ParticleSpan span = store_.span();
  for (const auto& [f, index] : forcings) {
    const Streams streams = streams_.streams(StreamPurpose::forcing, index);
    ctx_.streams = &streams;
    double added;
    {
      PluginCall call(site_of(pipeline_.forcings[index]), "apply");
      added = f->apply(ctx_, span);
    }
    if (!std::isfinite(added))
      throw std::runtime_error(where_text(pipeline_.forcings[index]) + " returned a non-finite energy (" +
                               fmt("%g", added) + ") from apply() at step " + std::to_string(ctx_.step) +
                               fmt(" (t = %.6g tau0", ctx_.time_in_tau0()) + (sites_.run_name().empty() ? ")" : ", " + sites_.run_name() + ")") +
                               ": the forcing produced invalid velocities");
    if (const std::size_t i = first_non_finite_velocity(span); i < span.count)
      throw std::runtime_error(where_text(pipeline_.forcings[index]) + " wrote a non-finite velocity" +
                               fmt(" (%g, %g, %g) for particle %u", span.vx[i], span.vy[i], span.vz[i], span.id[i]) +
                               " in apply() at step " + std::to_string(ctx_.step) +
                               fmt(" (t = %.6g tau0", ctx_.time_in_tau0()) + (sites_.run_name().empty() ? ")" : ", " + sites_.run_name() + ")") +
                               "; the run is stopped (a forcing must leave finite velocities)");
    // A forcing that multiplies the gas's thermal energy within one step (a shear rate of 1e6 /
    // tau0 at dt = 0.01 tau0: 3e7 times) makes every later step and diagnostic absurd (a theory
    // diagnostic then integrates its model for ever): refused with the number, one compare a step.
    const double thermal = 1.5 * static_cast<double>(global_.count) * global_.temperature;
    if (added > kMaxForcingEnergyPerStep * thermal && thermal > 0)
      throw std::runtime_error(
          where_text(pipeline_.forcings[index]) +
          fmt(" added %.3g times the gas's thermal energy (3/2 N T = %.3g) in one step", added / thermal, thermal) +
          " at step " + std::to_string(ctx_.step) +
          fmt(" (t = %.6g tau0, dt = %.3g tau0", ctx_.time_in_tau0(), ctx_.dt / system_.time_unit0) +
          (sites_.run_name().empty() ? ")" : ", " + sites_.run_name() + ")") +
          fmt(": more than %.0f times is absurd for one step (the step cannot resolve its heating); use a smaller "
              "run.time_step or a gentler forcing",
              kMaxForcingEnergyPerStep));
    ledger_.add_forcing(index, added);
  }
  ctx_.streams = nullptr;
}

// Free flight with walls and the counting sort into layers (slab), or the velocity kick of a body
// acceleration (homogeneous: no positions to move).
void Engine::stream(double dt) {
  const ParticleSpan span = store_.span();
  const double g2 = dot(acceleration_, acceleration_);
  if (mover_) {
    StreamingTally tally;
    mover_->stream(span, store_.cells(), grid_.block_counts(span.count), grid_, ctx_.time, dt, ctx_, streams_, tally,
                   &pool_);
    lap(Stage::flight);
    // The layers' ranges now; their member lists are written by the collision stage, interleaved
    // with the layers' collisions (CollisionStage::PendingMembers), except before a reordering.
    grid_.place_blocks(span.count);
    if (members_written_by_collisions()) {
      lap(Stage::sort);
    } else {
      grid_.scatter_blocks(store_.cells(), span.count, &pool_);
      lap(Stage::sort);
      permute_by_layer();  // the layers just sorted from the fresh cell[]
      lap(Stage::reorder);
    }
    for (int s = 0; s < 2; ++s) {
      walls_.add(s, tally.sides[s]);
      ledger_.add_wall(s, tally.sides[s].energy);
    }
    if (!accelerations_.empty()) ledger_.add_forcing(accelerations_[0], tally.acceleration_energy);
  } else if (g2 > 0) {
    // Blocks of the moment pieces' size, their energies added in block order.
    const std::size_t block = CellGrid::kMomentBlock, blocks = (span.count + block - 1) / block;
    kick_energy_.resize(blocks);
    for_pieces(&pool_, blocks, [&](std::size_t k) {
      double energy = 0;
      for (std::size_t i = k * block, e = std::min(span.count, i + block); i < e; ++i) {
        energy += (acceleration_.x * span.vx[i] + acceleration_.y * span.vy[i] + acceleration_.z * span.vz[i]) * dt;
        span.vx[i] += acceleration_.x * dt;
        span.vy[i] += acceleration_.y * dt;
        span.vz[i] += acceleration_.z * dt;
      }
      kick_energy_[k] = energy;
    });
    double energy = 0;
    for (const double e : kick_energy_) energy += e;
    ledger_.add_forcing(accelerations_[0], energy + 0.5 * g2 * dt * dt * static_cast<double>(span.count));
    lap(Stage::flight);
  }
}

void Engine::reorder_by_layer() {
  if (!grid_.is_slab()) return;
  const ParticleSpan span = store_.span();
  grid_.assign_and_sort(span.y.data, store_.cells(), span.count);  // from the positions as they are now
  permute_by_layer();
}

// Storage in the order of the current member lists; each layer is then a range of positions.
void Engine::permute_by_layer() {
  store_.permute(grid_.all_members(), &pool_);
  grid_.set_layer_order(store_.cells(), &pool_);
}

// Per-cell collisions (000 Eq. 4.13): in a slab each layer's majorant follows its own temperature
// (re-set at every moment update, update_moments); the cells draw from their own streams, so their
// order does not matter.
void Engine::collide(double dt) {
  CollisionStage::Totals t;
  try {
    const CollisionStage::PendingMembers pending{&grid_, store_.cells()};
    // A homogeneous system of one collision group has the global moments as that group's.
    const bool one_group = !grid_.is_slab() && subpopulation_count(store_.size(), pipeline_.subpopulation) == 1;
    t = collisions_.run(checked_collision_, store_.span(), grid_,
                        grid_.is_slab() ? cells_.data() : one_group ? &global_ : nullptr,
                        global_.temperature, system_.mass, system_.sigma, dt, streams_, cells_reversed_,
                        members_written_by_collisions() ? &pending : nullptr);
  } catch (const CollisionStage::Overload& e) {
    if (checked_collision_.wrote_non_finite()) non_finite("");
    throw std::runtime_error(now_text() + fmt(", with dt = %.3g tau0: ", dt / system_.time_unit0) + e.what() +
                             ": the time step no longer resolves the collisions; use a smaller run.time_step" +
                             (pipeline_.time_step_follows_temperature ? "" : " or run.time_step.follow_temperature: true"));
  }
  // What the rule wrote, checked batch by batch, and what it declared: a non-finite value stops
  // the run here, naming it, whatever else follows from it (diagnostics or none).
  if (checked_collision_.wrote_non_finite() || !std::isfinite(t.energy_change))
    non_finite(fmt("%g", t.energy_change));
  if (checked_collision_.handed_non_finite())
    throw std::runtime_error(now_text() + ": the collision stage found a non-finite velocity in storage: " +
                             velocity_culprits(false));
  ctx_.collisions += t.accepted;
  ctx_.candidates += t.candidates;
  ctx_.majorant_exceeded += t.majorant_exceeded;
  missed_collisions_ += t.missed;
  ctx_.collision_energy_change += t.energy_change;
  ledger_.set_collisions(ctx_.collision_energy_change);
  collision_tallies_.add(t.tallies);
}

// A non-finite velocity or energy found after a stage: named after the plugin that produced it.
// The collision rule's velocities and declared energy are checked every step (collide), a
// forcing's declared energy and velocities after every apply, a boundary's velocities at every
// hit (the mover); what is left (a plugin's save/load, the host itself) shows in the temperature
// of the moment update, every run.moments_every steps (run()).
void Engine::non_finite(const std::string& energy) const {
  const std::string at = fmt(" at step %llu (t = %.6g tau0", static_cast<unsigned long long>(ctx_.step),
                             ctx_.time_in_tau0()) +
                         (sites_.run_name().empty() ? ")" : ", " + sites_.run_name() + ")");
  if (checked_collision_.wrote_non_finite()) {
    const CheckedCollisionRule::Bad b = checked_collision_.first_bad();
    throw std::runtime_error(
        where_text(pipeline_.collision) + " wrote a non-finite velocity" + at +
        fmt(": particles %u and %u (cell %u) left a collision with (%g, %g, %g) and (%g, %g, %g)", b.i, b.j, b.cell,
            b.v1.x, b.v1.y, b.v1.z, b.v2.x, b.v2.y, b.v2.z) +
        "; the run is stopped (a collision rule must return finite velocities: `gdsmc conformance` checks it)");
  }
  throw std::runtime_error(where_text(pipeline_.collision) + " declared a non-finite kinetic-energy change (" + energy +
                           ")" + at + "; the run is stopped (`gdsmc conformance` checks a rule's declared energy)");
}

// What the checks as plugins act leave to the collision stage (a non-finite velocity handed to the
// rule) and to the moment update (a temperature that is not positive and finite): the collision
// rule's velocities are checked as they leave each batch, each forcing's energy and velocities after
// every apply(), each boundary's velocities at every wall hit, the initial state's temperature once.
std::string Engine::velocity_culprits(bool temperature) const {
  std::string text =
      "every velocity was finite where the host checks it (the collision rule's as they leave each batch, each "
      "forcing's after every apply(), each boundary's at every wall hit), so ";
  if (temperature) {
    text += "either finite velocities give this temperature (all equal: 0 up to rounding; beyond about 1e154: an overflow), written by ";
    std::vector<const PluginUse*> writers{&pipeline_.collision};
    for (const auto& f : pipeline_.forcings) writers.push_back(&f);
    for (std::size_t s = 0; s < pipeline_.boundaries.size() && s < 2; ++s) writers.push_back(&pipeline_.boundaries[s]);
    for (std::size_t k = 0; k < writers.size(); ++k)
      text += (k == 0 ? "" : k + 1 == writers.size() ? " or " : ", ") + where_text(*writers[k]);
    text += ", or ";
  }
  return text + "a velocity was written outside those calls (by a plugin through its read-only span or a stray "
                "pointer, or by the host itself)";
}

// One side of the bracketed diagnostics' pair of samples around the collision stage, for those that
// sample after this step: the clock reads t + dt, as it will after the step, and the moments are
// those of the state now (measured afresh for the next use after the collisions).
void Engine::sample_bracketed(SamplePhase phase) {
  const std::uint64_t next = ctx_.step + 1;
  if (std::none_of(slots_.begin(), slots_.end(), [&](const DiagnosticSlot& slot) { return slot.bracketed && slot.samples_at(next); }))
    return;
  const std::uint64_t step = ctx_.step;
  const double time = ctx_.time;
  ctx_.step = next;
  ctx_.time += ctx_.dt;
  measure_sampled_moments();
  const ParticleSpan span = store_.span();
  const double t = ctx_.time_in_tau0(), s = ctx_.collisions_per_particle();
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    DiagnosticSlot& slot = slots_[k];
    if (!slot.bracketed || !slot.samples_at(next)) continue;
    // The streams of the sample before the collisions are apart from those after (instance k).
    sample_slot(k, span, static_cast<std::uint32_t>(k) | (phase == SamplePhase::before_collisions ? 0x80000000u : 0u),
                phase, t, s);
    slot.bracketed_step = next;
  }
  ctx_.step = step;
  ctx_.time = time;
  sampled_step_ = static_cast<std::uint64_t>(-1);  // the collisions and forcings still to come change the state
}

// One sample() of diagnostic k on the moments in sampled_, with its streams of `instance`, counted
// in its record's means of t/tau0 and s.
void Engine::sample_slot(std::size_t k, const ParticleSpan& span, std::uint32_t instance, SamplePhase phase, double t,
                         double s) {
  DiagnosticSlot& slot = slots_[k];
  const Streams streams = streams_.streams(StreamPurpose::diagnostic, instance);
  ctx_.moments = &sampled_;
  ctx_.streams = &streams;
  ctx_.sample_phase = phase;
  {
    PluginCall call(*slot.site, "sample");
    slot.object->sample(ctx_, span);
  }
  ctx_.sample_phase = SamplePhase::after_step;
  ctx_.moments = nullptr;
  ctx_.streams = nullptr;
  slot.time_sum += t;
  slot.s_sum += s;
  ++slot.samples;
}

void Engine::sample_and_record(bool force_record) {
  const ParticleSpan span = store_.span();
  const double t = ctx_.time_in_tau0();
  const double s = ctx_.collisions_per_particle();
  bool have_moments = false;
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    DiagnosticSlot& slot = slots_[k];
    if (slot.last_record_step == ctx_.step) continue;
    const bool record = force_record || ctx_.step % slot.use->record_every == 0;
    // A bracketed slot has taken its pair in this step; a forced record without one (the initial
    // state, the end of a run) takes a lone sample.
    if ((force_record || slot.samples_at(ctx_.step)) && slot.bracketed_step != ctx_.step) {
      if (!have_moments) {  // once per sampled step, shared by every diagnostic
        if (sampled_step_ != ctx_.step) measure_sampled_moments();
        have_moments = true;
      }
      sample_slot(k, span, static_cast<std::uint32_t>(k), SamplePhase::after_step, t, s);
    }
    if (!record) continue;
    const double n = static_cast<double>(slot.samples);
    outputs_[k].begin_record(slot.time_sum / n, slot.s_sum / n);
    {
      PluginCall call(*slot.site, "record");
      slot.object->record(ctx_, outputs_[k]);
    }
    outputs_[k].check_record(slot.use->plugin->descriptor->name);
    slot.time_sum = slot.s_sum = 0;
    slot.samples = 0;
    slot.last_record_step = ctx_.step;
    if (static_cast<int>(k) == steady_slot_)
      if (const auto steady = is_steady(*pipeline_.stop_steady, outputs_[k])) steady_ = *steady;
  }
}

Progress Engine::progress(double elapsed) const {
  Progress pr;
  pr.fraction = stop_fraction(pipeline_, ctx_);
  pr.time_tau0 = ctx_.time_in_tau0();
  pr.collisions_per_particle = ctx_.collisions_per_particle();
  pr.temperature_over_T0 = global_.temperature / system_.initial_temperature;
  pr.elapsed_seconds = elapsed;
  pr.remaining_seconds = pr.fraction > 0 ? elapsed * (1.0 - pr.fraction) / pr.fraction : -1.0;
  pr.steps = ctx_.step;
  return pr;
}

void Engine::run(const std::function<void(const Progress&)>& report, double interval, const std::atomic<bool>* interrupt,
                 const CheckpointSchedule* checkpoints) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const double earlier_seconds = wall_seconds_;  // of the segments before a resume
  auto last_report = start;
  if (finished_) {  // restored after it finished: nothing left to do
    if (report) {
      Progress last = progress(wall_seconds_);
      last.final = true;
      report(last);
    }
    return;
  }
  const bool checkpointing = checkpoints && checkpoints->write;
  auto last_checkpoint = start;
  double next_checkpoint_s = checkpointing && checkpoints->every_collisions_per_particle > 0
                                 ? ctx_.collisions_per_particle() + checkpoints->every_collisions_per_particle
                                 : -1;
  auto write_checkpoint = [&] {
    wall_seconds_ = earlier_seconds + std::chrono::duration<double>(clock::now() - start).count();
    checkpoints->write(*this);
    last_checkpoint = clock::now();
  };
  // With checkpoints a step is never left half done: the interrupt is seen between steps.
  collisions_.set_interrupt(checkpointing ? nullptr : interrupt);
  while (!finished(pipeline_, ctx_, steady_)) {
    if (checkpointing && interrupt && interrupt->load()) {
      write_checkpoint();
      throw Interrupted();
    }
    poll_interrupt(interrupt);
    step();
    if (!std::isfinite(global_.temperature) || global_.temperature <= 0)
      throw std::runtime_error("the temperature became " + fmt("%.6g", global_.temperature) + " at step " +
                               std::to_string(ctx_.step) + " (t = " + fmt("%.6g", ctx_.time_in_tau0()) +
                               " tau0; checked every run.moments_every = " + std::to_string(pipeline_.moments_every) +
                               " steps): " + velocity_culprits(true));
    if (report) {
      const auto now = clock::now();
      if (std::chrono::duration<double>(now - last_report).count() >= interval) {
        last_report = now;
        report(progress(std::chrono::duration<double>(now - start).count()));
      }
    }
    if (checkpointing) {
      const bool by_time = checkpoints->every_seconds > 0 &&
                           std::chrono::duration<double>(clock::now() - last_checkpoint).count() >= checkpoints->every_seconds;
      const bool by_s = next_checkpoint_s >= 0 && ctx_.collisions_per_particle() >= next_checkpoint_s;
      if (by_s)
        while (next_checkpoint_s <= ctx_.collisions_per_particle()) next_checkpoint_s += checkpoints->every_collisions_per_particle;
      if (by_time || by_s) write_checkpoint();
    }
  }
  sample_and_record(true);
  if (layers_.enabled()) summary_.push_back(layers_.widths_text(ctx_.time_in_tau0()));
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    try {
      PluginCall call(*slots_[k].site, "finish");
      slots_[k].object->finish(ctx_, outputs_[k]);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slots_[k].use) + " failed at the end of the run: " + e.what());
    }
  }
  summary_.push_back(energy_balance_text());
  collisions_.set_interrupt(nullptr);
  finished_ = true;
  wall_seconds_ = earlier_seconds + std::chrono::duration<double>(clock::now() - start).count();
  if (checkpointing) checkpoints->write(*this);
  if (report) {
    Progress last = progress(wall_seconds_);
    last.final = true;
    report(last);
  }
}

// The run's energy balance per particle in units of T0: E - E0 against the sum of what every
// stage declared or the host tallied.
std::string Engine::energy_balance_text() {
  grid_.sampled_moments(store_.span(), system_.number_density, sampled_, &pool_);
  const double per = 1.0 / (static_cast<double>(system_.particles) * system_.initial_temperature);
  return "energy per particle [T0]: " + ledger_.balance_text(sampled_.kinetic_energy - initial_energy_, per);
}

CaseOutput Engine::output() {
  CaseOutput out;
  out.system = {{"particles", static_cast<double>(system_.particles)},
                {"number_density", system_.number_density},
                {"sigma", system_.sigma},
                {"mass", system_.mass},
                {"initial_temperature", system_.initial_temperature},
                {"mean_free_path0", system_.mean_free_path0},
                {"time_unit0", system_.time_unit0},
                {"volume", system_.volume},
                {"box_x", system_.box[0]},
                {"box_y", system_.box[1]},
                {"box_z", system_.box[2]},
                {"layers", static_cast<double>(system_.cells)},
                {"bins", static_cast<double>(system_.bins)}};
  out.run = {{"steps", static_cast<double>(ctx_.step)},
             {"final_time_tau0", ctx_.time_in_tau0()},
             {"collisions", static_cast<double>(ctx_.collisions)},
             {"collisions_per_particle", ctx_.collisions_per_particle()},
             {"candidates", static_cast<double>(ctx_.candidates)},
             {"majorant_exceeded", static_cast<double>(ctx_.majorant_exceeded)},
             {"collisions_missed_by_majorant", missed_collisions_},
             {"collision_energy_change", ctx_.collision_energy_change},
             {"kinetic_energy_initial", initial_energy_},
             {"kinetic_energy_final", sampled_.kinetic_energy},
             {"wall_seconds", wall_seconds_},
             {"reached_steady_state", steady_ ? 1.0 : 0.0}};
  layers_.write(out);
  ledger_.write(out.run);
  if (system_.geometry == Geometry::slab) walls_.write(out.run);
  out.plugins = plugin_provenance(pipeline_);
  out.diagnostics = outputs_;
  if (pipeline_.output_particles) out.particles = particle_datasets(store_.span(), system_);
  return out;
}

}  // namespace gdsmc::host
