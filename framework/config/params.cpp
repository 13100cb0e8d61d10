#include "config/params.hpp"

#include <algorithm>
#include <set>

#include "config/sections.hpp"
#include "config/suggest.hpp"
#include "config/units.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {

// "plugin 'NAME' (FILE)": the library a message is about, so that a plugin shadowed by another
// file of the same name is seen at once.
std::string plugin_ref(const std::string& name, const LoadedPlugin& lp) {
  return "plugin '" + name + "' (" + lp.file.string() + ")";
}

// The plugin search path a lookup went through, as given.
std::string searched_text(const PluginRegistry& r) {
  std::vector<std::string> dirs;
  for (const auto& d : r.searched()) dirs.push_back(d.string());
  return dirs.empty() ? "nothing" : join(dirs, ", ");
}

// The plugin an entry names (a bare name or {plugin: NAME, ...}), of the right kind; `map` is set
// to the entry when it is a mapping.
const LoadedPlugin* resolve_plugin(Checker& c, const PluginRegistry& plugins, const YAML::Node& node,
                                   const std::string& path, PluginKind kind, YAML::Node& map, std::string& name) {
  if (node.IsScalar()) {
    name = node.Scalar();
  } else if (node.IsMap() && node["plugin"] && node["plugin"].IsScalar()) {
    name = node["plugin"].Scalar();
    map.reset(node);
  } else {
    c.error(path, node, std::string("expected a plugin entry such as {plugin: NAME, ...} naming a ") + to_string(kind) +
                            " plugin");
    return nullptr;
  }
  const LoadedPlugin* lp = plugins.find(name);
  Checker::About about(c, name);
  if (!lp) {
    auto close = closest_names(name, plugins.names_of_kind(kind));
    if (close.empty()) close = closest_names(name, plugins.names());
    const auto all = plugins.names_of_kind(kind);
    c.error(path, node, "unknown " + std::string(to_string(kind)) + " plugin '" + name + "'" +
                            (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                            " (installed " + to_string(kind) + " plugins: " + (all.empty() ? "none" : join(all, ", ")) +
                            "; searched: " + searched_text(plugins) + "; `gdsmc plugins` lists them)");
    return nullptr;
  }
  if (lp->descriptor->kind != kind) {
    c.error(path, node, plugin_ref(name, *lp) + " is a " + to_string(lp->descriptor->kind) + " plugin, but a " +
                            to_string(kind) + " plugin is needed here");
    return nullptr;
  }
  return lp;
}

// The entry's own keys: unknown or duplicate keys, `name:`, and a diagnostic's sampling periods.
bool check_entry_keys(Checker& c, const Pipeline& p, const YAML::Node& map, const std::string& path, PluginKind kind,
                      const std::string& name, const std::vector<ParamSpec>& schema, PluginUse& use) {
  bool ok = true;
  if (!map) {
    if (kind_info(kind).writes_output) {
      use.sample_every = p.sample_every;
      use.record_every = p.record_every;
    }
    return ok;
  }
  const auto& reserved = reserved_keys(kind);
  std::vector<std::string> allowed = reserved;
  for (const auto& s : schema) allowed.push_back(s.name);
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.Scalar();
    const std::string sub = path + "." + key;
    if (!seen.insert(key).second) {
      c.error(sub, it->first, "duplicate key '" + key + "'");
      ok = false;
    }
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::vector<std::string> names;
      for (const auto& s : schema) names.push_back(s.name);
      auto close = closest_names(key, names);
      Checker::About about(c, name, key);
      c.error(sub, it->first, plugin_ref(name, *use.plugin) + " has no parameter '" + key + "'" +
                                  (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                                  " (parameters: " + (names.empty() ? "none" : join(names, ", ")) + ")");
      ok = false;
    }
  }
  if (map["name"]) {
    if (map["name"].IsScalar() && !map["name"].Scalar().empty()) use.instance_name = map["name"].Scalar();
    else c.error(path + ".name", map["name"], "expected a name for the output group");
  }
  if (kind_info(kind).writes_output) {
    use.sample_every = p.sample_every;
    use.record_every = p.record_every;
    for (auto [key, field] : {std::pair{"sample_every", &use.sample_every}, std::pair{"record_every", &use.record_every}}) {
      if (!map[key]) continue;
      auto v = c.integer(map[key], path + "." + key);
      if (v && *v >= 1) *field = static_cast<std::uint64_t>(*v);
      else if (v) c.error(path + "." + key, map[key], std::string(key) + " must be a whole number of steps >= 1");
    }
  }
  return ok;
}

