// Units of plugin parameters: what a value given in a unit is in reduced units.
//
// A unit is "reduced", "1" (dimensionless), or an expression in the reference units lambda0,
// sigma, tau0, T0 and m: products (`*` or a space), quotients (`/`), powers (`^2`, `^-1`,
// `^(1/2)`), `sqrt(...)`, parentheses and numeric factors ("2T0/(m*lambda0)", "T0/tau0",
// "lambda0^2 tau0^-3", "sqrt(2T0/m)"). Its dimension must equal the parameter's after a
// temperature is reduced to an energy (k_B = 1: mass length^2 / time^2).
#pragma once
#include <cmath>
#include <optional>
#include <string>

#include <gdsmc/params.hpp>

namespace gdsmc::host {

struct Pipeline;

// The reference scales in reduced units (m = 1); Ly is the gap of a slab (0: none, and the unit
// name Ly is then unknown).
struct UnitScales {
  double lambda0 = 1, tau0 = 1, T0 = 1, sigma = 1, Ly = 0;
};
UnitScales unit_scales(const Pipeline& p);

// Convert a value given in `unit` for a parameter of dimension `d` into reduced units.
// Returns nullopt for an unknown unit or one of another dimension, with `why` saying which and
// naming the valid units.
std::optional<double> to_reduced(double value, const std::string& unit, const Dimensions& d, const UnitScales& s,
                                 std::string& why);
// The SDK 2.0 signature, kept for callers that pass the scales one by one.
std::optional<double> to_reduced(double value, const std::string& unit, const Dimensions& d, double lambda0, double tau0,
                                 double T0, double sigma, std::string& why);

// The reference unit of a dimension as text ("lambda0^2 tau0^-3", "tau0^-1", "1"): what a bare
// number means.
std::string reference_unit(const Dimensions& d);

// A value of dimension `d` (`reduced`, in reduced units) in the units a reader may have meant:
// the reference unit, reduced units, and the thermal units on sigma and (slab) on Ly, lengths in
// sigma or Ly and speeds in sqrt(2T0/m): "12 lambda0 tau0^-2 = 0.0129 reduced = 0.0129 2T0/(m
// sigma) = 12 2T0/(m Ly)". Every unit written is one to_reduced() accepts.
std::string common_units_text(double reduced, const Dimensions& d, const UnitScales& s);

// The hard-sphere mean free time at T0 in tau0: lambda0 / <|v|>, <|v|> = sqrt(8 T0 / (pi m)).
inline const double kMeanFreeTimeTau0 = 0.5 * std::sqrt(M_PI);

// Reference-unit factor of a dimension (what a bare number means), for range checks and defaults:
// lambda0^length tau0^time T0^temperature m^mass in reduced units.
double reference_factor(const Dimensions& d, const Pipeline& p);
double reference_factor(const Dimensions& d, const UnitScales& s);
// The shorthands (Dimension::velocity, ...) as well.
inline double reference_factor(Dimension d, const Pipeline& p) { return reference_factor(dimensions_of(d), p); }
inline std::optional<double> to_reduced(double value, const std::string& unit, Dimension d, double lambda0, double tau0,
                                        double T0, double sigma, std::string& why) {
  return to_reduced(value, unit, dimensions_of(d), lambda0, tau0, T0, sigma, why);
}

}  // namespace gdsmc::host
