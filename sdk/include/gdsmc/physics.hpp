// gdsmc SDK, physics toolkit: helpers that plugins share (moments of a span, per-bin moment
// accumulators, formulas of kinetic theory (one gas and binary mixtures), the least-squares line, the HCS
// reservoir, wall laws, per-species parameters and Maxwellians of mixtures, running statistics of
// series: window means, the error estimators BatchMeans and jackknife_error, the steady-state
// test; the units of outputs). Header-only and outside the ABI fingerprint: a plugin compiles in what it uses, and
// the toolkit may change without a new ABI version. Nothing here crosses the plugin boundary.
#pragma once
#include "gdsmc/gdsmc.hpp"
#include "gdsmc/physics/bins.hpp"
#include "gdsmc/physics/hcs_reservoir.hpp"
#include "gdsmc/physics/jackknife.hpp"
#include "gdsmc/physics/kinetic_theory.hpp"
#include "gdsmc/physics/line_fit.hpp"
#include "gdsmc/physics/mixture_maxwellian.hpp"
#include "gdsmc/physics/mixture_theory.hpp"
#include "gdsmc/physics/moments.hpp"
#include "gdsmc/physics/series.hpp"
#include "gdsmc/physics/species_values.hpp"
#include "gdsmc/physics/steady.hpp"
#include "gdsmc/physics/units.hpp"
#include "gdsmc/physics/walls.hpp"
