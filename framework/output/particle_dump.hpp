// The final particle state as datasets (output.particles: true), in lambda0 and sqrt(2T0/m).
#pragma once
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/particles.hpp>

#include "output/records.hpp"

namespace gdsmc::host {

std::vector<ParticleDataset> particle_datasets(const ParticleSpan& s, const SystemInfo& system);

}  // namespace gdsmc::host
