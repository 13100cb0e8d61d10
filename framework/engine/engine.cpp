// The step loop: forcings, flight, collisions, moment updates, samples and records, the run to its
// stop condition with progress and checkpoints, and the run's output. Construction is in
// engine_setup.cpp, the checkpoint state in engine_state.cpp.
#include "engine/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "config/system_info.hpp"
#include "engine/majorant.hpp"
#include "engine/memory_estimate.hpp"
#include "engine/stop.hpp"
#include "output/particle_dump.hpp"
#include "output/provenance.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

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
  set_layer_majorants();
  sampled_step_ = static_cast<std::uint64_t>(-1);
  summary_.push_back(line);
  if (system_.realization == 0) std::fprintf(stderr, "%s\n", line.c_str());
}


// Every run.moments_every steps. A homogeneous system without forcings changes its velocities only
// in collisions, which conserve momentum and declare their kinetic-energy change (conformance
// checks both to round-off): its mean stays and T += 2 dE / (3 N) (m = 1; Eq. 4.15 differenced),
// without the pass over every particle (1.3 ms at N = 1e6, a step's collisions 1.6 ms). A step
// that samples measures both afresh, in the one pass it makes anyway; a rule that declares a
// non-finite change (which conformance refuses) gets the pass.
// Every layer's majorants from its moments (a mixture's per pair of species).
void Engine::set_layer_majorants() {
  if (species_mass())
    collisions_.set_species_majorants(grid_.species_cell_moments(), cells_.data(), global_.temperature);
  else
    collisions_.set_layer_majorants(cells_.data(), grid_.peculiar_speed_max(), global_.temperature, system_.mass);
}

void Engine::update_moments() {
  const double declared = ctx_.collision_energy_change - energy_at_update_;
  energy_at_update_ = ctx_.collision_energy_change;
  if (moments_follow_collisions_ && diagnostics_.samples_at(ctx_.step)) {
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
      set_layer_majorants();
  }
  if (!grid_.is_slab()) collisions_.reset_majorants();
}

