#include "engine/engine.hpp"

#include <chrono>
#include <cmath>

#include "engine/majorant.hpp"
#include "engine/stop.hpp"
#include "output/particle_dump.hpp"
#include "output/provenance.hpp"

namespace gdsmc::host {

namespace {
std::string where_text(const PluginUse& u) {
  return "plugin '" + u.plugin->descriptor->name + "' (" + u.path + ", " + u.where.str() + ")";
}
}  // namespace

Engine::Engine(const Pipeline& p, std::uint32_t realization) : Engine(p, realization, Setup::full) {}

void Engine::check_setup(const Pipeline& p) { Engine check(p, 0, Setup::objects_only); }

Engine::Engine(const Pipeline& p, std::uint32_t realization, Setup setup)
    : pipeline_(p), majorant_ratio_(kInitialMajorantRatio) {
  system_ = p.system_info(p.particles, realization);
  build_objects();
  std::vector<AttributeSpec> attributes;
  for (const auto& o : objects_)
    for (auto& a : o->attributes()) attributes.push_back(std::move(a));
  publish(attributes, setup);
  ctx_.system = &system_;
  ctx_.quantities = &board_;
  ctx_.key = stream_key(p.seed, realization);
  ctx_.cells = &global_;
  ctx_.cell_count = 1;
  ctx_.global = &global_;
  if (setup == Setup::full) generate_initial_state();
  begin_diagnostics();
  if (setup == Setup::full) sample_and_record(true);  // the initial state is the first record of every diagnostic
}

void Engine::build_objects() {
  const Pipeline& p = pipeline_;
  auto make = [&](const PluginUse& u) -> PluginObject* {
    try {
      objects_.push_back(create_object(*u.plugin, u.params));
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
    (f->stage() == Forcing::Stage::before_streaming ? forcings_before_ : forcings_after_)
        .emplace_back(f, static_cast<std::uint32_t>(k));
  }
  if (!p.boundaries.empty())
    throw std::runtime_error("boundaries are given but this version runs homogeneous systems only");
  for (const auto& u : p.diagnostics) slots_.push_back(DiagnosticSlot{static_cast<Diagnostic*>(make(u)), &u});
}

// Particles (full setup only) and the attributes, then every object publishes its quantities.
void Engine::publish(const std::vector<AttributeSpec>& attributes, Setup setup) {
  if (setup == Setup::full) store_.allocate(pipeline_.particles, attributes);
  else ParticleStore::check_attributes(attributes);
  for (const auto& o : objects_) o->publish(board_);
}

void Engine::generate_initial_state() {
  {
    Rng rng(ctx_.key, StreamPurpose::initial_state, 0, 0);
    try {
      initial_state_->generate(system_, store_.span(), rng);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(pipeline_.initial_state) + ": " + e.what());
    }
  }
  update_moments();
  if (!(global_.temperature > 0) || !std::isfinite(global_.temperature))
    throw std::runtime_error(where_text(pipeline_.initial_state) + " produced a state with temperature " +
                             std::to_string(global_.temperature) + "; a positive finite temperature is needed");
}

void Engine::begin_diagnostics() {
  const Pipeline& p = pipeline_;
  if (p.stop_steady)
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].use->instance_name == p.stop_steady->group) steady_slot_ = static_cast<int>(k);
  outputs_.reserve(slots_.size());
  for (auto& slot : slots_) {
    outputs_.emplace_back(slot.use->instance_name, &summary_);
    try {
      slot.object->begin(system_, board_, outputs_.back());
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slot.use) + ": " + e.what());
    }
  }
}

void Engine::update_moments() {
  const VelocityMoments m = velocity_moments(store_.span());
  global_.count = m.count;
  global_.number_density = system_.number_density;
  for (int a = 0; a < 3; ++a) global_.mean_velocity[a] = m.mean[a];
  global_.temperature = m.temperature;
}

