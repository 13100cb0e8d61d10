// gdsmc SDK, physics toolkit: per-species values of a plugin parameter in a mixture (SDK 6.5,
// SystemInfo::species), written as one string, e.g.
//   species_temperatures: "heavy: 2.0"          species_accommodation: "light: 1, heavy: 0.5"
// "name: value" entries separated by commas or semicolons; a species not listed takes the plugin's
// one-species value. The syntax and the range of the values are checked when the plugin is built
// (parse_species_values, in its constructor: the error names the parameter), the names when the
// system is known (species_values, in begin() or generate(): the error lists the run's species).
// Values are bare numbers in the unit the parameter's documentation gives (a temperature in T0):
// the host converts only whole parameters, so the plugin multiplies by its unit itself.
#pragma once
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <vector>

#include "gdsmc/context.hpp"
#include "gdsmc/params.hpp"

namespace gdsmc {

struct SpeciesValue {
  std::string species;
  double value = 0;
};

// The allowed values of a per-species parameter: [lower, upper], lower excluded if lower_open.
struct SpeciesValueRange {
  double lower = -HUGE_VAL, upper = HUGE_VAL;
  bool lower_open = false;
  bool contains(double v) const { return (lower_open ? v > lower : v >= lower) && v <= upper; }
  std::string text() const {
    auto num = [](double v) { return std::isinf(v) ? std::string(v > 0 ? "inf" : "-inf") : value_text(v); };
    return std::string(lower_open ? "(" : "[") + num(lower) + ", " + num(upper) + (std::isinf(upper) ? ")" : "]");
  }
};

namespace detail {
inline std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\n\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\n\r") - b + 1);
}
}  // namespace detail

// Parses "name: value, name: value" (an empty string: no entries). Throws ParameterError naming
// `parameter` on a malformed entry, a repeated name or a value outside `range`.
inline std::vector<SpeciesValue> parse_species_values(const std::string& plugin, const std::string& parameter,
                                                      const std::string& text, const SpeciesValueRange& range) {
  std::vector<SpeciesValue> out;
  const std::string form = "; write \"name: value\" entries separated by commas, e.g. \"heavy: 2.0, light: 1.0\"";
  std::vector<std::string> pieces(1);
  for (char c : text) {
    if (c == ',' || c == ';') pieces.emplace_back();
    else pieces.back() += c;
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const std::string entry = detail::trimmed(pieces[k]);
    if (entry.empty()) {
      if (pieces.size() == 1 || (k + 1 == pieces.size() && k > 0)) continue;  // "" or a trailing separator
      throw ParameterError(parameter, plugin + ": " + parameter + ": an empty entry in \"" + text + "\"" + form);
    }
    const std::size_t colon = entry.find(':');
    if (colon == std::string::npos)
      throw ParameterError(parameter, plugin + ": " + parameter + ": entry \"" + entry + "\" has no ':'" + form);
    SpeciesValue v;
    v.species = detail::trimmed(entry.substr(0, colon));
    const std::string number = detail::trimmed(entry.substr(colon + 1));
    char* stop = nullptr;
    errno = 0;
    v.value = std::strtod(number.c_str(), &stop);
    if (v.species.empty() || number.empty() || *stop != '\0' || errno == ERANGE || !std::isfinite(v.value))
      throw ParameterError(parameter, plugin + ": " + parameter + ": entry \"" + entry +
                                          "\" is not a species name and a finite number" + form);
    if (!range.contains(v.value))
      throw ParameterError(parameter, plugin + ": " + parameter + ": the value of species '" + v.species + "' (" +
                                          value_text(v.value) + ") is outside " + range.text());
    for (const auto& o : out)
      if (o.species == v.species)
        throw ParameterError(parameter, plugin + ": " + parameter + ": species '" + v.species + "' is given twice");
    out.push_back(std::move(v));
  }
  return out;
}

// The run's species names, "light, heavy" ("" in a run without system.species).
inline std::string species_names(const SystemInfo& sys) {
  std::string s;
  if (!sys.species) return s;
  for (std::size_t k = 0; k < sys.species_count; ++k) s += (k ? ", " : "") + std::string(sys.species[k].name);
  return s;
}

// One value per species of the run (species_count entries): `fallback` times `unit`, or the given
// value times `unit` for a species listed in `given`. Throws ParameterError naming `parameter` for
// a name that is not one of the run's species, listing them.
inline std::vector<double> species_values(const SystemInfo& sys, const std::string& plugin, const std::string& parameter,
                                          const std::vector<SpeciesValue>& given, double fallback, double unit = 1.0) {
  std::vector<double> values(sys.species_count, fallback);
  for (const auto& g : given) {
    std::size_t found = sys.species_count;
    for (std::size_t k = 0; sys.species && k < sys.species_count; ++k)
      if (g.species == sys.species[k].name) found = k;
    if (found == sys.species_count)
      throw ParameterError(parameter, plugin + ": " + parameter + ": no species '" + g.species + "' in this run; " +
                                          (sys.species ? "the species are: " + species_names(sys)
                                                       : std::string("the run has a single species (per-species values "
                                                                     "need system.species)")));
    values[found] = g.value * unit;
  }
  return values;
}

// True when particles of the run may differ in mass from SystemInfo::mass: a mixture, or a single
// declared species whose mass is not the reference mass. Plugins take their per-species code path
// only then (or when a per-species parameter is given), so that a one-species run stays
// bit-identical to what it was before SDK 6.5.
inline bool has_species_masses(const SystemInfo& sys) {
  return sys.species_count > 1 || sys.species_mass(0) != sys.mass;
}

}  // namespace gdsmc