void Engine::measure_sampled_moments() {
  grid_.sampled_moments(store_.span(), system_.number_density, sampled_, &pool_,
                        moments_follow_collisions_ ? global_.mean_velocity : nullptr, moments_parts_);
  sampled_step_ = ctx_.step;
  sampled_parts_ = moments_parts_;
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
  if (diagnostics_.any_bracketed()) {
    sample_bracketed(SamplePhase::before_collisions);
    lap(Stage::diagnostics);
  }
  collide(dt);
  lap(Stage::collisions);
  if (diagnostics_.any_bracketed()) {
    sample_bracketed(SamplePhase::after_collisions);
    lap(Stage::diagnostics);
  }
  if (!forcings_after_.empty()) {
    apply_forcings(forcings_after_);
    lap(Stage::forcings);
  }
  ctx_.time += dt;
  ++ctx_.step;
  if (layers_.enabled()) {  // due and profiling until the edges are set
    const double t = ctx_.time_in_tau0();
    if (layers_.due(t)) {
      // with this step's positions, and new moments for the new layers
      if (ranks_) set_layers_decomposed();
      else set_layers_from_profile();
      lap(Stage::reorder);
    } else if (layers_.profiling(t) && ctx_.step % pipeline_.moments_every == 0) {
      if (!ranks_) {
        layers_.sample_profile(store_.span());
      } else {  // rank 0 samples the profile of the gathered particles
        gather_whole();
        if (ranks_->root()) on_whole_serial([&] { layers_.sample_profile(store_.span()); });
      }
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
  if (ranks_) {  // on rank 0, with every particle in the single-process order; the velocities back
    gather_whole();
    if (ranks_->root()) on_whole_serial([&] { apply_forcings(forcings); });
    return_whole();
    return;
  }
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
  if (!mover_) {
    if (dot(acceleration_, acceleration_) > 0) kick(dt);
    return;
  }
  StreamingTally tally;
  const ParticleSpan span = store_.span();
  mover_->stream(span, store_.cells(), grid_.block_counts(span.count), grid_, ctx_.time, dt, ctx_, streams_, tally,
                 &pool_);
  lap(Stage::flight);
  if (ranks_) {  // the particles that left this rank's layers to their ranks, and every rank's tallies
    migrate();
    merge_tally(tally);
    lap(Stage::sort);
  }
  sort_into_layers();
  check_streaming_tally(tally);
  for (int s = 0; s < 2; ++s) {
    walls_.add(s, tally.sides[s]);
    ledger_.add_wall(s, tally.sides[s].energy);
  }
  if (species_mass()) walls_.add_species(tally.species_sides.data(), StreamingTally::kMaxSpecies);
  if (!accelerations_.empty()) ledger_.add_forcing(accelerations_[0], tally.acceleration_energy);
}

// After the flight: the layers' ranges; their member lists are written by the collision stage,
// interleaved with the layers' collisions (CollisionStage::PendingMembers), except when they are
// needed first (members_written_by_collisions): then sorted now, and at a reordering storage is
// put in their order.
void Engine::sort_into_layers() {
  const std::size_t n = store_.size();
  grid_.place_blocks(n);
  if (members_written_by_collisions()) {
    lap(Stage::sort);
    return;
  }
  grid_.scatter_blocks(store_.cells(), n, &pool_);
  if (ranks_) sort_members_by_key();
  lap(Stage::sort);
  if (!reorders_now()) return;
  permute_by_layer();  // the layers just sorted from the fresh cell[]
  if (ranks_) rebalance();
  lap(Stage::reorder);
}

// A homogeneous system's body acceleration: every velocity kicked by g dt.
void Engine::kick(double dt) {
  const ParticleSpan span = store_.span();
  const double g2 = dot(acceleration_, acceleration_);
  // Blocks of the moment pieces' size, their energies added in block order.
  const std::size_t block = CellGrid::kMomentBlock, blocks = (span.count + block - 1) / block;
  kick_energy_.resize(blocks);
  for_pieces(&pool_, blocks, [&](std::size_t k) {
    double energy = 0;
    const double* mass = species_mass();
    for (std::size_t i = k * block, e = std::min(span.count, i + block); i < e; ++i) {
      const double work = (acceleration_.x * span.vx[i] + acceleration_.y * span.vy[i] + acceleration_.z * span.vz[i]) * dt;
      energy += mass ? mass[span.species[i]] * (work + 0.5 * g2 * dt * dt) : work;  // m_i (g.v dt + g^2 dt^2 / 2)
      span.vx[i] += acceleration_.x * dt;
      span.vy[i] += acceleration_.y * dt;
      span.vz[i] += acceleration_.z * dt;
    }
    kick_energy_[k] = energy;
  });
  double energy = 0;
  for (const double e : kick_energy_) energy += e;
  ledger_.add_forcing(accelerations_[0],
                      species_mass() ? energy : energy + 0.5 * g2 * dt * dt * static_cast<double>(span.count));
  lap(Stage::flight);
}

// The mover's tallies are NaN when a term was not finite or beyond the fixed-point range (2^33
// T0 per hit or particle, engine/fixed_point_sum.hpp): the run stops, naming the source.
void Engine::check_streaming_tally(const StreamingTally& tally) const {
  const auto finite = [](const BoundaryTally& t) {
    return std::isfinite(t.energy) && std::isfinite(t.momentum[0]) && std::isfinite(t.momentum[1]) && std::isfinite(t.momentum[2]);
  };
  const char* beyond = ": more than 2^33 T0 (or a non-finite value) in one step of one particle is beyond the range of "
                       "the exact tallies; the run is stopped (use a smaller run.time_step or a gentler forcing)";
  for (int s = 0; s < 2; ++s)
    if (!finite(tally.sides[s]))
      throw std::runtime_error(where_text(pipeline_.boundaries[s]) + " exchanged a non-finite energy or momentum with a particle " +
                               now_text() + beyond);
  if (!std::isfinite(tally.acceleration_energy))
    throw std::runtime_error(where_text(pipeline_.forcings[accelerations_.empty() ? 0 : accelerations_[0]]) +
                             " did a non-finite work on a particle " + now_text() + beyond);
}

void Engine::reorder_by_layer() {
  if (!grid_.is_slab()) return;
  const ParticleSpan span = store_.span();
  grid_.assign_and_sort(span.y.data, store_.cells(), span.count);  // from the positions as they are now
  permute_by_layer();
}

// Storage in the order of the current member lists; each layer is then a range of positions (and,
// decomposed, each particle's key its place in the single-process run's storage).
void Engine::permute_by_layer() {
  store_.permute(grid_.all_members(), &pool_);
  grid_.set_layer_order(store_.cells(), &pool_);
  if (ranks_) renumber_keys();
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
  if (ranks_ && !diagnostics_.bracketed_due_at(next)) return;
  if (ranks_ && !samples_locally(root_says(diagnostics_.bracketed_particles_at(next)))) {
    gather_whole();  // on rank 0, with every particle in the single-process order
    if (ranks_->root()) on_whole_serial([&] { sample_bracketed(phase); });
    return;
  }
  if (!ranks_ && !diagnostics_.bracketed_at(next)) return;
  const std::uint64_t step = ctx_.step;
  const double time = ctx_.time;
  ctx_.step = next;
  ctx_.time += ctx_.dt;
  measure_sampled_moments();  // every rank's share of the moments of a decomposed slab
  if (!ranks_ || ranks_->root()) diagnostics_.sample_bracketed(ctx_, diagnostic_span(), streams_, sampled_, phase);
  ctx_.step = step;
  ctx_.time = time;
  sampled_step_ = static_cast<std::uint64_t>(-1);  // the collisions and forcings still to come change the state
}

void Engine::sample_and_record(bool force_record) {
  if (ranks_) {  // rank 0 samples and records; its steady flag to all
    if (!force_record && !diagnostics_.due_at(ctx_.step)) return;
    if (samples_locally(root_says(diagnostics_.lone_sample_at(ctx_.step, force_record, true)))) {
      // Every rank's share of the moments, when some diagnostic samples (a bracketed one that took
      // its pair this step only records); rank 0's cache of a gathered sample is its own.
      if (root_says(diagnostics_.lone_sample_at(ctx_.step, force_record, false))) measure_sampled_moments();
      if (ranks_->root()) {
        const auto moments = [&]() -> const SampledMoments& { return sampled_; };
        if (const auto steady = diagnostics_.sample_and_record(ctx_, ParticleSpan{}, streams_, force_record, moments))
          steady_ = *steady;
      }
    } else {
      gather_whole();  // on rank 0, with every particle in the single-process order
      if (ranks_->root()) on_whole_serial([&] { sample_and_record(force_record); });
    }
    steady_ = root_says(steady_);
    return;
  }
  const auto moments = [&]() -> const SampledMoments& {
    if (!sampled_fresh()) measure_sampled_moments();
    return sampled_;
  };
  if (const auto steady = diagnostics_.sample_and_record(ctx_, store_.span(), streams_, force_record, moments))
    steady_ = *steady;
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
    if (ranks_) gather_whole();  // the output's particles, on rank 0
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
  auto write_state = [&] { write_checkpoint_state(*checkpoints); };
  auto write_checkpoint = [&] {
    wall_seconds_ = earlier_seconds + std::chrono::duration<double>(clock::now() - start).count();
    write_state();
    last_checkpoint = clock::now();
  };
  // Whether to stop (interrupted) before the next step: decomposed, when any rank was interrupted.
  auto interrupted = [&] {
    const bool mine = interrupt && interrupt->load();
    return ranks_ ? any_rank(mine) : mine;
  };
  // With checkpoints a step is never left half done: the interrupt is seen between steps; so too
  // over ranks, which all stop at the same step.
  collisions_.set_interrupt(checkpointing || ranks_ ? nullptr : interrupt);
  while (!finished(pipeline_, ctx_, steady_)) {
    const bool stop = interrupted();
    if (checkpointing && stop) {
      write_checkpoint();
      throw Interrupted();
    }
    if (stop) throw Interrupted();
    step();
    if (!std::isfinite(global_.temperature) || global_.temperature <= 0)
      throw std::runtime_error("the temperature became " + fmt("%.6g", global_.temperature) + " at step " +
                               std::to_string(ctx_.step) + " (t = " + fmt("%.6g", ctx_.time_in_tau0()) +
                               " tau0; checked every run.moments_every = " + std::to_string(pipeline_.moments_every) +
                               " steps): " + velocity_culprits(true));
    if (report && (!ranks_ || ranks_->root())) {
      const auto now = clock::now();
      if (std::chrono::duration<double>(now - last_report).count() >= interval) {
        last_report = now;
        report(progress(std::chrono::duration<double>(now - start).count()));
      }
    }
    if (checkpointing) {
      bool by_time = checkpoints->every_seconds > 0 &&
                     std::chrono::duration<double>(clock::now() - last_checkpoint).count() >= checkpoints->every_seconds;
      if (ranks_ && checkpoints->every_seconds > 0) by_time = any_rank(by_time);
      const bool by_s = next_checkpoint_s >= 0 && ctx_.collisions_per_particle() >= next_checkpoint_s;
      if (by_s)
        while (next_checkpoint_s <= ctx_.collisions_per_particle()) next_checkpoint_s += checkpoints->every_collisions_per_particle;
      if (by_time || by_s) write_checkpoint();
    }
  }
  finish_diagnostics();
  collisions_.set_interrupt(nullptr);
  finished_ = true;
  wall_seconds_ = earlier_seconds + std::chrono::duration<double>(clock::now() - start).count();
  if (checkpointing) write_state();
  if (report && (!ranks_ || ranks_->root())) {
    Progress last = progress(wall_seconds_);
    last.final = true;
    report(last);
  }
}

// The run's state through `checkpoints`: decomposed, rank 0 writes it with every particle gathered
// (the other ranks send theirs) and the layers' shared moments.
void Engine::write_checkpoint_state(const CheckpointSchedule& checkpoints) {
  if (!ranks_) return checkpoints.write(*this);
  gather_whole();
  if (!ranks_->root()) return;
  whole_grid_.set_species_cell_values(grid_.species_cell_values());  // a mixture's majorant scales (save())
  on_whole_serial([&] { checkpoints.write(*this); });
}

// After the last step: the last record, the diagnostics' finish and the summary's layer widths and
// energy balance (decomposed: rank 0, with the last state's particles gathered for them and the output).
void Engine::finish_diagnostics() {
  sample_and_record(true);
  if (ranks_) gather_whole();
  if (layers_.enabled()) summary_.push_back(layers_.widths_text(ctx_.time_in_tau0()));
  const auto finish = [&] {
    diagnostics_.finish(ctx_);
    summary_.push_back(energy_balance_text());
  };
  if (!ranks_) finish();
  else if (ranks_->root()) on_whole_serial(finish);
}

// The run's energy balance per particle in units of T0: E - E0 against the sum of what every
// stage declared or the host tallied.
std::string Engine::energy_balance_text() {
  grid_.sampled_moments(store_.span(), system_.number_density, sampled_, &pool_);
  const double per = 1.0 / (static_cast<double>(system_.particles) * system_.initial_temperature);
  return "energy per particle [T0]: " + ledger_.balance_text(sampled_.kinetic_energy - initial_energy_, per);
}

}  // namespace gdsmc::host
