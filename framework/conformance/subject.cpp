// The plugin under test, its parameter assignments and the pipelines built around it.
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

namespace fs = std::filesystem;


// Total momentum, kinetic energy (m = 1) and sum of speeds (the round-off scale) of all particles.
void velocity_totals(const ParticleSpan& p, Vec3& momentum, double& energy, double& speed_sum) {
  momentum = {};
  energy = speed_sum = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const Vec3 v = p.velocity(i);
    momentum += v;
    energy += 0.5 * dot(v, v);
    speed_sum += norm(v);
  }
}
// --------------------------------------------------------------------------------------------
// The plugin under test and how to build pipelines around it


// One line of YAML: a node read in block style keeps that style through the emitter, so every
// collection of a copy is set to flow style first.
std::string yaml_text(const YAML::Node& n) {
  const std::function<void(YAML::Node)> flow = [&flow](YAML::Node node) {
    if (!node.IsMap() && !node.IsSequence()) return;
    node.SetStyle(YAML::EmitterStyle::Flow);
    for (auto it = node.begin(); it != node.end(); ++it) flow(node.IsMap() ? it->second : *it);
  };
  YAML::Node copy = YAML::Clone(n);
  flow(copy);
  YAML::Emitter e;
  e << YAML::Flow << copy;
  return e.c_str();
}

std::string num(double v) { return fmt("%.17g", v); }

// A value inside the declared range (for required parameters without a default).
std::string in_range_value(const ParamSpec& s) {
  switch (s.type) {
    case ParamType::real: {
      if (s.min && s.max) return num(0.5 * (*s.min + *s.max));
      if (s.min) return num(*s.min + std::max(1.0, std::fabs(*s.min)));
      if (s.max) return num(*s.max - std::max(1.0, std::fabs(*s.max)));
      return "1";
    }
    case ParamType::integer: {
      double v = 1;
      if (s.min && s.max) v = std::floor(0.5 * (*s.min + *s.max));
      else if (s.min) v = std::floor(*s.min) + 1;
      else if (s.max) v = std::ceil(*s.max) - 1;
      return fmt("%.0f", v);
    }
    case ParamType::boolean: return "false";
    case ParamType::choice: return s.choices.empty() ? "none" : quoted(s.choices.front());
    case ParamType::string: return quoted("conformance");
  }
  return "1";
}

Assignment base_assignment(const Subject& s) {
  Assignment a = s.user_params;
  for (const auto& spec : s.desc().parameters)
    if (!spec.default_ && !a.count(spec.name)) a[spec.name] = in_range_value(spec);
  return a;
}

std::string describe_assignment(const Subject& s, const Assignment& a) {
  std::string t;
  for (const auto& spec : s.desc().parameters) {
    std::string v;
    if (auto it = a.find(spec.name); it != a.end()) v = it->second;
    else if (spec.default_) v = value_text(*spec.default_) + " (default)";
    t += (t.empty() ? "" : ", ") + spec.name + " = " + v;
  }
  return t.empty() ? "no parameters" : t;
}

std::string slot_path(PluginKind k) { return kind_info(k).first_entry; }

const PluginUse& slot(const Pipeline& p, PluginKind k) {
  if (const PluginUse* use = p.use_at(slot_path(k))) return *use;
  throw std::logic_error("the test pipeline has no entry at " + slot_path(k));
}

// The plugin's own entries among a refused pipeline's messages.
std::vector<ConfigError> own_errors(const PipelineError& e, PluginKind k) {
  const std::string path = slot_path(k);
  std::vector<ConfigError> out;
  for (const auto& error : e.errors())
    if (error.path == path || error.path.rfind(path + ".", 0) == 0 || error.path.rfind(path + "[", 0) == 0)
      out.push_back(error);
  return out;
}

std::string error_text(const std::vector<ConfigError>& own, const PipelineError& e) {
  if (own.empty()) return join(e.messages(), "; ");
  std::vector<std::string> lines;
  for (const auto& error : own) lines.push_back(error.text());
  return join(lines, "; ");
}

std::string stand_in_plugin(const PluginKindInfo& info) {
  if (!info.stand_in) return "";
  const YAML::Node entry = YAML::Load(info.stand_in);
  return entry.IsMap() ? entry["plugin"].Scalar() : entry.Scalar();
}

