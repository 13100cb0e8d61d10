// Units of plugin parameters: what a value given in a unit is in reduced units.
#pragma once
#include <optional>
#include <string>

#include <gdsmc/params.hpp>

namespace gdsmc::host {

struct Pipeline;

// Convert a value given in `unit` for a parameter of dimension `d` into reduced units.
// Returns nullopt (and sets `valid` to the accepted units) for an unknown unit.
std::optional<double> to_reduced(double value, const std::string& unit, Dimension d, double lambda0, double tau0,
                                 double T0, double sigma, std::string& valid);

// Reference-unit factor of a dimension (what a bare number means), for range checks and defaults.
double reference_factor(Dimension d, const Pipeline& p);

}  // namespace gdsmc::host
