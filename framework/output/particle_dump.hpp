// The final particle state as datasets (output.particles: true), in lambda0 and sqrt(2T0/m).
#pragma once
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/particles.hpp>

#include "output/records.hpp"

namespace gdsmc::host {

// Positions, velocities and every declared attribute, as views of the particle store.
std::vector<ParticleColumn> particle_columns(const ParticleSpan& s, const SystemInfo& system);

// The datasets of particle_columns: written at once into the run's open output file
// (OutputFile::current()), in bounded chunks straight from the store, or, with no file open,
// copied into memory.
std::vector<ParticleDataset> particle_datasets(const ParticleSpan& s, const SystemInfo& system);

}  // namespace gdsmc::host
