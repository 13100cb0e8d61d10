// The engine's checkpoint state: what save() writes and load() reads back, in the one order that
// is the format of a run's state (docs/user-guide.md, "Checkpoints and resuming").
#include <gdsmc/state.hpp>

#include <stdexcept>

#include "engine/engine.hpp"

namespace gdsmc::host {

Engine::SavedProgress Engine::saved_progress(StateReader& in) {
  SavedProgress p;
  std::uint8_t finished = 0;
  in.read("engine.finished", finished);
  p.finished = finished != 0;
  in.read("engine.step", p.step);
  in.read("engine.clocks", p.clocks, 5);
  return p;
}

// The order of entries is the checkpoint format: load() reads exactly what save() writes.
void Engine::save(StateWriter& out) const {
  out.write("engine.finished", static_cast<std::uint8_t>(finished_));
  out.write("engine.step", ctx_.step);
  const double clocks[5] = {ctx_.time, ctx_.dt, ctx_.collision_energy_change, initial_energy_, energy_at_update_};
  out.write("engine.clocks", clocks, 5);
  const std::uint64_t counts[4] = {ctx_.collisions, ctx_.candidates, ctx_.majorant_exceeded, streams_.step()};
  out.write("engine.counts", counts, 4);
  const std::uint8_t flags[2] = {ctx_.in_average_window, steady_};
  out.write("engine.flags", flags, 2);
  out.write("engine.wall_seconds", wall_seconds_);
  out.write("engine.missed_collisions", missed_collisions_);
  out.write("engine.stage_seconds", clock_.seconds().data(), kStages);
  // A finished run keeps its particles only when they are part of the output.
  const std::uint8_t particles = !finished_ || pipeline_.output_particles;
  out.write("engine.has_particles", particles);
  if (particles) store_.save(out);
  std::vector<std::uint64_t> cell_counts;
  std::vector<double> cell_values;
  for (std::size_t k = 0; k <= cells_.size(); ++k) {
    const CellMoments& c = k == cells_.size() ? global_ : cells_[k];  // the cells, then the global moments
    cell_counts.push_back(c.count);
    cell_values.insert(cell_values.end(), {c.number_density, c.mean_velocity[0], c.mean_velocity[1], c.mean_velocity[2],
                                           c.temperature});
  }
  out.write("moments.count", cell_counts);
  out.write("moments.values", cell_values);
  out.write("moments.kinetic_energy", sampled_.kinetic_energy);
  if (species_mass()) out.write("moments.species", grid_.species_cell_values());  // a mixture's majorant scales
  walls_.save(out);
  collision_tallies_.save(out);
  ledger_.save(out);
  collisions_.save(out);
  diagnostics_.save(out);
  out.write("summary.lines", static_cast<std::uint64_t>(summary_.size()));
  for (const auto& line : summary_) out.write("summary.line", line);
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    BufferStateWriter plugin;
    try {
      objects_[k]->save_state(plugin);
    } catch (const std::exception& e) {
      throw std::runtime_error(where_text(*object_uses_[k]) + ": save_state failed: " + e.what());
    }
    out.write("plugin." + object_uses_[k]->path, plugin.bytes());
  }
  layers_.save(out);
}

// The moments of the last update (cells, global, a mixture's per species) as save() wrote them.
void Engine::load_moments(StateReader& in) {
  std::vector<std::uint64_t> cell_counts;
  std::vector<double> cell_values;
  in.read("moments.count", cell_counts);
  in.read("moments.values", cell_values);
  if (cell_counts.size() != cells_.size() + 1 || cell_values.size() != 5 * cell_counts.size())
    throw StateError("checkpoint entry 'moments': " + std::to_string(cell_counts.size()) + " cells where the system has " +
                     std::to_string(cells_.size()) + " (and the global moments)");
  for (std::size_t k = 0; k < cell_counts.size(); ++k) {
    CellMoments& c = k == cells_.size() ? global_ : cells_[k];
    c.count = cell_counts[k];
    const double* v = cell_values.data() + 5 * k;
    c.number_density = v[0];
    for (int a = 0; a < 3; ++a) c.mean_velocity[a] = v[1 + a];
    c.temperature = v[4];
  }
  in.read("moments.kinetic_energy", sampled_.kinetic_energy);
  if (species_mass()) {
    std::vector<double> species;
    in.read("moments.species", species);
    if (!grid_.set_species_cell_values(species))
      throw StateError("checkpoint entry 'moments.species': " + std::to_string(species.size()) +
                       " values where the mixture has " + std::to_string(3 * cells_.size() * system_.species_count));
  }
}

void Engine::load(StateReader& in) {
  const SavedProgress head = saved_progress(in);
  finished_ = head.finished;
  ctx_.step = head.step;
  ctx_.time = head.clocks[0];
  ctx_.dt = head.clocks[1];
  ctx_.collision_energy_change = head.clocks[2];
  initial_energy_ = head.clocks[3];
  energy_at_update_ = head.clocks[4];
  std::uint64_t counts[4];
  in.read("engine.counts", counts, 4);
  ctx_.collisions = counts[0];
  ctx_.candidates = counts[1];
  ctx_.majorant_exceeded = counts[2];
  streams_.set_step(counts[3]);
  std::uint8_t flags[2];
  in.read("engine.flags", flags, 2);
  ctx_.in_average_window = flags[0] != 0;
  steady_ = flags[1] != 0;
  in.read("engine.wall_seconds", wall_seconds_);
  in.read("engine.missed_collisions", missed_collisions_);
  in.read("engine.stage_seconds", clock_.seconds().data(), kStages);
  std::uint8_t particles = 0;
  in.read("engine.has_particles", particles);
  if (particles) {
    store_.load(in);
    if (grid_.is_slab()) grid_.sort(store_.cells(), store_.size(), &pool_);  // the layers' member lists
  } else if (!finished_) {
    throw StateError("checkpoint: an unfinished run without its particles");
  }
  load_moments(in);
  walls_.load(in);
  collision_tallies_.load(in);
  ledger_.load(in);
  collisions_.load(in);
  diagnostics_.load(in);
  std::uint64_t lines = 0;
  in.read("summary.lines", lines);
  if (lines > in.remaining()) throw StateError("checkpoint entry 'summary.lines': a damaged count");
  summary_.assign(static_cast<std::size_t>(lines), std::string());
  for (auto& line : summary_) in.read("summary.line", line);
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    std::vector<unsigned char> bytes;
    in.read("plugin." + object_uses_[k]->path, bytes);
    BufferStateReader plugin(bytes);
    try {
      objects_[k]->load_state(plugin);
    } catch (const std::exception& e) {
      throw StateError(where_text(*object_uses_[k]) + ": load_state failed: " + e.what());
    }
    if (!plugin.at_end())
      throw StateError(where_text(*object_uses_[k]) + ": load_state read " + std::to_string(bytes.size() - plugin.remaining()) +
                       " of the " + std::to_string(bytes.size()) + " bytes its save_state wrote (next entry '" +
                       plugin.peek_name() + "')");
  }
  layers_.load(in, [&](const std::vector<double>& edges) {
    try {
      grid_.set_edges(edges);
    } catch (const std::invalid_argument& e) {
      throw StateError(std::string("checkpoint entry 'layers.edges': ") + e.what());
    }
  });
}

}  // namespace gdsmc::host