// A real parameter given as a number (reference units) or as {value, unit}.
std::optional<double> convert_real(Checker& c, Pipeline& p, const ParamSpec& spec, const YAML::Node& v,
                                   const std::string& sub, const std::string& who) {
  const SourceLocation at = c.where(sub, v);
  std::optional<double> value;
  double reference_value = 0;
  if (v.IsMap()) {
    if (spec.dimension.dimensionless()) {
      c.error(sub, v, who + " is dimensionless: give a plain number");
      return std::nullopt;
    }
    c.check_keys(v, sub, {"value", "unit"});
    if (!v["value"] || !v["unit"]) {
      c.error(sub, v, who + ": expected {value: NUMBER, unit: UNIT}");
      return std::nullopt;
    }
    auto num = c.real(v["value"], sub + ".value");
    if (!num) return std::nullopt;
    std::string why;
    value = to_reduced(*num, v["unit"].Scalar(), spec.dimension, unit_scales(p), why);
    if (!value) {
      c.error(sub + ".unit", v["unit"], "unknown unit '" + v["unit"].Scalar() + "' for " + who + ": " + why);
      return std::nullopt;
    }
    reference_value = *value / reference_factor(spec.dimension, p);
  } else {
    auto num = c.real(v, sub);
    if (!num) return std::nullopt;
    if (!spec.dimension.dimensionless() && !read_bare(c, p, sub, v, *num, spec.dimension)) return std::nullopt;
    reference_value = *num;
    value = *num * reference_factor(spec.dimension, p);
  }
  const bool low = spec.min && (spec.min_inclusive ? reference_value < *spec.min : reference_value <= *spec.min);
  const bool high = spec.max && (spec.max_inclusive ? reference_value > *spec.max : reference_value >= *spec.max);
  if (low || high) {
    c.error(at, sub, "value " + value_text(reference_value) + " is out of range for " + who,
            spec.range_text() + (spec.dimension.dimensionless() ? "" : " in " + reference_unit(spec.dimension)));
    return std::nullopt;
  }
  return value;
}

// One given parameter value, checked against its spec and stored in reduced units.
bool convert_param(Checker& c, Pipeline& p, const ParamSpec& spec, const YAML::Node& v, const std::string& sub,
                   const std::string& name, PluginUse& use) {
  const std::optional<ParamValue> value =
      read_value(c, p, spec, v, sub, "parameter '" + spec.name + "' of " + plugin_ref(name, *use.plugin));
  if (value) use.params.set(spec.name, *value, c.where(sub, v));
  return value.has_value();
}

// A parameter the entry does not give: its default in reduced units, or an error when it has none.
bool default_param(Checker& c, const Pipeline& p, const ParamSpec& spec, const std::string& path,
                   const std::string& name, PluginUse& use) {
  if (!spec.default_) {
    c.error(use.where, path, plugin_ref(name, *use.plugin) + " needs parameter '" + spec.name + "' (" + spec.doc + ")");
    return false;
  }
  ParamValue dv = *spec.default_;
  if (spec.type == ParamType::real && !spec.dimension.dimensionless())
    dv = std::get<double>(dv) * reference_factor(spec.dimension, p);
  use.params.set(spec.name, dv, use.where, true);
  return true;
}

