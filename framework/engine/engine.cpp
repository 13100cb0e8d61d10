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
    : pipeline_(p), pool_(run_threads(p, threads)), streams_(p.seed, realization) {
  run_name_ = thread_run_name();
  build_sites();
  system_ = p.system_info(p.particles, realization);
  open_layers();
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
  open_ledger();
  const std::size_t cells = system_.cells;
  collisions_.reset(cells);
  collisions_.set_pair_count(p.candidate_pairs_squared ? PairCount::squared : PairCount::distinct);
  collisions_.set_pair_selection(p.pair_selection == 0   ? PairSelection::uniform
                                 : p.pair_selection == 1 ? PairSelection::weighted
                                                         : PairSelection::automatic);
  collisions_.set_tally_count(tallies_total_.size());
  collisions_.set_subpopulation(p.subpopulation);
  collisions_.set_pool(&pool_);
  cells_.assign(cells, CellMoments{});
  moments_follow_collisions_ = system_.geometry != Geometry::slab && forcings_before_.empty() &&
                               forcings_after_.empty() && accelerations_.empty();
  collisions_.set_collisions_only(moments_follow_collisions_);
  if (setup != Setup::objects_only) {
    if (system_.geometry == Geometry::slab) {
      grid_.slab(system_.particles, cells, system_.box[1], system_.cross_section());
      if (adaptive_layers()) grid_.set_edges(layer_edges_);
    } else {
      grid_.homogeneous(system_.particles, system_.volume);
    }
    checked_collision_.bind(store_.span());
    if (setup == Setup::full) generate_initial_state();
  }
  ctx_.cells = cells_.data();
  ctx_.cell_count = cells_.size();
  ctx_.global = &global_;
  ctx_.boundaries = tallies_.data();
  ctx_.boundary_count = system_.geometry == Geometry::slab ? 2 : 0;
  ctx_.energy_ledger = ledger_.data();
  ctx_.energy_ledger_size = ledger_.size();
  ctx_.collision_tallies = tallies_total_.empty() ? nullptr : tallies_total_.data();
  ctx_.collision_tally_count = tallies_total_.size();
  begin_diagnostics();
  report_layout(attributes, outputs_);  // what the memory estimate counts (validate)
  if (setup == Setup::full) sample_and_record(true);  // the initial state is the first record of every diagnostic
  if (setup == Setup::restore) load(*state);
}

// Layers sized to the local mean free path: until the transient ends, the pipeline's count of
// equal widths, but given as edges from the start, so that a plugin sees in begin() that this
// run's layers are not uniform (SystemInfo::layer_edges non-null) and can refuse it there.
void Engine::open_layers() {
  if (!adaptive_layers() || system_.geometry != Geometry::slab) return;
  const std::size_t m = system_.cells;
  const double ly = system_.box[1], half = 0.5 * ly;
  layer_edges_.resize(m + 1);
  for (std::size_t I = 0; I <= m; ++I) layer_edges_[I] = -half + ly * static_cast<double>(I) / static_cast<double>(m);
  layer_edges_[0] = -half;
  layer_edges_[m] = half;
  system_.layer_edges = layer_edges_.data();
  // The profile's fine bins: 64 per layer (the densest layer is then still a few bins wide where
  // the density is up to ~16 times its mean), within [1024, 2^22].
  layer_profile_.assign(std::clamp<std::size_t>(64 * m, 1024, std::size_t{1} << 22), 0.0);
  layer_count_sums_.assign(m, 0.0);
}

// One sample of the density profile: every particle's y into the fine bins.
void Engine::sample_layer_profile() {
  const ParticleSpan p = store_.span();
  const double half = 0.5 * system_.box[1];
  const double scale = static_cast<double>(layer_profile_.size()) / system_.box[1];
  const std::size_t last = layer_profile_.size() - 1;
  double* const h = layer_profile_.data();
  for (std::size_t i = 0; i < p.count; ++i) {
    const double f = (p.y[i] + half) * scale;
    const std::size_t b = f > 0 ? std::min(static_cast<std::size_t>(f), last) : 0;
    h[b] += 1.0;
  }
  ++layer_profile_samples_;
}

