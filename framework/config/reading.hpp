// What `validate` prints, and `run` before its first step, about how the pipeline's numbers were
// read: so that a number written in another unit than the one it is read in shows before the run
// (docs/user-guide.md, "Units").
#pragma once
#include <string>
#include <vector>

#include "config/pipeline.hpp"

namespace gdsmc::host {

// One line per dimensional value written as a bare number: its key and place, what it was read
// as (its dimension and unit) and its value in the other common units.
std::vector<std::string> bare_value_lines(const Pipeline& p);

// The dimensionless numbers of the system the host defines: n sigma^3 and the packing fraction
// phi = pi n sigma^3/6, lambda0 and tau0, for a slab Ly in sigma and lambda0, Kn = lambda0/Ly and
// the particles per layer N/M, and the time step over the mean free time of hard spheres at T0.
std::string system_numbers_line(const Pipeline& p);

}  // namespace gdsmc::host
