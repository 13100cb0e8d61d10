#include "pipeline.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string s;
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? sep : "") + v[k];
  return s;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// Reads a YAML document and records every problem with its location.
class Checker {
 public:
  Checker(fs::path file, std::vector<std::string> overrides) : file_(std::move(file)), overrides_(std::move(overrides)) {}

  // "a.b[2].c" and "a.b.2.c" -> "a.b[2].c", the form the checker uses for paths.
  static std::string canonical(std::string key) {
    std::replace(key.begin(), key.end(), '[', '.');
    key.erase(std::remove(key.begin(), key.end(), ']'), key.end());
    std::string out, part;
    std::stringstream ss(key);
    while (std::getline(ss, part, '.')) {
      if (part.empty()) continue;
      const bool index = !out.empty() && std::all_of(part.begin(), part.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
      out += index ? "[" + part + "]" : (out.empty() ? "" : ".") + part;
    }
    return out;
  }

  SourceLocation where(const std::string& path, const YAML::Node& node) const {
    for (const auto& o : overrides_) {
      const std::string key = canonical(o.substr(0, o.find('=')));
      if (path == key || path.rfind(key + ".", 0) == 0 || path.rfind(key + "[", 0) == 0)
        return SourceLocation{"--set " + o, 0, 0};
    }
    const YAML::Mark m = node.Mark();
    if (m.line < 0) return SourceLocation{file_.string(), 0, 0};
    return SourceLocation{file_.string(), m.line + 1, m.column + 1};  // yaml-cpp marks are 0-based
  }
  void error(const SourceLocation& at, const std::string& path, const std::string& message) {
    errors_.push_back(at.str() + ": " + (path.empty() ? "" : path + ": ") + message);
  }
  void error(const std::string& path, const YAML::Node& node, const std::string& message) {
    error(where(path, node), path, message);
  }
  const std::vector<std::string>& errors() const { return errors_; }

  // Report keys not in `allowed` (with close spellings) and duplicate keys.
  void check_keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed) {
    std::set<std::string> seen;
    for (auto it = map.begin(); it != map.end(); ++it) {
      const std::string key = it->first.Scalar();
      const std::string sub = path.empty() ? key : path + "." + key;
      if (!seen.insert(key).second) error(sub, it->first, "duplicate key '" + key + "'");
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        auto close = closest_names(key, allowed);
        error(sub, it->first, "unknown key '" + key + "'" +
                                  (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                                  " (valid keys: " + join(allowed, ", ") + ")");
      }
    }
  }

  std::optional<double> real(const YAML::Node& n, const std::string& path) {
    double v;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
      error(path, n, "expected a number, got " + describe(n));
      return std::nullopt;
    }
    return v;
  }
  std::optional<std::int64_t> integer(const YAML::Node& n, const std::string& path) {
    double v;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v) || v != std::floor(v) ||
        std::fabs(v) > 9.0e15) {
      error(path, n, "expected a whole number, got " + describe(n));
      return std::nullopt;
    }
    return static_cast<std::int64_t>(v);
  }
  std::optional<bool> boolean(const YAML::Node& n, const std::string& path) {
    bool v;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
      error(path, n, "expected true or false, got " + describe(n));
      return std::nullopt;
    }
    return v;
  }
  static std::string describe(const YAML::Node& n) {
    if (n.IsMap()) return "a mapping";
    if (n.IsSequence()) return "a list";
    if (n.IsNull()) return "nothing";
    return "'" + n.Scalar() + "'";
  }

 private:
  fs::path file_;
  std::vector<std::string> overrides_;
  std::vector<std::string> errors_;
};