// The end of the transient: edges at the quantiles I/M of the measured profile (linear within a
// fine bin), so that every layer holds the same mean number of particles N/M. With the dilute
// lambda(y) = 1/(sqrt(2) pi n(y) sigma^2) a layer's width in local mean free paths is
// sqrt(2) pi sigma^2 N_I / A, the same N/M for all: Ly/(M lambda0) <= the target. With max_width L
// each fine bin also weighs as if it held c = N w lambda0 / (bins L) particles more: a layer then
// spans one unit of n(y)/(n-bar w lambda0) + 1/L, so it is at most w local mean free paths and at
// most L wide (c = 0 without L: the same edges as before to the bit). Then frozen.
void Engine::set_layers_from_profile() {
  sample_layer_profile();  // the state at the end of the transient is one sample (the only one of a short one)
  const std::size_t m = system_.cells, bins = layer_profile_.size();
  const double ly = system_.box[1], half = 0.5 * ly, width = ly / static_cast<double>(bins);
  double particles = 0;
  for (const double c : layer_profile_) particles += c;
  const double per_bin = pipeline_.layers_max_width > 0
                             ? particles * pipeline_.layers_mean_free_paths * system_.mean_free_path0 /
                                   (static_cast<double>(bins) * pipeline_.layers_max_width)
                             : 0.0;
  const double total = particles + per_bin * static_cast<double>(bins);
  std::vector<double> edges(m + 1);
  edges[0] = -half;
  edges[m] = half;
  double below = 0;  // weight of the bins before j
  std::size_t j = 0;
  for (std::size_t I = 1; I < m; ++I) {
    const double target = total * static_cast<double>(I) / static_cast<double>(m);
    while (j + 1 < bins && below + (layer_profile_[j] + per_bin) < target) below += layer_profile_[j++] + per_bin;
    const double in_bin = layer_profile_[j] + per_bin;
    const double f = in_bin > 0 ? std::clamp((target - below) / in_bin, 0.0, 1.0) : 0.5;
    edges[I] = -half + (static_cast<double>(j) + f) * width;
  }
  // Strictly increasing, and inside the slab, whatever the rounding.
  for (std::size_t I = 1; I < m; ++I) {
    if (!(edges[I] > edges[I - 1])) edges[I] = std::nextafter(edges[I - 1], half);
  }
  for (std::size_t I = m - 1; I >= 1; --I) {
    if (!(edges[I] < edges[I + 1])) edges[I] = std::nextafter(edges[I + 1], -half);
  }
  try {
    grid_.set_edges(edges);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(now_text() + ": system.layers: the layers sized from the density profile cannot be used: " +
                             e.what());
  }
  layer_edges_ = std::move(edges);
  system_.layer_edges = layer_edges_.data();
  layers_set_ = true;
  layers_set_time_tau0_ = ctx_.time_in_tau0();
  layer_profile_.assign(layer_profile_.size(), 0.0);
  // Every particle into its new layer, storage in the new layer order, and the new layers' moments
  // and majorants now (forcings and diagnostics read ctx.cells before the next moment update).
  reorder_by_layer();
  grid_.cell_moments(store_.span(), system_.number_density, cells_, global_, &pool_);
  collisions_.set_layer_majorants(cells_.data(), grid_.peculiar_speed_max(), global_.temperature, system_.mass);
  sampled_step_ = static_cast<std::uint64_t>(-1);
  double narrow = ly, wide = 0;
  for (std::size_t I = 0; I < m; ++I) {
    narrow = std::min(narrow, layer_edges_[I + 1] - layer_edges_[I]);
    wide = std::max(wide, layer_edges_[I + 1] - layer_edges_[I]);
  }
  // A layer holds total/m of the weight: at most that many particles (its width in local mean free
  // paths: the particles' share of Ly/lambda0) and that many bins' worth of per_bin.
  const double share = total / static_cast<double>(m);
  const std::string bound =
      per_bin > 0 ? fmt("each at most %.4g local mean free paths and %.4g lambda0 wide (targets %.4g and max_width "
                        "%.4g lambda0)",
                        share / particles * ly / system_.mean_free_path0,
                        share / per_bin * width / system_.mean_free_path0, pipeline_.layers_mean_free_paths,
                        pipeline_.layers_max_width / system_.mean_free_path0)
                  : fmt("each %.4g local mean free paths (target %.4g)",
                        ly / (static_cast<double>(m) * system_.mean_free_path0), pipeline_.layers_mean_free_paths);
  const std::string line =
      fmt("layers: set at t = %.4g tau0 from the density over t >= %.4g tau0 (%llu samples): %zu layers %.4g to %.4g "
          "lambda0 wide, %s",
          layers_set_time_tau0_, 0.5 * pipeline_.layers_after_tau0, static_cast<unsigned long long>(layer_profile_samples_),
          m, narrow / system_.mean_free_path0, wide / system_.mean_free_path0, bound.c_str());
  summary_.push_back(line);
  if (system_.realization == 0) std::fprintf(stderr, "%s\n", line.c_str());
}

