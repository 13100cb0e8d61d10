// The engine's construction: every plugin object built and begun, the particles allocated and
// the initial state generated, the slab's mover, the ledger and the diagnostics' outputs opened.
#include <cmath>

#include "config/system_info.hpp"
#include "engine/engine.hpp"
#include "engine/memory_estimate.hpp"
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
  return std::move(check.diagnostics_.outputs());
}

Engine::Engine(const Pipeline& p, std::uint32_t realization, Setup setup, unsigned threads, StateReader* state)
    : pipeline_(p), pool_(run_threads(p, threads)), sites_(p, &ctx_.step), streams_(p.seed, realization) {
  system_ = system_info(p, p.particles, realization);
  for (std::size_t s = 0; s < system_.species_count && system_.species; ++s) species_mass_.push_back(system_.species_mass(s));
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
  if (species_mass()) {
    std::vector<double> diameter;
    for (std::size_t s = 0; s < system_.species_count; ++s) diameter.push_back(system_.species_diameter(s));
    collisions_.set_species(species_mass(), diameter.data(), system_.species_count);
  }
  collisions_.reset(cells);
  collisions_.set_pair_count(p.candidate_pairs_squared ? PairCount::squared : PairCount::distinct);
  collisions_.set_pair_selection(p.pair_selection == 0   ? PairSelection::uniform
                                 : p.pair_selection == 1 ? PairSelection::weighted
                                                         : PairSelection::automatic);
  collisions_.set_tally_count(collision_tallies_.size());
  collisions_.set_subpopulation(p.subpopulation);
  collisions_.set_pool(&pool_);
  cells_.assign(cells, CellMoments{});
  // (not a mixture: its majorants follow each species' temperature, which the pass measures)
  moments_follow_collisions_ = !species_mass() && system_.geometry != Geometry::slab && forcings_before_.empty() &&
                               forcings_after_.empty() && accelerations_.empty();
  collisions_.set_collisions_only(moments_follow_collisions_);
  if (setup != Setup::objects_only) {
    if (system_.geometry == Geometry::slab) {
      grid_.slab(system_.particles, cells, system_.box[1], system_.cross_section());
      if (layers_.enabled()) grid_.set_edges(layers_.edges());
    } else {
      grid_.homogeneous(system_.particles, system_.volume);
    }
    grid_.set_species(species_mass(), system_.species_count);
    grid_.set_sampling_system(&system_);
    checked_collision_.bind(store_.span());
    if (setup == Setup::full) generate_initial_state();
  }
  ctx_.cells = cells_.data();
  ctx_.cell_count = cells_.size();
  ctx_.global = &global_;
  ctx_.boundaries = walls_.data();
  ctx_.boundary_count = system_.geometry == Geometry::slab ? 2 : 0;
  if (species_mass() && system_.geometry == Geometry::slab) {
    walls_.open_species(system_.species_count);
    ctx_.species_boundaries = walls_.species_data();
  }
  ctx_.energy_ledger = ledger_.data();
  ctx_.energy_ledger_size = ledger_.size();
  ctx_.collision_tallies = collision_tallies_.data();
  ctx_.collision_tally_count = collision_tallies_.size();
  begin_diagnostics();
  report_layout(attributes, diagnostics_.outputs());  // what the memory estimate counts (validate)
  if (setup == Setup::full) sample_and_record(true);  // the initial state is the first record of every diagnostic
  if (setup == Setup::restore) load(*state);
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
  for (const auto& u : p.diagnostics) diagnostics_.add(static_cast<Diagnostic*>(make(u)), &u, &site_of(u));
  checked_collision_.set(collision_, &site_of(p.collision));
  refuse_one_species_plugins();
}

// A mixture runs only plugins that weigh particles by their species' masses (extension
// "gdsmc.species"): one written for a single species of unit mass would give wrong physics
// without an error.
void Engine::refuse_one_species_plugins() {
  if (system_.species_count < 2) return;
  std::string refused;
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    PluginCall call(site_of(*object_uses_[k]), "extension");
    if (!objects_[k]->extension(species_id)) refused += "\n  " + where_text(*object_uses_[k]);
  }
  if (!refused.empty())
    throw std::runtime_error("system.species makes this run a mixture of " + std::to_string(system_.species_count) +
                             " species, but these plugins handle one species only (they do not offer the extension "
                             "'gdsmc.species'; the plugin author guide's section on species says what it asks of a plugin):" + refused);
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
  mover_->set_species(species_mass(), system_.species_count);
  mover_->set_tally_units(system_.initial_temperature, system_.mass);  // fixed-point units of T0, sqrt(m T0)
}

// Particles (full setup only) and the attributes, then every object publishes its quantities.
void Engine::publish(const std::vector<AttributeSpec>& attributes, Setup setup) {
  if (setup == Setup::full) {
    store_.allocate(pipeline_.particles, attributes, system_.geometry == Geometry::slab);
    if (system_.species_count > 1) store_.set_species(species_counts(pipeline_.species, pipeline_.particles));
  } else {
    ParticleStore::check_attributes(attributes);
  }
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
  sampled_parts_ = moments_all;
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

// The parts of the sampled moments that some diagnostic reads (MomentsRead), and the host's own use
// of them (update_moments) when only the collisions change the velocities.
void Engine::begin_diagnostics() {
  const std::uint32_t read = diagnostics_.begin(pipeline_, system_, board_, moments_follow_collisions_, &summary_);
  moments_parts_ = read | (moments_follow_collisions_ ? static_cast<std::uint32_t>(moments_all) : 0u);
}

}  // namespace gdsmc::host