// The entry filling a required slot of `kind` in a pipeline built around a plugin of another kind:
// the kind's stand-in (kinds.hpp) when `reg` has that plugin, of that kind, declaring every
// parameter the entry sets; else the first plugin of the kind, in the registry's order, whose
// parameters all have defaults.
std::string stand_in(const PluginRegistry& reg, PluginKind kind) {
  const PluginKindInfo& info = kind_info(kind);
  auto declares = [](const PluginDescriptor& d, const std::string& key) {
    return std::any_of(d.parameters.begin(), d.parameters.end(), [&](const ParamSpec& p) { return p.name == key; });
  };
  if (info.stand_in) {
    const YAML::Node entry = YAML::Load(info.stand_in);
    const LoadedPlugin* lp = reg.find(stand_in_plugin(info));
    bool usable = lp && lp->descriptor->kind == kind;
    if (usable && entry.IsMap())
      for (auto it = entry.begin(); it != entry.end(); ++it)
        usable = usable && (it->first.Scalar() == "plugin" || declares(*lp->descriptor, it->first.Scalar()));
    if (usable) return info.stand_in;
  }
  for (const PluginInfo& found : reg.available()) {
    if (found.kind != kind) continue;
    const LoadedPlugin* lp = reg.find(found.name);
    if (!lp || lp->descriptor->kind != kind) continue;  // a plugin of the same name found earlier
    const auto& params = lp->descriptor->parameters;
    if (std::all_of(params.begin(), params.end(), [](const ParamSpec& p) { return p.default_.has_value(); }))
      return lp->descriptor->name;
  }
  throw std::runtime_error(std::string("cannot build a test pipeline: no ") + info.role + " plugin (kind '" +
                           to_string(kind) + "') whose parameters all have defaults on the plugin search path " +
                           "to go with this one (give --plugin-path, GDSMC_PLUGIN_PATH or --context)");
}

// Fillers for the slots the plugin does not occupy: the --context pipeline's entries, else the
// stand-in from the plugin, the user's plugin paths, the context's and the search path.
std::string filler(const Subject& s, PluginKind kind) {
  static std::map<PluginKind, std::string> cache;
  if (auto it = cache.find(kind); it != cache.end()) return it->second;
  const std::string& from_context = kind == PluginKind::initial_state ? s.context_initial : s.context_collision;
  if (!from_context.empty()) return cache[kind] = from_context;
  PluginRegistry reg;
  auto add = [&](const fs::path& p) {
    try {
      reg.add(p);
    } catch (const std::exception&) {
    }
  };
  add(s.file);
  for (const auto& p : s.cfg.plugin_paths) add(p);
  for (const auto& p : s.context_paths) add(p);
  for (const auto& p : PluginRegistry::default_search_path()) add(p);
  return cache[kind] = stand_in(reg, kind);
}

std::string entry_text(const std::string& plugin, const Assignment& a) {
  std::string t = "{plugin: " + quoted(plugin);
  for (const auto& [k, v] : a) t += ", " + k + ": " + v;
  return t + "}";
}


// Write and load a pipeline with the plugin (parameters `a`) in its slot.
std::unique_ptr<Pipeline> load_test_pipeline(const Subject& s, const Assignment& a, std::size_t particles) {
  static int counter = 0;
  const PluginKind k = s.kind();
  const std::string self = entry_text(s.desc().name, a);
  std::ostringstream y;
  y << "run: {seed: " << s.cfg.seed << ", particles: " << particles << ", time_step: {value: " << kTimeStepTau0
    << ", unit: tau0}, stop: {collisions_per_particle: 1}}\n";
  // A boundary needs a slab: a gap of one mean free path in a few layers, the plugin on both planes.
  if (!s.context_system.empty() && k != PluginKind::boundary)
    y << "system: " << s.context_system << "\n";
  else
    y << "system: {density: " << num(kDensity) << ", temperature: 1.0"
      << (k == PluginKind::boundary ? ", domain: slab, box: {y: 1.0}, layers: 4" : "") << "}\n";
  y << "initial_state: " << (k == PluginKind::initial_state ? self : filler(s, PluginKind::initial_state)) << "\n";
  y << "collision: " << (k == PluginKind::collision_rule ? self : filler(s, PluginKind::collision_rule)) << "\n";
  if (k == PluginKind::forcing || !s.context_forcings.empty()) {
    y << "forcings: [";
    if (k == PluginKind::forcing) y << self;
    for (std::size_t i = 0; i < s.context_forcings.size(); ++i)
      y << (i || k == PluginKind::forcing ? ", " : "") << s.context_forcings[i];
    y << "]\n";
  }
  if (k == PluginKind::boundary) y << "boundaries: {y: " << self << "}\n";
  else if (!s.context_boundaries.empty()) y << "boundaries: " << s.context_boundaries << "\n";
  if (k == PluginKind::diagnostic) y << "diagnostics: [" << self << "]\n";
  if (!s.context_paths.empty()) {
    y << "plugins: [";
    for (std::size_t i = 0; i < s.context_paths.size(); ++i) y << (i ? ", " : "") << quoted(s.context_paths[i].string());
    y << "]\n";
  }
  y << "output: {file: " << quoted((s.workdir / "unused.h5").string()) << "}\n";
  const fs::path file = s.workdir / fmt("pipeline-%d-%d.yaml", static_cast<int>(::getpid()), counter++);
  {
    std::ofstream out(file);
    out << y.str();
  }
  std::vector<fs::path> extra{s.file};
  for (const auto& p : s.cfg.plugin_paths) extra.push_back(p);
  return std::make_unique<Pipeline>(load_pipeline(file, {}, extra).pipeline);
}

}  // namespace gdsmc::host::conformance