// After the edges are set, at every moment update: each layer's count, for its mean width in local
// mean free paths at the end.
void Engine::tally_layer_widths() {
  for (std::size_t I = 0; I < cells_.size(); ++I) layer_count_sums_[I] += static_cast<double>(cells_[I].count);
  ++layer_count_samples_;
}

// delta y_I / lambda_I = sqrt(2) pi sigma^2 n_I delta y_I = N_I / (n-bar A lambda0), N_I the mean
// count since the edges were set (NaN before).
double Engine::layer_width_local(std::size_t I) const {
  if (!layers_set_ || layer_count_samples_ == 0) return std::nan("");
  const double mean_count = layer_count_sums_[I] / static_cast<double>(layer_count_samples_);
  return mean_count / (system_.number_density * system_.cross_section() * system_.mean_free_path0);
}

std::string Engine::layer_widths_text() const {
  if (!layers_set_)
    return fmt("layers: the run ended at t = %.4g tau0, before system.layers.after = %.4g tau0: the layers stayed "
               "equal",
               ctx_.time_in_tau0(), pipeline_.layers_after_tau0);
  double lo = INFINITY, hi = 0;
  for (std::size_t I = 0; I < system_.cells; ++I) {
    const double w = layer_width_local(I);
    lo = std::min(lo, w);
    hi = std::max(hi, w);
  }
  return fmt("layers: %zu, set at t = %.4g tau0; widths in local mean free paths (mean densities over %llu moment "
             "updates since): %.3g to %.3g (target %.4g)",
             system_.cells, layers_set_time_tau0_, static_cast<unsigned long long>(layer_count_samples_), lo, hi,
             pipeline_.layers_mean_free_paths);
}

namespace {
const char* role_of(PluginKind kind) {
  switch (kind) {
    case PluginKind::collision_rule: return "collision rule";
    case PluginKind::forcing: return "forcing";
    case PluginKind::boundary: return "boundary";
    case PluginKind::initial_state: return "initial state";
    case PluginKind::diagnostic: return "diagnostic";
  }
  return "plugin";
}
}  // namespace

// One site per plugin entry, for the fatal-signal handler: every text it points to is built here,
// once (site_texts_ is sized first, so that no string moves after a site points into it).
void Engine::build_sites() {
  const Pipeline& p = pipeline_;
  std::vector<const PluginUse*> uses{&p.initial_state, &p.collision};
  for (const auto& u : p.forcings) uses.push_back(&u);
  for (std::size_t s = 0; s < p.boundaries.size() && s < 2; ++s) uses.push_back(&p.boundaries[s]);
  for (const auto& u : p.diagnostics) uses.push_back(&u);
  site_texts_.reserve(uses.size());
  sites_.reserve(uses.size());
  for (const PluginUse* u : uses) {
    site_texts_.push_back(u->path + ", " + u->where.str());
    PluginCallSite site;
    site.plugin = u->plugin ? u->plugin->descriptor->name.c_str() : "?";
    site.role = u->plugin ? role_of(u->plugin->descriptor->kind) : "plugin";
    site.where = site_texts_.back().c_str();
    site.step = &ctx_.step;
    site.run = run_name_.c_str();
    sites_.push_back(site);
    site_uses_.push_back(u);
  }
}

