// The final particle state as datasets (output.particles: true), in lambda0 and sqrt(2T0/m).
#pragma once
#include <functional>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/particles.hpp>

#include "output/records.hpp"

namespace gdsmc::host {

// Positions, velocities and every declared attribute, as views of the particle store.
// `species`: a mixture's species index of every particle as doubles (written as the column
// "species"), nullptr with one species.
std::vector<ParticleColumn> particle_columns(const ParticleSpan& s, const SystemInfo& system,
                                             const double* species = nullptr);

// What writes the final particles into the run's output file as the run ends, in bounded chunks
// straight from the store, and returns the datasets naming where they are (OutputFile::stager).
using ParticleStager = std::function<std::vector<ParticleDataset>(const std::vector<ParticleColumn>&)>;

// The datasets of particle_columns: handed to `stage` when given, else copied into memory.
std::vector<ParticleDataset> particle_datasets(const ParticleSpan& s, const SystemInfo& system, const double* species,
                                               const ParticleStager* stage);

}  // namespace gdsmc::host