// Apply "a.b[2].c=value" (or a.b.2.c) to the document.
void apply_override(YAML::Node& root, const std::string& assignment, std::vector<std::string>& errors) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    errors.push_back("--set " + assignment + ": expected key.path=value");
    return;
  }
  std::string path = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  std::replace(path.begin(), path.end(), '[', '.');
  path.erase(std::remove(path.begin(), path.end(), ']'), path.end());
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');)
    if (!p.empty()) parts.push_back(p);
  YAML::Node value_node;
  try {
    value_node = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    errors.push_back("--set " + assignment + ": the value is not valid YAML: " + e.msg);
    return;
  }
  // Walk with fresh handles (yaml-cpp node assignment rebinds, so use reset()).
  YAML::Node cur;
  cur.reset(root);
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    YAML::Node next;
    if (cur.IsSequence()) {
      char* end = nullptr;
      const long idx = std::strtol(parts[k].c_str(), &end, 10);
      if (*end || idx < 0 || static_cast<std::size_t>(idx) >= cur.size()) {
        errors.push_back("--set " + assignment + ": '" + parts[k] + "' is not an index of the list (size " +
                         std::to_string(cur.size()) + ")");
        return;
      }
      next.reset(cur[static_cast<std::size_t>(idx)]);
    } else {
      next.reset(cur[parts[k]]);
    }
    cur.reset(next);
  }
  if (parts.empty()) {
    errors.push_back("--set " + assignment + ": empty key path");
    return;
  }
  if (cur.IsSequence()) {
    char* end = nullptr;
    const long idx = std::strtol(parts.back().c_str(), &end, 10);
    if (*end || idx < 0 || static_cast<std::size_t>(idx) >= cur.size()) {
      errors.push_back("--set " + assignment + ": '" + parts.back() + "' is not an index of the list");
      return;
    }
    cur[static_cast<std::size_t>(idx)] = value_node;
  } else {
    cur[parts.back()] = value_node;
  }
}

// Canonical path "a.b.2" -> "a.b[2]" for messages and override matching.
std::string item(const std::string& path, std::size_t k) { return path + "[" + std::to_string(k) + "]"; }

}  // namespace

PipelineError::PipelineError(std::vector<std::string> messages)
    : std::runtime_error(join(messages, "\n")), messages_(std::move(messages)) {}

std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& candidates) {
  std::vector<std::pair<std::size_t, std::string>> scored;
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  for (const auto& c : candidates) {
    std::size_t d = edit_distance(word, c);
    const bool contains = word.size() >= 3 && (c.find(word) != std::string::npos || word.find(c) != std::string::npos);
    if (d <= limit || contains) scored.emplace_back(contains ? std::min(d, limit) : d, c);
  }
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> out;
  for (std::size_t k = 0; k < scored.size() && k < 3; ++k) out.push_back(scored[k].second);
  return out;
}

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

SystemInfo Pipeline::system_info(std::size_t n, std::uint32_t realization) const {
  SystemInfo sys;
  sys.particles = n;
  sys.number_density = number_density;
  sys.sigma = sigma;
  sys.mass = 1.0;
  sys.initial_temperature = temperature;
  sys.mean_free_path0 = mean_free_path0();
  sys.time_unit0 = time_unit0();
  sys.volume = static_cast<double>(n) / number_density;
  sys.geometry = geometry;
  sys.box[0] = sys.box[1] = sys.box[2] = std::cbrt(sys.volume);
  sys.cells = 1;
  sys.seed = seed;
  sys.realization = realization;
  return sys;
}

double Pipeline::mean_free_path0() const { return 1.0 / (std::sqrt(2.0) * M_PI * number_density * sigma * sigma); }
double Pipeline::time_unit0() const { return mean_free_path0() / std::sqrt(2.0 * temperature); }

