#include "engine.hpp"

#include <chrono>
#include <cmath>

namespace gdsmc::host {

namespace {
// Initial majorant of the hard-sphere acceptance rate |g| in units of sqrt(T/m): for a Maxwellian
// |g| / sqrt(T/m) is sqrt(2) chi_3, which exceeds 6 sqrt(2) with probability ~1e-7 per candidate.
// Exceedances are counted and raise the ratio (see CellCollision::majorant_exceeded).
constexpr double kInitialMajorantRatio = 6.0 * M_SQRT2;
constexpr double kMajorantHeadroom = 1.05;

std::string where_text(const PluginUse& u) {
  return "plugin '" + u.plugin->descriptor->name + "' (" + u.path + ", " + u.where.str() + ")";
}
}  // namespace

Engine::Engine(const Pipeline& p, std::uint32_t realization) : pipeline_(p), majorant_ratio_(kInitialMajorantRatio) {
  system_ = p.system_info(p.particles, realization);

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

  std::vector<AttributeSpec> attributes;
  for (const auto& o : objects_)
    for (auto& a : o->attributes()) attributes.push_back(std::move(a));
  store_.allocate(p.particles, attributes);
  for (const auto& o : objects_) o->publish(board_);

  ctx_.system = &system_;
  ctx_.quantities = &board_;
  ctx_.key = stream_key(p.seed, realization);
  ctx_.cells = &global_;
  ctx_.cell_count = 1;
  ctx_.global = &global_;

  {
    Rng rng(ctx_.key, StreamPurpose::initial_state, 0, 0);
    try {
      initial_state_->generate(system_, store_.span(), rng);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(p.initial_state) + ": " + e.what());
    }
  }
  update_moments();
  if (!(global_.temperature > 0) || !std::isfinite(global_.temperature))
    throw std::runtime_error(where_text(p.initial_state) + " produced a state with temperature " +
                             std::to_string(global_.temperature) + "; a positive finite temperature is needed");

  if (p.stop_steady)
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].use->instance_name == p.stop_steady->group) steady_slot_ = static_cast<int>(k);
  outputs_.reserve(slots_.size());
  for (auto& slot : slots_) {
    outputs_.emplace_back(slot.use->instance_name, &summary_);
    try {
      slot.object->begin(system_, board_, outputs_.back());
    } catch (const ParameterError& e) {
      throw std::runtime_error(where_text(*slot.use) + ": " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slot.use) + ": " + e.what());
    }
  }
  sample_and_record(true);  // the initial state is the first record of every diagnostic
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
    if (static_cast<int>(k) == steady_slot_) check_steady();
  }
}

void Engine::check_steady() {
  // Means of the series over the windows (s - 2W, s - W] and (s - W, s] of the last record.
  const SteadyStop& st = *pipeline_.stop_steady;
  const DiagnosticOutput& out = outputs_[static_cast<std::size_t>(steady_slot_)];
  const DiagnosticOutput::Column* col = nullptr;
  for (const auto& c : out.columns)
    if (c.name == st.column) col = &c;
  if (!col) {
    throw std::runtime_error("run.stop.steady: diagnostic '" + st.group + "' has no series '" + st.column + "'");
  }
  const auto& s = out.collisions_per_particle;
  if (s.empty() || s.back() < 2 * st.window) return;
  double sum[2] = {0, 0};
  std::size_t n[2] = {0, 0};
  for (std::size_t k = s.size(); k-- > 0;) {
    const double age = s.back() - s[k];
    if (age >= 2 * st.window) break;
    const int w = age < st.window ? 1 : 0;
    sum[w] += col->values[k];
    ++n[w];
  }
  if (n[0] < 3 || n[1] < 3) return;
  const double older = sum[0] / static_cast<double>(n[0]), newer = sum[1] / static_cast<double>(n[1]);
  steady_ = std::fabs(newer - older) <= st.tolerance * std::fabs(newer);
}

bool Engine::finished() const {
  if (steady_) return true;
  if (pipeline_.stop_collisions_per_particle && ctx_.collisions_per_particle() >= *pipeline_.stop_collisions_per_particle)
    return true;
  if (pipeline_.stop_time_tau0 && ctx_.time_in_tau0() >= *pipeline_.stop_time_tau0 * (1.0 - 1e-12)) return true;
  return false;
}

double Engine::stop_fraction() const {
  double f = 0;
  if (pipeline_.stop_collisions_per_particle)
    f = std::max(f, ctx_.collisions_per_particle() / *pipeline_.stop_collisions_per_particle);
  if (pipeline_.stop_time_tau0) f = std::max(f, ctx_.time_in_tau0() / *pipeline_.stop_time_tau0);
  return std::min(1.0, f);
}

void Engine::run(const std::function<void(const Progress&)>& report, double interval, const std::atomic<bool>* interrupt) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  auto progress = [&](double elapsed) {
    Progress pr;
    pr.fraction = stop_fraction();
    pr.time_tau0 = ctx_.time_in_tau0();
    pr.collisions_per_particle = ctx_.collisions_per_particle();
    pr.temperature_over_T0 = global_.temperature / system_.initial_temperature;
    pr.elapsed_seconds = elapsed;
    pr.remaining_seconds = pr.fraction > 0 ? elapsed * (1.0 - pr.fraction) / pr.fraction : -1.0;
    pr.steps = ctx_.step;
    return pr;
  };
  while (!finished()) {
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
  auto prov = [&](const std::string& role, const PluginUse& u) {
    PluginProvenance pp{role, u.instance_name, u.plugin->descriptor->name, u.plugin->descriptor->version,
                        u.plugin->file.string(), {}};
    for (const auto& [k, e] : u.params.entries()) pp.parameters[k] = value_text(e.value);
    out.plugins.push_back(std::move(pp));
  };
  prov("initial_state", pipeline_.initial_state);
  prov("collision", pipeline_.collision);
  for (const auto& u : pipeline_.forcings) prov(u.path, u);
  for (const auto& u : pipeline_.diagnostics) prov(u.path, u);
  out.diagnostics = outputs_;
  if (pipeline_.output_particles) {
    const ParticleSpan s = store_.span();
    const double length = system_.mean_free_path0, speed = std::sqrt(2.0 * system_.initial_temperature / system_.mass);
    auto column = [&](const char* name, const double* v, double scale, const char* unit, const char* doc) {
      ParticleDataset d{name, unit, doc, 1, std::vector<double>(v, v + s.count)};
      for (double& x : d.data) x /= scale;
      out.particles.push_back(std::move(d));
    };
    column("x", s.x, length, "lambda0", "final position x");
    column("y", s.y, length, "lambda0", "final position y");
    column("z", s.z, length, "lambda0", "final position z");
    column("vx", s.vx, speed, "sqrt(2T0/m)", "final velocity x");
    column("vy", s.vy, speed, "sqrt(2T0/m)", "final velocity y");
    column("vz", s.vz, speed, "sqrt(2T0/m)", "final velocity z");
    for (std::size_t a = 0; a < s.attribute_count; ++a) {
      const AttributeSpec& spec = s.attribute_specs[a];
      const double* data = s.attribute_data[a];
      out.particles.push_back(ParticleDataset{spec.name, spec.unit, spec.doc, spec.components,
                                              std::vector<double>(data, data + s.count * spec.components)});
    }
  }
  return out;
}

}  // namespace gdsmc::host
