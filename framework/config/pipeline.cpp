#include "config/pipeline.hpp"

#include <cmath>
#include <map>
#include <set>

#include <yaml-cpp/yaml.h>

#include "config/overrides.hpp"
#include "config/params.hpp"
#include "config/sections.hpp"
#include "config/yaml_reader.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

std::string where_text(const PluginUse& use) {
  return "plugin '" + use.plugin->descriptor->name + "' (" + use.path + ", " + use.where.str() + ", library " +
         use.plugin->file.string() + ")";
}

double Pipeline::mean_free_path0() const { return 1.0 / (std::sqrt(2.0) * M_PI * number_density * sigma * sigma); }
double Pipeline::time_unit0() const { return mean_free_path0() / std::sqrt(2.0 * temperature); }

namespace {

// `text` (the file as read) parsed: a YAML mapping, or PipelineError at the place it breaks.
YAML::Node parse_document(const fs::path& file, const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw PipelineError({file.string() + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                         ": malformed YAML: " + e.msg});
  }
  if (!root.IsMap())
    throw PipelineError({file.string() + ":1:1: a pipeline is a YAML mapping with keys run, system, initial_state, "
                                         "collision, diagnostics, ..."});
  return root;
}

void apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides) {
  std::vector<std::string> errors;
  for (const auto& o : overrides) apply_override(root, o, errors);
  if (!errors.empty()) throw PipelineError(errors);
}

// Plugin search path: --plugin-path, the pipeline's `plugins:` (relative to the file), then the defaults.
std::shared_ptr<const PluginRegistry> build_registry(Checker& c, const YAML::Node& root, const fs::path& file,
                                                     const std::vector<fs::path>& extra_plugin_paths) {
  auto registry = std::make_shared<PluginRegistry>();
  std::vector<std::string> load_errors;
  auto add_path = [&](const fs::path& where, const std::string& origin) {
    try {
      registry->add(where);
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
        const std::string where = c.where(item("plugins", k), pl[k]).str();
        std::error_code ec;
        if (!fs::exists(d, ec)) {
          c.warn(where + ": plugins[" + std::to_string(k) + "]: " + d.string() +
                 " does not exist; no plugins are loaded from it");
          continue;
        }
        add_path(d, where);
      }
    }
  }
  for (const auto& d : PluginRegistry::default_search_path()) add_path(d, "plugin search path");
  for (const auto& e : load_errors) c.error(SourceLocation{}, "", e);
  for (const auto& w : registry->warnings()) c.warn(w);
  return registry;
}

// The section `key` of the document; when it is missing, an error that shows a minimal valid one.
YAML::Node required_section(Checker& c, const YAML::Node& root, const fs::path& file, const std::string& key) {
  static const std::map<std::string, std::string> kExample = {
      {"run", "run: {particles: 10000, time_step: {value: 0.01, unit: tau0}, stop: {collisions_per_particle: 50}}"},
      {"system", "system: {density: 1.0e-3, temperature: 1.0}   (n sigma^3 and T0; a homogeneous system)"},
      {"initial_state", "initial_state: maxwellian"},
      {"collision", "collision: {plugin: inelastic_hard_spheres, alpha: 0.9}"},
  };
  YAML::Node n = root[key];
  if (!n)
    c.error(SourceLocation{file.string(), 1, 1}, key,
            "missing required section '" + key + "'; a minimal one: " + kExample.at(key) +
                " (docs/user-guide.md, \"The pipeline\", lists every key)");
  return n;
}

// boundaries: {y_min: PLUGIN, y_max: PLUGIN} or {y: PLUGIN} for both planes of a slab.
void parse_boundaries(Checker& c, const YAML::Node& root, const std::shared_ptr<const PluginRegistry>& plugins, Pipeline& p) {
  const YAML::Node b = root["boundaries"];
  const bool given = b && !b.IsNull() && !(b.IsSequence() && b.size() == 0);
  if (p.geometry != Geometry::slab) {
    if (given)
      c.error("boundaries", b, "boundaries need a slab (system.domain: slab); a homogeneous system has none");
    return;
  }
  if (!given || !b.IsMap()) {
    c.error(given ? c.where("boundaries", b) : SourceLocation{p.file.string(), 1, 1}, "boundaries",
            "a slab needs its two y boundaries: boundaries: {y_min: PLUGIN, y_max: PLUGIN}, or {y: PLUGIN} for "
            "both (periodic, lees_edwards, specular_wall, diffuse_wall, maxwell_wall, or your own)");
    return;
  }
  c.check_keys(b, "boundaries", {"y", "y_min", "y_max"});
  if (b["y"] && (b["y_min"] || b["y_max"])) {
    c.error("boundaries", b, "give either y (both planes) or y_min and y_max, not both");
    return;
  }
  if (b["y"]) {
    if (auto u = check_plugin(c, plugins, p, b["y"], "boundaries.y", PluginKind::boundary)) p.boundaries = {*u, *u};
    return;
  }
  for (const char* side : {"y_min", "y_max"})
    if (!b[side])
      c.error("boundaries", b, std::string("missing '") + side + "': a slab needs a boundary on both y planes");
  if (!b["y_min"] || !b["y_max"]) return;
  auto low = check_plugin(c, plugins, p, b["y_min"], "boundaries.y_min", PluginKind::boundary);
  auto high = check_plugin(c, plugins, p, b["y_max"], "boundaries.y_max", PluginKind::boundary);
  if (low && high) p.boundaries = {*low, *high};
}