const PluginCallSite& Engine::site_of(const PluginUse& use) const {
  for (std::size_t k = 0; k < site_uses_.size(); ++k)
    if (site_uses_[k] == &use) return sites_[k];
  static const PluginCallSite unknown{};
  return unknown;
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
    tally_names_ = collision_->tallies();
  } catch (const ParameterError& e) {
    throw std::runtime_error(where_text(u) + ": parameter '" + e.parameter() + "': " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(where_text(u) + ": " + e.what());
  }
  tallies_total_.resize(tally_names_.size());
  for (std::size_t k = 0; k < tally_names_.size(); ++k) tallies_total_[k].name = tally_names_[k].c_str();
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

// The energy ledger: collisions, every forcing (by its instance name), each y boundary.
void Engine::open_ledger() {
  ledger_names_.push_back("collisions");
  for (const auto& u : pipeline_.forcings) ledger_names_.push_back(u.instance_name);
  if (system_.geometry == Geometry::slab) {
    ledger_names_.push_back("y_min");
    ledger_names_.push_back("y_max");
  }
  ledger_.resize(ledger_names_.size());
  for (std::size_t k = 0; k < ledger_.size(); ++k) ledger_[k].stage = ledger_names_[k].c_str();
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
  lap_start_ = std::chrono::steady_clock::now();
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
  if (adaptive_layers() && !layers_set_) {
    const double t = ctx_.time_in_tau0();
    if (t >= pipeline_.layers_after_tau0) {
      set_layers_from_profile();  // with this step's positions, and new moments for the new layers
      lap(Stage::reorder);
    } else if (t >= 0.5 * pipeline_.layers_after_tau0 && ctx_.step % pipeline_.moments_every == 0) {
      sample_layer_profile();
      lap(Stage::moments);
    }
  }
  if (ctx_.step % pipeline_.moments_every == 0) {
    update_moments();
    if (layers_set_) tally_layer_widths();
    lap(Stage::moments);
  }
  sample_and_record(false);
  lap(Stage::diagnostics);
}

const char* Engine::stage_name(Stage s) {
  static const char* const names[] = {"forcings", "flight", "sort", "reorder", "collisions", "moments", "diagnostics"};
  return names[static_cast<int>(s)];
}

std::string Engine::stage_times_text(const StageSeconds& seconds) {
  std::vector<std::size_t> order;
  double total = 0;
  for (std::size_t k = 0; k < kStages; ++k) {
    total += seconds[k];
    if (seconds[k] > 0) order.push_back(k);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seconds[a] > seconds[b]; });
  std::string text = fmt("%.3g", total);
  for (std::size_t i = 0; i < order.size(); ++i)
    text += std::string(i == 0 ? " = " : ", ") + stage_name(static_cast<Stage>(order[i])) + " " +
            fmt("%.3g", seconds[order[i]]) + fmt(" (%.0f %%)", 100.0 * seconds[order[i]] / total);
  return text;
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
                               fmt(" (t = %.6g tau0", ctx_.time_in_tau0()) + (run_name_.empty() ? ")" : ", " + run_name_ + ")") +
                               ": the forcing produced invalid velocities");
    if (const std::size_t i = first_non_finite_velocity(span); i < span.count)
      throw std::runtime_error(where_text(pipeline_.forcings[index]) + " wrote a non-finite velocity" +
                               fmt(" (%g, %g, %g) for particle %u", span.vx[i], span.vy[i], span.vz[i], span.id[i]) +
                               " in apply() at step " + std::to_string(ctx_.step) +
                               fmt(" (t = %.6g tau0", ctx_.time_in_tau0()) + (run_name_.empty() ? ")" : ", " + run_name_ + ")") +
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
          (run_name_.empty() ? ")" : ", " + run_name_ + ")") +
          fmt(": more than %.0f times is absurd for one step (the step cannot resolve its heating); use a smaller "
              "run.time_step or a gentler forcing",
              kMaxForcingEnergyPerStep));
    ledger_[1 + index].energy += added;
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
      BoundaryTally& t = tallies_[s];
      t.hits += tally.sides[s].hits;
      for (int a = 0; a < 3; ++a) t.momentum[a] += tally.sides[s].momentum[a];
      t.energy += tally.sides[s].energy;
      ledger_[ledger_.size() - 2 + s].energy += tally.sides[s].energy;
    }
    if (!accelerations_.empty()) ledger_[1 + accelerations_[0]].energy += tally.acceleration_energy;
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
    ledger_[1 + accelerations_[0]].energy += energy + 0.5 * g2 * dt * dt * static_cast<double>(span.count);
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
  ledger_[0].energy = ctx_.collision_energy_change;
  for (std::size_t k = 0; k < tallies_total_.size(); ++k) tallies_total_[k].value += t.tallies[k];
}

