#include "config/units.hpp"

#include <cmath>
#include <vector>

#include "config/pipeline.hpp"

namespace gdsmc::host {

std::optional<double> to_reduced(double value, const std::string& unit, Dimension d, double lambda0, double tau0,
                                 double T0, double sigma, std::string& valid) {
  struct U {
    const char* name;
    double factor;
  };
  const double v0 = std::sqrt(2.0 * T0);  // m = 1
  std::vector<U> units;
  switch (d) {
    case Dimension::none: units = {{"1", 1.0}}; break;
    case Dimension::length: units = {{"lambda0", lambda0}, {"sigma", sigma}, {"reduced", 1.0}}; break;
    case Dimension::time: units = {{"tau0", tau0}, {"reduced", 1.0}}; break;
    case Dimension::inverse_time: units = {{"1/tau0", 1.0 / tau0}, {"tau0^-1", 1.0 / tau0}, {"reduced", 1.0}}; break;
    case Dimension::temperature: units = {{"T0", T0}, {"reduced", 1.0}}; break;
    case Dimension::velocity: units = {{"sqrt(2T0/m)", v0}, {"reduced", 1.0}}; break;
    case Dimension::acceleration: units = {{"2T0/(m*lambda0)", 2.0 * T0 / lambda0}, {"reduced", 1.0}}; break;
  }
  for (const auto& u : units)
    if (unit == u.name) return value * u.factor;
  valid.clear();
  for (const auto& u : units) valid += (valid.empty() ? "" : ", ") + std::string(u.name);
  return std::nullopt;
}

double reference_factor(Dimension d, const Pipeline& p) {
  std::string valid;
  const char* ref = d == Dimension::length ? "lambda0"
                    : d == Dimension::time ? "tau0"
                    : d == Dimension::inverse_time ? "1/tau0"
                    : d == Dimension::temperature ? "T0"
                    : d == Dimension::velocity ? "sqrt(2T0/m)"
                    : d == Dimension::acceleration ? "2T0/(m*lambda0)"
                                                   : "1";
  return *to_reduced(1.0, ref, d, p.mean_free_path0(), p.time_unit0(), p.temperature, p.sigma, valid);
}

}  // namespace gdsmc::host