// initial_state, collision, forcings, boundaries and diagnostics, checked against their plugins.
void parse_plugins(Checker& c, const YAML::Node& root, const fs::path& file, const std::shared_ptr<const PluginRegistry>& plugins,
                   Pipeline& p) {
  auto need = [&](const char* key) { return required_section(c, root, file, key); };
  if (YAML::Node n = need("initial_state"))
    if (auto u = check_plugin(c, plugins, p, n, "initial_state", PluginKind::initial_state)) p.initial_state = *u;
  if (YAML::Node n = need("collision"))
    if (auto u = check_plugin(c, plugins, p, n, "collision", PluginKind::collision_rule)) p.collision = *u;
  auto list = [&](const char* key, PluginKind kind, std::vector<PluginUse>& into) {
    const YAML::Node n = root[key];
    if (!n || n.IsNull()) return;
    if (!n.IsSequence()) {
      c.error(key, n, "expected a list of plugin entries");
      return;
    }
    for (std::size_t k = 0; k < n.size(); ++k)
      if (auto u = check_plugin(c, plugins, p, n[k], item(key, k), kind)) into.push_back(*u);
  };
  list("forcings", PluginKind::forcing, p.forcings);
  parse_boundaries(c, root, plugins, p);
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

}  // namespace

namespace {

// The walls' work per step: a particle travels |v_y| dt, on average dt/sqrt(pi) lambda0 in y at
// T0 (dt in tau0 = lambda0/sqrt(2T0/m)), so it meets a wall about dt/(sqrt(pi) Ly) times a step.
// Above kMaxWallHitsPerStep a step would spend its time reflecting particles (a slab 1e-6 lambda0
// wide took ~17 s a step, deaf to Ctrl-C): refused; above one, the gap is crossed within a step
// (the walls are resolved poorly): warned about. Both with the number.
constexpr double kMaxWallHitsPerStep = 100;
void check_wall_hits(Checker& c, const YAML::Node& root, Pipeline& p) {
  const double gap = p.box_y / p.mean_free_path0();  // Ly in lambda0
  const double hits = p.time_step_tau0 / (std::sqrt(M_PI) * gap);
  if (!(hits > 1)) return;
  const YAML::Node sys = root["system"];
  const YAML::Node at = sys["box"] && sys["box"].IsMap() && sys["box"]["y"] ? sys["box"]["y"] : sys;
  const std::string what = fmt("a step of %.3g tau0 across a gap Ly = %.3g lambda0: each particle would meet the walls "
                               "about %.3g times a step (|v_y| dt / Ly at T0; %.3g wall hits a step for %zu particles)",
                               p.time_step_tau0, gap, hits, hits * static_cast<double>(p.particles), p.particles);
  const double largest = std::sqrt(M_PI) * gap;  // one hit a particle a step
  if (hits > kMaxWallHitsPerStep)
    c.error("system.box.y", at,
            what + fmt(", more than %.0f: the run would spend its steps reflecting particles; use a time step of at "
                       "most %.3g tau0 (one wall hit a particle a step) or a wider gap",
                       kMaxWallHitsPerStep, largest));
  else
    c.warn(c.where("system.box.y", at).str() + ": system.box.y: " + what +
           fmt(": the gap is crossed within a step; a step of at most %.3g tau0 resolves it", largest));
}

// The document's top-level keys (before the registry is built, so their errors come first).
void check_sections(Checker& c, const YAML::Node& root) {
  c.check_keys(root, "", {"run", "system", "initial_state", "collision", "forcings", "boundaries", "diagnostics",
                          "output", "plugins", "sweep", "units"});
}

// Everything after the document's keys and the registry: every section, every plugin.
void check_document(Checker& c, const YAML::Node& root, const std::shared_ptr<const PluginRegistry>& plugins, Pipeline& p) {
  const fs::path& file = p.file;
  auto need = [&](const char* key) { return required_section(c, root, file, key); };
  if (const YAML::Node u = root["units"]) parse_units(c, u, p);  // first: it decides how the others read
  if (const YAML::Node run = need("run")) {
    parse_run(c, run, p);
    if (run.IsMap() && run["particles"]) p.particles_where = c.where("run.particles", run["particles"]);
  }
  if (YAML::Node sys = need("system")) parse_system(c, sys, p);
  if (p.geometry == Geometry::slab && p.particles > 0 && p.particles < p.layers)
    c.error("system.layers", root["system"]["layers"] ? root["system"]["layers"] : root["system"],
            std::to_string(p.particles) + " particles in " + std::to_string(p.layers) +
                " layers is fewer than one particle per layer on average; use at most " + std::to_string(p.particles) +
                " layers (the paper uses N/M = 200)");
  if (p.geometry == Geometry::slab && p.box_y > 0 && p.time_step_tau0 > 0) check_wall_hits(c, root, p);
  if (YAML::Node out = root["output"]) parse_output(c, out, p);
  if (p.output_file.empty()) p.output_file = file.stem().string() + ".h5";
  if (const YAML::Node sw = root["sweep"]) parse_sweep(c, sw, p);
  // Plugins need lambda0 and tau0 for their units: only check them once the system is sound.
  if (p.number_density > 0) parse_plugins(c, root, file, plugins, p);
}

}  // namespace