namespace {

// Reference-unit factor of a dimension (what a bare number means), for range checks and defaults.
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

const std::vector<std::string> kDiagnosticReserved = {"plugin", "name", "sample_every", "record_every"};
const std::vector<std::string> kReserved = {"plugin", "name"};

std::optional<PluginUse> check_plugin(Checker& c, const Pipeline& p, const YAML::Node& node, const std::string& path,
                                      PluginKind kind) {
  PluginUse use;
  use.path = path;
  use.where = c.where(path, node);
  YAML::Node map;
  std::string name;
  if (node.IsScalar()) {
    name = node.Scalar();
  } else if (node.IsMap() && node["plugin"] && node["plugin"].IsScalar()) {
    name = node["plugin"].Scalar();
    map.reset(node);
  } else {
    c.error(path, node, std::string("expected a plugin entry such as {plugin: NAME, ...} naming a ") + to_string(kind) +
                            " plugin");
    return std::nullopt;
  }
  const LoadedPlugin* lp = p.registry->find(name);
  if (!lp) {
    auto close = closest_names(name, p.registry->names_of_kind(kind));
    if (close.empty()) close = closest_names(name, p.registry->names());
    const auto all = p.registry->names_of_kind(kind);
    c.error(path, node, "unknown " + std::string(to_string(kind)) + " plugin '" + name + "'" +
                            (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                            " (installed " + to_string(kind) + " plugins: " + (all.empty() ? "none" : join(all, ", ")) +
                            "; `gdsmc plugins` lists them)");
    return std::nullopt;
  }
  if (lp->descriptor->kind != kind) {
    c.error(path, node, "plugin '" + name + "' is a " + to_string(lp->descriptor->kind) + " plugin, but a " +
                            to_string(kind) + " plugin is needed here");
    return std::nullopt;
  }
  use.plugin = lp;
  use.instance_name = name;
  const auto& schema = lp->descriptor->parameters;
  const auto& reserved = kind == PluginKind::diagnostic ? kDiagnosticReserved : kReserved;
  bool ok = true;
  if (map) {
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
        c.error(sub, it->first, "plugin '" + name + "' has no parameter '" + key + "'" +
                                    (close.empty() ? "" : "; did you mean " + join(close, ", ") + "?") +
                                    " (parameters: " + (names.empty() ? "none" : join(names, ", ")) + ")");
        ok = false;
      }
    }
    if (map["name"]) {
      if (map["name"].IsScalar() && !map["name"].Scalar().empty()) use.instance_name = map["name"].Scalar();
      else c.error(path + ".name", map["name"], "expected a name for the output group");
    }
    if (kind == PluginKind::diagnostic) {
      use.sample_every = p.sample_every;
      use.record_every = p.record_every;
      for (auto [key, field] : {std::pair{"sample_every", &use.sample_every}, std::pair{"record_every", &use.record_every}}) {
        if (!map[key]) continue;
        auto v = c.integer(map[key], path + "." + key);
        if (v && *v >= 1) *field = static_cast<std::uint64_t>(*v);
        else if (v) c.error(path + "." + key, map[key], std::string(key) + " must be a whole number of steps >= 1");
      }
    }
  } else if (kind == PluginKind::diagnostic) {
    use.sample_every = p.sample_every;
    use.record_every = p.record_every;
  }

