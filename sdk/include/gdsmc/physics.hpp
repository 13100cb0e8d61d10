// gdsmc SDK, physics toolkit: helpers that plugins share (moments of a span, formulas of kinetic
// theory, the HCS reservoir, wall laws, running statistics of series). Header-only and outside the
// ABI fingerprint: a plugin compiles in what it uses, and the toolkit may change without a new
// ABI version. Nothing here crosses the plugin boundary.
#pragma once
#include "gdsmc/gdsmc.hpp"
#include "gdsmc/physics/hcs_reservoir.hpp"
#include "gdsmc/physics/kinetic_theory.hpp"
#include "gdsmc/physics/moments.hpp"
#include "gdsmc/physics/series.hpp"
#include "gdsmc/physics/walls.hpp"
