// The `sweep:` section: value axes (key.path: [values]) and named variants.
#include <set>

#include "config/sections.hpp"

namespace gdsmc::host {

namespace {

// Refuses a sweep key that cannot differ between cases: the study writes one output file, expands
// one sweep and searches one plugin path, so such a key would be silently ignored.
bool case_key(Checker& c, const std::string& key, const std::string& path, const YAML::Node& node) {
  const std::string section = key.substr(0, key.find_first_of(".["));
  if (section != "output" && section != "sweep" && section != "plugins") return true;
  const char* why = section == "output" ? "a study writes one output file with every case in it (set output.file, or -o)"
                    : section == "sweep" ? "a sweep cannot hold a sweep (add an axis beside this one)"
                                         : "every case uses the study's plugin search path (set plugins: at the top)";
  c.error(path, node, "'" + key + "' cannot vary between sweep cases: " + why +
                          "; a sweep varies keys under run, system, units, initial_state, collision, forcings, "
                          "boundaries and diagnostics");
  return false;
}

}  // namespace

void parse_sweep(Checker& c, const YAML::Node& sw, Pipeline& p) {
  if (!sw.IsMap()) {
    c.error("sweep", sw, "expected a mapping: key.path: [values...], or AXIS: {VARIANT: {key.path: value, ...}, ...}");
  } else {
    std::set<std::string> axes;
    for (auto it = sw.begin(); it != sw.end(); ++it) {
      const std::string name = it->first.Scalar();
      const std::string sub = "sweep." + name;
      if (!axes.insert(name).second) c.error(sub, it->first, "duplicate sweep axis '" + name + "'");
      SweepAxis axis;
      axis.name = name;
      const YAML::Node v = it->second;
      if (v.IsSequence() && !case_key(c, name, sub, it->first)) continue;
      if (v.IsSequence() && v.size() > 0) {
        for (std::size_t k = 0; k < v.size(); ++k) {
          YAML::Emitter e;
          e << YAML::Flow << v[k];
          axis.values.push_back({e.c_str(), {name + "=" + e.c_str()}, {c.where(item(sub, k), v[k])}});
        }
      } else if (v.IsMap() && v.size() > 0) {
        for (auto vt = v.begin(); vt != v.end(); ++vt) {
          SweepAxis::Value value{vt->first.Scalar(), {}, {}};
          if (!vt->second.IsMap()) {
            c.error(sub + "." + value.label, vt->second, "a named variant is a mapping of key.path: value overrides");
            continue;
          }
          for (auto ot = vt->second.begin(); ot != vt->second.end(); ++ot) {
            if (!case_key(c, ot->first.Scalar(), sub + "." + value.label + "." + ot->first.Scalar(), ot->first)) continue;
            YAML::Emitter e;
            e << YAML::Flow << ot->second;
            value.overrides.push_back(ot->first.Scalar() + "=" + e.c_str());
            value.where.push_back(c.where(sub + "." + value.label + "." + ot->first.Scalar(), ot->second));
          }
          axis.values.push_back(std::move(value));
        }
      } else {
        c.error(sub, v, "expected a non-empty list of values or a mapping of named variants");
        continue;
      }
      p.sweep.push_back(std::move(axis));
    }
  }
}

}  // namespace gdsmc::host