// Let the plugin refuse what its schema cannot express.
bool test_construct(Checker& c, const LoadedPlugin& lp, const std::string& path, const std::string& name,
                    const PluginUse& use) {
  try {
    (void)create_object(lp, use.params);
  } catch (const ParameterError& e) {
    const SourceLocation at = use.params.has(e.parameter()) ? use.params.entry(e.parameter()).where : use.where;
    Checker::About about(c, name, e.parameter());
    c.plugin_error(at, path + "." + e.parameter(), ErrorOrigin::refused_by_plugin,
                   plugin_ref(name, lp) + " refused parameter '" + e.parameter() + "': " + e.what());
    return false;
  } catch (const std::exception& e) {
    Checker::About about(c, name);
    c.plugin_error(use.where, path, ErrorOrigin::plugin_failed, plugin_ref(name, lp) + " failed to construct: " + e.what());
    return false;
  }
  return true;
}

}  // namespace

std::optional<ParamValue> read_value(Checker& c, Pipeline& p, const ParamSpec& spec, const YAML::Node& v,
                                     const std::string& sub, const std::string& who) {
  switch (spec.type) {
    case ParamType::real:
      if (auto value = convert_real(c, p, spec, v, sub, who)) return *value;
      return std::nullopt;
    case ParamType::integer: {
      auto num = c.integer(v, sub);
      if (!num) return std::nullopt;
      const double d = static_cast<double>(*num);
      if ((spec.min && (spec.min_inclusive ? d < *spec.min : d <= *spec.min)) ||
          (spec.max && (spec.max_inclusive ? d > *spec.max : d >= *spec.max))) {
        c.error(c.where(sub, v), sub, "value " + std::to_string(*num) + " is out of range for " + who, spec.range_text());
        return std::nullopt;
      }
      return *num;
    }
    case ParamType::boolean:
      if (auto b = c.boolean(v, sub)) return *b;
      return std::nullopt;
    case ParamType::string:
    case ParamType::choice: {
      if (!v.IsScalar()) {
        c.error(sub, v, who + ": expected text, got " + Checker::describe(v));
        return std::nullopt;
      }
      const std::string s = v.Scalar();
      if (spec.type == ParamType::choice && std::find(spec.choices.begin(), spec.choices.end(), s) == spec.choices.end()) {
        auto close = closest_names(s, spec.choices);
        c.error(sub, v, "'" + s + "' is not valid for " + who,
                spec.range_text() + (close.empty() ? "" : " (did you mean " + join(close, ", ") + "?)"));
        return std::nullopt;
      }
      return s;
    }
  }
  return std::nullopt;
}

std::optional<PluginUse> check_plugin(Checker& c, const std::shared_ptr<const PluginRegistry>& plugins, Pipeline& p,
                                      const YAML::Node& node, const std::string& path, PluginKind kind) {
  PluginUse use;
  use.path = path;
  use.where = c.where(path, node);
  YAML::Node map;
  std::string name;
  const LoadedPlugin* lp = resolve_plugin(c, *plugins, node, path, kind, map, name);
  if (!lp) return std::nullopt;
  use.plugin = std::shared_ptr<const LoadedPlugin>(plugins, lp);  // shares the registry's lifetime
  use.instance_name = name;
  const auto& schema = lp->descriptor->parameters;
  Checker::About about(c, name);
  bool ok = check_entry_keys(c, p, map, path, kind, name, schema, use);
  for (const auto& spec : schema) {
    Checker::About about_parameter(c, name, spec.name);
    const std::string sub = path + "." + spec.name;
    const YAML::Node v = map ? map[spec.name] : YAML::Node();
    const bool good = v ? convert_param(c, p, spec, v, sub, name, use) : default_param(c, p, spec, path, name, use);
    ok = ok && good;
  }
  if (!ok) return std::nullopt;
  if (!test_construct(c, *lp, path, name, use)) return std::nullopt;
  return use;
}

}  // namespace gdsmc::host