  for (const auto& spec : schema) {
    const std::string sub = path + "." + spec.name;
    const YAML::Node v = map ? map[spec.name] : YAML::Node();
    if (!v) {
      if (!spec.default_) {
        c.error(use.where, path, "plugin '" + name + "' needs parameter '" + spec.name + "' (" + spec.doc + ")");
        ok = false;
        continue;
      }
      ParamValue dv = *spec.default_;
      if (spec.type == ParamType::real && spec.dimension != Dimension::none)
        dv = std::get<double>(dv) * reference_factor(spec.dimension, p);
      use.params.set(spec.name, dv, use.where, true);
      continue;
    }
    const SourceLocation at = c.where(sub, v);
    const std::string who = "parameter '" + spec.name + "' of plugin '" + name + "'";
    switch (spec.type) {
      case ParamType::real: {
        std::optional<double> value;
        double reference_value = 0;
        if (v.IsMap()) {
          if (spec.dimension == Dimension::none) {
            c.error(sub, v, who + " is dimensionless: give a plain number");
            ok = false;
            break;
          }
          c.check_keys(v, sub, {"value", "unit"});
          if (!v["value"] || !v["unit"]) {
            c.error(sub, v, who + ": expected {value: NUMBER, unit: UNIT}");
            ok = false;
            break;
          }
          auto num = c.real(v["value"], sub + ".value");
          if (!num) { ok = false; break; }
          std::string valid;
          value = to_reduced(*num, v["unit"].Scalar(), spec.dimension, p.mean_free_path0(), p.time_unit0(),
                             p.temperature, p.sigma, valid);
          if (!value) {
            c.error(sub + ".unit", v["unit"], "unknown unit '" + v["unit"].Scalar() + "' for " + who + " (valid: " + valid + ")");
            ok = false;
            break;
          }
          reference_value = *value / reference_factor(spec.dimension, p);
        } else {
          auto num = c.real(v, sub);
          if (!num) { ok = false; break; }
          reference_value = *num;
          value = *num * (spec.dimension == Dimension::none ? 1.0 : reference_factor(spec.dimension, p));
        }
        const bool low = spec.min && (spec.min_inclusive ? reference_value < *spec.min : reference_value <= *spec.min);
        const bool high = spec.max && (spec.max_inclusive ? reference_value > *spec.max : reference_value >= *spec.max);
        if (low || high) {
          c.error(at, sub, "value " + value_text(reference_value) + " is out of range for " + who + "; valid: " +
                               spec.range_text() + (spec.dimension == Dimension::none ? "" : std::string(" in ") + to_string(spec.dimension)));
          ok = false;
          break;
        }
        use.params.set(spec.name, *value, at);
        break;
      }
      case ParamType::integer: {
        auto num = c.integer(v, sub);
        if (!num) { ok = false; break; }
        const double d = static_cast<double>(*num);
        if ((spec.min && (spec.min_inclusive ? d < *spec.min : d <= *spec.min)) ||
            (spec.max && (spec.max_inclusive ? d > *spec.max : d >= *spec.max))) {
          c.error(at, sub, "value " + std::to_string(*num) + " is out of range for " + who + "; valid: " + spec.range_text());
          ok = false;
          break;
        }
        use.params.set(spec.name, *num, at);
        break;
      }
      case ParamType::boolean: {
        auto b = c.boolean(v, sub);
        if (!b) { ok = false; break; }
        use.params.set(spec.name, *b, at);
        break;
      }
      case ParamType::string:
      case ParamType::choice: {
        if (!v.IsScalar()) {
          c.error(sub, v, who + ": expected text, got " + Checker::describe(v));
          ok = false;
          break;
        }
        const std::string s = v.Scalar();
        if (spec.type == ParamType::choice && std::find(spec.choices.begin(), spec.choices.end(), s) == spec.choices.end()) {
          auto close = closest_names(s, spec.choices);
          c.error(sub, v, "'" + s + "' is not valid for " + who + "; " + spec.range_text() +
                              (close.empty() ? "" : " (did you mean " + join(close, ", ") + "?)"));
          ok = false;
          break;
        }
        use.params.set(spec.name, s, at);
        break;
      }
    }
  }
  if (!ok) return std::nullopt;
  // Let the plugin refuse what its schema cannot express.
  try {
    (void)create_object(*lp, use.params);
  } catch (const ParameterError& e) {
    const SourceLocation at = use.params.has(e.parameter()) ? use.params.entry(e.parameter()).where : use.where;
    c.error(at, path + "." + e.parameter(), "plugin '" + name + "' refused parameter '" + e.parameter() + "': " + e.what());
    return std::nullopt;
  } catch (const std::exception& e) {
    c.error(use.where, path, "plugin '" + name + "' failed to construct: " + e.what());
    return std::nullopt;
  }
  return use;
}

}  // namespace