void Engine::step() {
  const double T = global_.temperature;
  // dt = c tau0, or c tau0 sqrt(T0/T) so that it follows the mean free time (000 Sec. IV.B)
  double dt = pipeline_.time_step_tau0 * system_.time_unit0;
  if (pipeline_.time_step_follows_temperature) dt *= std::sqrt(system_.initial_temperature / T);
  ctx_.dt = dt;
  const ParticleSpan span = store_.span();

  for (auto& [f, index] : forcings_before_) {
    Rng rng = ctx_.rng(StreamPurpose::forcing, index << 16);
    f->apply(ctx_, span, rng);
  }

  // Collision stage: one cell holding every particle in a homogeneous system (000 Eq. 4.23).
  {
    Rng rng = ctx_.rng(StreamPurpose::collisions, 0);
    CellCollision cell;
    cell.particles = span;
    cell.members = nullptr;
    cell.count = static_cast<std::uint32_t>(span.count);
    cell.volume = system_.volume;
    cell.sigma = system_.sigma;
    cell.dt = dt;
    const double thermal_speed = std::sqrt(global_.temperature / system_.mass);
    cell.majorant = majorant_ratio_ * thermal_speed;
    cell.remainder = candidate_remainder_;
    cell.rng = &rng;
    collision_->collide_cell(cell);
    candidate_remainder_ = cell.remainder;
    if (cell.max_rate > cell.majorant) majorant_ratio_ = kMajorantHeadroom * cell.max_rate / thermal_speed;
    ctx_.collisions += static_cast<double>(cell.accepted);
    ctx_.candidates += static_cast<double>(cell.candidates);
    ctx_.majorant_exceeded += static_cast<double>(cell.majorant_exceeded);
    ctx_.collision_energy_change += cell.energy_change;
  }

  for (auto& [f, index] : forcings_after_) {
    Rng rng = ctx_.rng(StreamPurpose::forcing, index << 16);
    f->apply(ctx_, span, rng);
  }

  ctx_.time += dt;
  ++ctx_.step;
  if (ctx_.step % pipeline_.moments_every == 0) update_moments();
  sample_and_record(false);
}

void Engine::sample_and_record(bool force_record) {
  const ParticleSpan span = store_.span();
  const double t = ctx_.time_in_tau0();
  const double s = ctx_.collisions_per_particle();
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    DiagnosticSlot& slot = slots_[k];
    const bool record = force_record || ctx_.step % slot.use->record_every == 0;
    if (slot.last_record_step == ctx_.step) continue;
    if (record || ctx_.step % slot.use->sample_every == 0) {
      slot.object->sample(ctx_, span);
      slot.time_sum += t;
      slot.s_sum += s;
      ++slot.samples;
    }
    if (!record) continue;
    const double n = static_cast<double>(slot.samples);
    outputs_[k].begin_record(slot.time_sum / n, slot.s_sum / n);
    slot.object->record(ctx_, outputs_[k]);
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

void Engine::run(const std::function<void(const Progress&)>& report, double interval, const std::atomic<bool>* interrupt) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  while (!finished(pipeline_, ctx_, steady_)) {
    if (interrupt && interrupt->load(std::memory_order_relaxed)) throw Interrupted();
    step();
    if (!std::isfinite(global_.temperature) || global_.temperature <= 0)
      throw std::runtime_error("the temperature became " + std::to_string(global_.temperature) + " at step " +
                               std::to_string(ctx_.step) + " (t = " + std::to_string(ctx_.time_in_tau0()) +
                               " tau0): a plugin produced invalid velocities");
    if (report) {
      const auto now = clock::now();
      if (std::chrono::duration<double>(now - last_report).count() >= interval) {
        last_report = now;
        report(progress(std::chrono::duration<double>(now - start).count()));
      }
    }
  }
  sample_and_record(true);
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    try {
      slots_[k].object->finish(ctx_, outputs_[k]);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slots_[k].use) + " failed at the end of the run: " + e.what());
    }
  }
  wall_seconds_ = std::chrono::duration<double>(clock::now() - start).count();
  if (report) report(progress(wall_seconds_));
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
                {"volume", system_.volume}};
  out.run = {{"steps", static_cast<double>(ctx_.step)},
             {"final_time_tau0", ctx_.time_in_tau0()},
             {"collisions", ctx_.collisions},
             {"collisions_per_particle", ctx_.collisions_per_particle()},
             {"candidates", ctx_.candidates},
             {"majorant_exceeded", ctx_.majorant_exceeded},
             {"collision_energy_change", ctx_.collision_energy_change},
             {"wall_seconds", wall_seconds_},
             {"reached_steady_state", steady_ ? 1.0 : 0.0}};
  out.plugins = plugin_provenance(pipeline_);
  out.diagnostics = outputs_;
  if (pipeline_.output_particles) out.particles = particle_datasets(store_.span(), system_);
  return out;
}

}  // namespace gdsmc::host
