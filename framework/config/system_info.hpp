// What plugins see of a pipeline's system (SDK SystemInfo): built from the configuration for a
// given particle count and realization.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include <gdsmc/context.hpp>

#include "config/pipeline.hpp"

namespace gdsmc::host {

// The system of `p` with `particles` particles (homogeneous: a cube of volume N/n; slab: Ly given,
// Lx given or equal to Lz, Lx Ly Lz = N/n, 000 Eq. 4.2), as realization `realization` sees it.
// A mixture's species_count and species point into p.species_table.
SystemInfo system_info(const Pipeline& p, std::size_t particles, std::uint32_t realization);

// The most species a mixture may list (system.species).
inline constexpr std::size_t kMaxSpecies = 16;
// How many of `particles` particles each species gets: the counts given, or floor(x_s N) with the
// rest to the largest remainders (config/species_section.cpp). Particles with identity [0, N_0)
// are species 0, the next N_1 species 1, and so on.
std::vector<std::size_t> species_counts(const std::vector<SpeciesSpec>& species, std::size_t particles);

}  // namespace gdsmc::host