Pipeline load_pipeline(const fs::path& file, const std::vector<std::string>& overrides,
                       const std::vector<fs::path>& extra_plugin_paths) {
  Pipeline p;
  p.file = file;
  p.overrides = overrides;
  if (std::filesystem::is_directory(file))
    throw PipelineError({file.string() + ": cannot read the pipeline file (it is a directory)"});
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw PipelineError({file.string() + ": cannot read the pipeline file (" + std::strerror(errno) + ")"});
    std::ostringstream ss;
    ss << in.rdbuf();
    p.source_text = ss.str();
  }
  YAML::Node root;
  try {
    root = YAML::Load(p.source_text);
  } catch (const YAML::ParserException& e) {
    throw PipelineError({file.string() + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                         ": malformed YAML: " + e.msg});
  }
  if (!root.IsMap())
    throw PipelineError({file.string() + ":1:1: a pipeline is a YAML mapping with keys run, system, initial_state, "
                                         "collision, diagnostics, ..."});
  {
    std::vector<std::string> errors;
    for (const auto& o : overrides) apply_override(root, o, errors);
    if (!errors.empty()) throw PipelineError(errors);
  }
  YAML::Emitter emitter;
  emitter << root;
  p.resolved_text = emitter.c_str();

  Checker c(file, overrides);
  c.check_keys(root, "", {"run", "system", "initial_state", "collision", "forcings", "boundaries", "diagnostics",
                          "output", "plugins", "sweep"});
  auto need = [&](const char* key) -> YAML::Node {
    YAML::Node n = root[key];
    if (!n) c.error(SourceLocation{file.string(), 1, 1}, key, std::string("missing required section '") + key + "'");
    return n;
  };

  // Plugin search path: --plugin-path, the pipeline's `plugins:` (relative to the file), then the defaults.
  p.registry = std::make_shared<PluginRegistry>();
  std::vector<std::string> load_errors;
  auto add_path = [&](const fs::path& where, const std::string& origin) {
    try {
      p.registry->add(where);
    } catch (const PluginLoadError& e) {
      load_errors.push_back(origin + ": " + e.what());
    }
  };
  for (const auto& extra : extra_plugin_paths) add_path(extra, "--plugin-path");
  if (const YAML::Node pl = root["plugins"]) {
    if (!pl.IsSequence()) {
      c.error("plugins", pl, "expected a list of plugin directories or .so files");
    } else {
      for (std::size_t k = 0; k < pl.size(); ++k) {
        fs::path d = pl[k].Scalar();
        if (d.is_relative()) d = file.parent_path() / d;
        add_path(d, c.where(item("plugins", k), pl[k]).str());
      }
    }
  }
  for (const auto& d : PluginRegistry::default_search_path()) add_path(d, "plugin search path");
  for (const auto& e : load_errors) c.error(SourceLocation{}, "", e);

  // run
  if (YAML::Node run = need("run")) {
    if (!run.IsMap()) {
      c.error("run", run, "expected a mapping");
    } else {
      c.check_keys(run, "run", {"seed", "particles", "time_step", "stop", "sample_every", "record_every", "moments_every",
                                "realizations", "average_after"});
      if (run["realizations"]) {
        if (auto v = c.integer(run["realizations"], "run.realizations")) {
          if (*v < 1 || *v > 100000) c.error("run.realizations", run["realizations"], "realizations must be between 1 and 100000");
          else p.realizations = static_cast<std::uint32_t>(*v);
        }
      }
      if (const YAML::Node aa = run["average_after"]) {
        if (!aa.IsMap()) {
          c.error("run.average_after", aa, "expected {collisions_per_particle: S} or {time: T (tau0)}");
        } else {
          c.check_keys(aa, "run.average_after", {"collisions_per_particle", "time"});
          if (aa["collisions_per_particle"])
            if (auto v = c.real(aa["collisions_per_particle"], "run.average_after.collisions_per_particle")) {
              if (*v < 0) c.error("run.average_after.collisions_per_particle", aa["collisions_per_particle"], "must be >= 0");
              else p.average_after_collisions_per_particle = *v;
            }
          if (aa["time"])
            if (auto v = c.real(aa["time"], "run.average_after.time")) {
              if (*v < 0) c.error("run.average_after.time", aa["time"], "must be >= 0 (tau0)");
              else p.average_after_time_tau0 = *v;
            }
          if (aa["collisions_per_particle"] && aa["time"])
            c.error("run.average_after", aa, "give collisions_per_particle or time, not both");
        }
      }
      if (run["seed"]) {
        if (auto v = c.integer(run["seed"], "run.seed")) {
          if (*v < 0) c.error("run.seed", run["seed"], "seed must be >= 0");
          else p.seed = static_cast<std::uint64_t>(*v);
        }
      }
      if (!run["particles"]) {
        c.error("run", run, "missing required key 'particles' (number of simulated particles, >= 2)");
      } else if (auto v = c.integer(run["particles"], "run.particles")) {
        if (*v < 2 || *v > 4000000000LL)
          c.error("run.particles", run["particles"], "particles must be between 2 and 4e9, got " + std::to_string(*v));
        else
          p.particles = static_cast<std::size_t>(*v);
      }
      if (!run["time_step"]) {
        c.error("run", run, "missing required key 'time_step' (e.g. {value: 0.01, unit: tau0, follow_temperature: true})");
      } else {
        const YAML::Node ts = run["time_step"];
        std::optional<double> v;
        std::string unit = "tau0";
        if (ts.IsMap()) {
          c.check_keys(ts, "run.time_step", {"value", "unit", "follow_temperature"});
          if (!ts["value"]) c.error("run.time_step", ts, "missing 'value'");
          else v = c.real(ts["value"], "run.time_step.value");
          if (ts["unit"]) unit = ts["unit"].Scalar();
          if (ts["follow_temperature"])
            if (auto b = c.boolean(ts["follow_temperature"], "run.time_step.follow_temperature"))
              p.time_step_follows_temperature = *b;
        } else {
          v = c.real(ts, "run.time_step");
        }
        if (unit != "tau0") c.error("run.time_step.unit", ts["unit"], "unknown unit '" + unit + "' (valid: tau0)");
        if (v && *v <= 0) c.error("run.time_step", ts, "time step must be > 0, got " + value_text(*v));
        else if (v) p.time_step_tau0 = *v;
      }
      if (!run["stop"]) {
        c.error("run", run, "missing required key 'stop' (e.g. {collisions_per_particle: 50} or {time: 100})");
      } else {
        const YAML::Node st = run["stop"];
        if (!st.IsMap()) {
          c.error("run.stop", st, "expected {collisions_per_particle: S} and/or {time: T (tau0)}");
        } else {
          c.check_keys(st, "run.stop", {"collisions_per_particle", "time", "steady"});
          if (const YAML::Node sd = st["steady"]) {
            if (!sd.IsMap()) {
              c.error("run.stop.steady", sd, "expected {series: GROUP/COLUMN, window: S, tolerance: X}");
            } else {
              c.check_keys(sd, "run.stop.steady", {"series", "window", "tolerance"});
              SteadyStop ss;
              bool ok = true;
              const std::string series = sd["series"] ? sd["series"].Scalar() : "";
              const auto slash = series.find('/');
              if (slash == std::string::npos || slash == 0 || slash + 1 == series.size()) {
                c.error("run.stop.steady.series", sd["series"] ? sd["series"] : sd,
                        "expected a series as GROUP/COLUMN, e.g. temperature/temperature");
                ok = false;
              } else {
                ss.group = series.substr(0, slash);
                ss.column = series.substr(slash + 1);
              }
              const double window = sd["window"] ? c.real(sd["window"], "run.stop.steady.window").value_or(0.0) : 0.0;
              const double tol = sd["tolerance"] ? c.real(sd["tolerance"], "run.stop.steady.tolerance").value_or(0.0) : 0.0;
              if (!(window > 0)) {
                c.error("run.stop.steady.window", sd["window"] ? sd["window"] : sd, "window must be > 0 collisions per particle");
                ok = false;
              }
              if (!(tol > 0)) {
                c.error("run.stop.steady.tolerance", sd["tolerance"] ? sd["tolerance"] : sd, "tolerance must be > 0 (relative)");
                ok = false;
              }
              if (ok) {
                ss.window = window;
                ss.tolerance = tol;
                p.stop_steady = ss;
              }
              if (!st["collisions_per_particle"] && !st["time"])
                c.error("run.stop", st, "a steady stop also needs collisions_per_particle or time as an upper limit");
            }
          }
          if (st["collisions_per_particle"])
            if (auto v = c.real(st["collisions_per_particle"], "run.stop.collisions_per_particle")) {
              if (*v <= 0) c.error("run.stop.collisions_per_particle", st["collisions_per_particle"], "must be > 0");
              else p.stop_collisions_per_particle = *v;
            }
          if (st["time"]) {
            const YAML::Node t = st["time"];
            std::optional<double> v;
            if (t.IsMap()) {
              c.check_keys(t, "run.stop.time", {"value", "unit"});
              if (t["value"]) v = c.real(t["value"], "run.stop.time.value");
              if (t["unit"] && t["unit"].Scalar() != "tau0")
                c.error("run.stop.time.unit", t["unit"], "unknown unit '" + t["unit"].Scalar() + "' (valid: tau0)");
            } else {
              v = c.real(t, "run.stop.time");
            }
            if (v && *v <= 0) c.error("run.stop.time", t, "must be > 0");
            else if (v) p.stop_time_tau0 = *v;
          }
          if (!st["collisions_per_particle"] && !st["time"])
            c.error("run.stop", st, "give collisions_per_particle and/or time");
        }
      }
      for (auto [key, field] : {std::pair{"sample_every", &p.sample_every}, std::pair{"record_every", &p.record_every},
                                std::pair{"moments_every", &p.moments_every}}) {
        if (!run[key]) continue;
        const std::string sub = std::string("run.") + key;
        if (auto v = c.integer(run[key], sub)) {
          if (*v < 1) c.error(sub, run[key], std::string(key) + " must be a whole number of steps >= 1");
          else *field = static_cast<std::uint64_t>(*v);
        }
      }
    }
  }

  // system
  if (YAML::Node sys = need("system")) {
    if (!sys.IsMap()) {
      c.error("system", sys, "expected a mapping");
    } else {
      c.check_keys(sys, "system", {"density", "mean_free_path", "sigma", "temperature", "domain"});
      if (sys["sigma"])
        if (auto v = c.real(sys["sigma"], "system.sigma")) {
          if (*v <= 0) c.error("system.sigma", sys["sigma"], "sigma must be > 0");
          else p.sigma = *v;
        }
      if (sys["temperature"])
        if (auto v = c.real(sys["temperature"], "system.temperature")) {
          if (*v <= 0) c.error("system.temperature", sys["temperature"], "the initial temperature T0 must be > 0");
          else p.temperature = *v;
        }
      if (sys["density"] && sys["mean_free_path"]) {
        c.error("system", sys, "give either density or mean_free_path, not both");
      } else if (sys["density"]) {
        if (auto v = c.real(sys["density"], "system.density")) {
          if (*v <= 0) c.error("system.density", sys["density"], "number density must be > 0 (particles per sigma^3)");
          else p.number_density = *v;
        }
      } else if (sys["mean_free_path"]) {
        if (auto v = c.real(sys["mean_free_path"], "system.mean_free_path")) {
          if (*v <= 0) c.error("system.mean_free_path", sys["mean_free_path"], "mean free path must be > 0 (sigma units)");
          else p.number_density = 1.0 / (std::sqrt(2.0) * M_PI * p.sigma * p.sigma * *v);
        }
      } else {
        c.error("system", sys, "missing 'density' (n, per sigma^3) or 'mean_free_path' (lambda0, in sigma)");
      }
      if (sys["domain"]) {
        const YAML::Node d = sys["domain"];
        if (!(d.IsScalar() && d.Scalar() == "homogeneous"))
          c.error("system.domain", d, "this version runs homogeneous systems only (domain: homogeneous); slab "
                                      "domains with layers and walls are not available yet");
      }
    }
  }

  if (YAML::Node out = root["output"]) {
    if (!out.IsMap()) {
      c.error("output", out, "expected {file: NAME.h5}");
    } else {
      c.check_keys(out, "output", {"file", "particles"});
      if (out["file"]) p.output_file = out["file"].Scalar();
      if (out["particles"])
        if (auto b = c.boolean(out["particles"], "output.particles")) p.output_particles = *b;
    }
  }
  if (p.output_file.empty()) p.output_file = file.stem().string() + ".h5";

  if (const YAML::Node sw = root["sweep"]) {
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
        if (v.IsSequence() && v.size() > 0) {
          for (std::size_t k = 0; k < v.size(); ++k) {
            YAML::Emitter e;
            e << YAML::Flow << v[k];
            axis.values.push_back({e.c_str(), {name + "=" + e.c_str()}});
          }
        } else if (v.IsMap() && v.size() > 0) {
          for (auto vt = v.begin(); vt != v.end(); ++vt) {
            SweepAxis::Value value{vt->first.Scalar(), {}};
            if (!vt->second.IsMap()) {
              c.error(sub + "." + value.label, vt->second, "a named variant is a mapping of key.path: value overrides");
              continue;
            }
            for (auto ot = vt->second.begin(); ot != vt->second.end(); ++ot) {
              YAML::Emitter e;
              e << YAML::Flow << ot->second;
              value.overrides.push_back(ot->first.Scalar() + "=" + e.c_str());
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

  // Plugins need lambda0 and tau0 for their units: only check them once the system is sound.
  const bool system_ok = p.number_density > 0;
  if (system_ok) {
    if (YAML::Node n = need("initial_state"))
      if (auto u = check_plugin(c, p, n, "initial_state", PluginKind::initial_state)) p.initial_state = *u;
    if (YAML::Node n = need("collision"))
      if (auto u = check_plugin(c, p, n, "collision", PluginKind::collision_rule)) p.collision = *u;
    auto list = [&](const char* key, PluginKind kind, std::vector<PluginUse>& into) {
      const YAML::Node n = root[key];
      if (!n || n.IsNull()) return;
      if (!n.IsSequence()) {
        c.error(key, n, "expected a list of plugin entries");
        return;
      }
      for (std::size_t k = 0; k < n.size(); ++k)
        if (auto u = check_plugin(c, p, n[k], item(key, k), kind)) into.push_back(*u);
    };
    list("forcings", PluginKind::forcing, p.forcings);
    list("boundaries", PluginKind::boundary, p.boundaries);
    list("diagnostics", PluginKind::diagnostic, p.diagnostics);
    if (p.stop_steady) {
      bool found = false;
      for (const auto& d : p.diagnostics) found = found || d.instance_name == p.stop_steady->group;
      if (!found)
        c.error(SourceLocation{file.string(), 0, 0}, "run.stop.steady.series",
                "no diagnostic writes the group '" + p.stop_steady->group + "'");
    }
    std::set<std::string> names;
    for (const auto& d : p.diagnostics)
      if (!names.insert(d.instance_name).second)
        c.error(d.where, d.path, "two diagnostics write to the group '" + d.instance_name + "'; give one a `name:`");
  }
  if (!c.errors().empty()) throw PipelineError(c.errors());
  return p;
}

}  // namespace gdsmc::host
