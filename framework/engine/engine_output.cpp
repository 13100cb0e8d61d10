// The run's output: its /system and /run attributes, the diagnostics' records and, with
// output.particles, the final particles (a decomposed run's gathered on rank 0).
#include "config/system_info.hpp"
#include "engine/engine.hpp"
#include "output/particle_dump.hpp"
#include "output/provenance.hpp"

namespace gdsmc::host {

// A mixture's species in /system (species.<name>.{index, mass, diameter, fraction, count}, mass in m
// and diameter in sigma) and its wall tallies per species in /run
// (boundary.<side>.<name>.{hits, momentum_x, momentum_y, momentum_z, energy}).
void Engine::write_species(CaseOutput& out) const {
  const std::vector<std::size_t> counts = species_counts(pipeline_.species, system_.particles);
  out.system["species_count"] = static_cast<double>(system_.species_count);
  for (std::size_t s = 0; s < system_.species_count; ++s) {
    const std::string key = std::string("species.") + system_.species[s].name + ".";
    out.system[key + "index"] = static_cast<double>(s);
    out.system[key + "mass"] = system_.species[s].mass;
    out.system[key + "diameter"] = system_.species[s].diameter;
    out.system[key + "fraction"] = system_.species[s].fraction;
    out.system[key + "count"] = static_cast<double>(counts[s]);
  }
  const BoundaryTally* tallies = walls_.species_data();
  for (std::size_t side = 0; tallies && side < 2; ++side)
    for (std::size_t s = 0; s < system_.species_count; ++s) {
      const BoundaryTally& t = tallies[side * system_.species_count + s];
      const std::string key = std::string(side == 0 ? "boundary.y_min." : "boundary.y_max.") + system_.species[s].name + ".";
      out.run[key + "hits"] = static_cast<double>(t.hits);
      out.run[key + "momentum_x"] = t.momentum[0];
      out.run[key + "momentum_y"] = t.momentum[1];
      out.run[key + "momentum_z"] = t.momentum[2];
      out.run[key + "energy"] = t.energy;
    }
}

CaseOutput Engine::output(const ParticleStager* stage) {
  if (ranks_) {  // rank 0, after run(): the particles of the last record, gathered
    if (!ranks_->root()) throw std::logic_error("Engine::output: a decomposed run's output is rank 0's");
    CaseOutput out;
    on_whole_serial([&] { out = output(stage); });
    return out;
  }
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
  out.diagnostics = diagnostics_.outputs();
  if (species_mass()) write_species(out);
  if (pipeline_.output_particles) {
    const ParticleSpan span = store_.span();
    std::vector<double> species;
    if (span.species) species.assign(span.species, span.species + span.count);
    out.particles = particle_datasets(span, system_, span.species ? species.data() : nullptr, stage);
  }
  return out;
}

}  // namespace gdsmc::host
