// What plugins see of a pipeline's system (SDK SystemInfo): built from the configuration for a
// given particle count and realization.
#pragma once
#include <cstddef>
#include <cstdint>

#include <gdsmc/context.hpp>

#include "config/pipeline.hpp"

namespace gdsmc::host {

// The system of `p` with `particles` particles (homogeneous: a cube of volume N/n; slab: Ly given,
// Lx given or equal to Lz, Lx Ly Lz = N/n, 000 Eq. 4.2), as realization `realization` sees it.
SystemInfo system_info(const Pipeline& p, std::size_t particles, std::uint32_t realization);

}  // namespace gdsmc::host