// A non-finite velocity or energy found after a stage: named after the plugin that produced it.
// The collision rule's velocities and declared energy are checked every step (collide), a
// forcing's declared energy and velocities after every apply, a boundary's velocities at every
// hit (the mover); what is left (a plugin's save/load, the host itself) shows in the temperature
// of the moment update, every run.moments_every steps (run()).
void Engine::non_finite(const std::string& energy) const {
  const std::string at = fmt(" at step %llu (t = %.6g tau0", static_cast<unsigned long long>(ctx_.step),
                             ctx_.time_in_tau0()) +
                         (run_name_.empty() ? ")" : ", " + run_name_ + ")");
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
  if (adaptive_layers()) summary_.push_back(layer_widths_text());
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    try {
      PluginCall call(*slots_[k].site, "finish");
      slots_[k].object->finish(ctx_, outputs_[k]);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*slots_[k].use) + " failed at the end of the run: " + e.what());
    }
  }
  finish_energy_balance();
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
// stage declared or the host tallied; the residual is round-off for plugins that tell the truth.
void Engine::finish_energy_balance() {
  grid_.sampled_moments(store_.span(), system_.number_density, sampled_, &pool_);
  const double per = 1.0 / (static_cast<double>(system_.particles) * system_.initial_temperature);
  double added = 0;
  std::string parts;
  for (const auto& e : ledger_) {
    added += e.energy;
    parts += std::string(parts.empty() ? "" : ", ") + e.stage + " " + fmt("%.6g", e.energy * per);
  }
  const double change = sampled_.kinetic_energy - initial_energy_;
  summary_.push_back("energy per particle [T0]: E - E0 = " + fmt("%.6g", change * per) + " = " + parts +
                     " (residual " + fmt("%.2g", (change - added) * per) + ")");
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
  if (adaptive_layers()) {
    // The layers' edges as the rest of the run used them (equal widths if the run ended before
    // they were set), and each one's mean width in local mean free paths since.
    out.system["layers_target_mean_free_paths"] = pipeline_.layers_mean_free_paths;
    out.system["layers_set_at_tau0"] = layers_set_ ? layers_set_time_tau0_ : std::nan("");
    if (pipeline_.layers_max_width > 0)
      out.system["layers_max_width_lambda0"] = pipeline_.layers_max_width / system_.mean_free_path0;
    ParticleDataset edges{"layer_edges", "lambda0",
                          "the edges of the collision layers along y (layers + 1 values from -Ly/2 to +Ly/2), set "
                          "at layers_set_at_tau0 from the transient's density profile (system.layers: "
                          "{mean_free_paths, after}; equal widths before)",
                          1, {}, ""};
    for (const double e : layer_edges_) edges.data.push_back(e / system_.mean_free_path0);
    out.system_arrays.push_back(std::move(edges));
    ParticleDataset widths{"layer_width_local_mean_free_paths", "1",
                           "each layer's width over its local mean free path, delta y_I / lambda_I with lambda_I = "
                           "1/(sqrt(2) pi n_I sigma^2) and n_I its mean density over the moment updates after the "
                           "edges were set (NaN if they never were)",
                           1, {}, ""};
    for (std::size_t I = 0; I < system_.cells; ++I) widths.data.push_back(layer_width_local(I));
    out.system_arrays.push_back(std::move(widths));
  }
  for (const auto& e : ledger_) out.run[std::string("energy_added.") + e.stage] = e.energy;
  for (std::size_t s = 0; s < ctx_.boundary_count; ++s) {
    const std::string side = s == 0 ? "y_min" : "y_max";
    const BoundaryTally& t = tallies_[s];
    out.run["boundary." + side + ".hits"] = static_cast<double>(t.hits);
    out.run["boundary." + side + ".momentum_x"] = t.momentum[0];
    out.run["boundary." + side + ".momentum_y"] = t.momentum[1];
    out.run["boundary." + side + ".momentum_z"] = t.momentum[2];
    out.run["boundary." + side + ".energy"] = t.energy;
  }
  out.plugins = plugin_provenance(pipeline_);
  out.diagnostics = outputs_;
  if (pipeline_.output_particles) out.particles = particle_datasets(store_.span(), system_);
  return out;
}

}  // namespace gdsmc::host
