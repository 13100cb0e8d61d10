// The `units:` key and the dimensional values written as bare numbers.
#include <string>

#include "config/sections.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

void parse_units(Checker& c, const YAML::Node& u, Pipeline& p) {
  if (u.IsScalar() && u.Scalar() == "explicit") p.units_explicit = true;
  else if (!(u.IsScalar() && u.Scalar() == "reference"))
    c.error("units", u,
            "valid: reference (the default: a bare number with a dimension is in the reference unit of that "
            "dimension, lambda0 for a length, tau0 for a time, ...) or explicit (every dimensional value must be "
            "written as {value: X, unit: U})");
}

bool read_bare(Checker& c, Pipeline& p, const std::string& path, const YAML::Node& node, double value,
               const Dimensions& d) {
  const SourceLocation at = c.where(path, node);
  if (p.units_explicit) {
    const std::string v = fmt("%.10g", value);
    c.error(at, path,
            v + " is a bare " + to_string(d) + " and the pipeline sets units: explicit: write {value: " + v +
                ", unit: " + reference_unit(d) +
                "} if it is in " + reference_unit(d) + " (what a bare number means without units: explicit), or "
                "give the unit it is in (`gdsmc plugins NAME` and docs/user-guide.md, \"Units\", list them)");
    return false;
  }
  p.bare_values.push_back({path, at, value, d});
  return true;
}

}  // namespace gdsmc::host