LoadedPipeline load_pipeline(const fs::path& file, const std::vector<std::string>& overrides,
                             const std::vector<fs::path>& extra_plugin_paths) {
  LoadedPipeline loaded;
  Pipeline& p = loaded.pipeline;
  p.file = file;
  p.overrides = overrides;
  p.source_text = read_pipeline_text(file);
  YAML::Node root = parse_document(file, p.source_text);
  apply_overrides(root, overrides);
  YAML::Emitter emitter;
  emitter << root;
  p.resolved_text = emitter.c_str();

  Checker c(file, overrides);
  check_sections(c, root);
  loaded.plugins = build_registry(c, root, file, extra_plugin_paths);
  check_document(c, root, loaded.plugins, p);
  loaded.warnings = c.warnings();
  if (!c.errors().empty()) throw PipelineError(c.errors(), loaded.warnings);
  return loaded;
}

namespace {

// `text` with the lines of its top-level `sweep:` section emptied (line breaks kept, so every other
// location is unchanged); `text` itself when the section cannot be cut out by lines (a flow mapping).
std::string without_sweep(const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception&) {
    return text;
  }
  int first = -1, end = -1;
  for (auto it = root.begin(); it != root.end(); ++it)
    if (it->first.Scalar() == "sweep" && it->first.Mark().column == 0) first = it->first.Mark().line;
  if (first < 0) return text;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const int line = it->first.Mark().line;
    if (line == first && it->first.Scalar() != "sweep") return text;  // another key on the sweep's line
    if (line > first && (end < 0 || line < end)) end = line;
  }
  std::string out;
  out.reserve(text.size());
  int line = 0;
  for (char ch : text) {
    if (ch == '\n' || line < first || (end >= 0 && line >= end)) out += ch;
    if (ch == '\n') ++line;
  }
  return out;
}

}  // namespace

SweepCaseLoader::SweepCaseLoader(const LoadedPipeline& base)
    : base_(base), text_(without_sweep(base.pipeline.source_text)) {}

const PluginUse* Pipeline::use_at(const std::string& path) const {
  for (const PluginUse* u : {&initial_state, &collision})
    if (u->path == path) return u;
  for (const auto* list : {&forcings, &boundaries, &diagnostics})
    for (const auto& u : *list)
      if (u.path == path) return &u;
  return nullptr;
}

Pipeline SweepCaseLoader::load(const std::vector<const SweepAxis::Value*>& values) const {
  const Pipeline& base = base_.pipeline;
  Pipeline p;
  p.file = base.file;
  p.overrides = base.overrides;
  YAML::Node root = parse_document(p.file, text_);
  apply_overrides(root, base.overrides);
  std::vector<std::pair<std::string, SourceLocation>> from_sweep;
  std::vector<std::string> errors;
  for (const SweepAxis::Value* v : values)
    for (std::size_t k = 0; k < v->overrides.size(); ++k) {
      const SourceLocation& at = v->where[k];
      apply_override(root, v->overrides[k], errors, at.str() + ": sweep value " + v->overrides[k]);
      from_sweep.emplace_back(v->overrides[k], at);
    }
  if (!errors.empty()) throw PipelineError(errors);
  root.remove("sweep");  // a --set may have written one
  Checker c(p.file, base.overrides, std::move(from_sweep));
  check_sections(c, root);
  check_document(c, root, base_.plugins, p);
  if (!c.errors().empty()) throw PipelineError(c.errors());
  p.output_file = base.output_file;
  return p;
}

}  // namespace gdsmc::host
