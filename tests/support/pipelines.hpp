// Test support: small pipelines, and the host in-process (load a pipeline, read what an engine's
// diagnostics hold, drive one diagnostic directly).
#pragma once
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/pipeline.hpp"
#include "config/system_info.hpp"
#include "engine/engine.hpp"
#include "output/diagnostic_output.hpp"
#include "plugins/loader.hpp"
#include "plugins/registry.hpp"
#include "support/files.hpp"

namespace gdsmc::test {

// A homogeneous cooling state small enough for a test to run in a fraction of a second.
inline const std::string kSmallHcsPipeline = R"(run:
  seed: 3
  particles: 400
  time_step: {value: 0.02, unit: tau0}
  stop: {collisions_per_particle: 1}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
diagnostics: [temperature]
output: {file: out.h5}
)";

// A Lees-Edwards slab whose forcing acts on the particles (the drag of the equivalent elastic model,
// 000 Eq. 4.12), small enough for a decomposed run to take seconds.
inline const std::string kDragSlabPipeline =
    "run:\n  seed: 9\n  particles: 6000\n  time_step: {value: 2.0e-3, unit: tau0, follow_temperature: true}\n"
    "  stop: {collisions_per_particle: 1.5}\n  record_every: 40\n"
    "system:\n  density: 1.0e-3\n  temperature: 1.0\n  domain: slab\n  box: {y: 2.5}\n  layers: 20\n"
    "initial_state: {plugin: maxwellian}\n"
    "collision: {plugin: equivalent_elastic_hard_spheres, alpha: 0.8}\nforcings: [{plugin: drag}]\n"
    "boundaries:\n  y: {plugin: lees_edwards, shear_rate: 2}\n"
    "diagnostics: [slab_averages, energy_balance]\n"
    "output: {file: out.h5, particles: true}\n";

// A small valid pipeline (a homogeneous cooling state of 1000 particles to s = 5); the tests change
// it with --set or the arguments.
inline std::string small_pipeline(const std::string& run_extra = "", const std::string& stop = "{collisions_per_particle: 5}",
                                  int particles = 1000, double alpha = 0.9, const std::string& diagnostics = "  - {plugin: temperature}\n") {
  return "run:\n"
         "  seed: 3\n"
         "  particles: " + std::to_string(particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n" + run_extra +
         "system:\n"
         "  density: 1.0e-3\n"
         "  temperature: 1.0\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}\n"
         "diagnostics:\n" + diagnostics +
         "output: {file: out.h5}\n";
}

// Load a pipeline written from `yaml` into <dir>/<name>, with the in-tree plugins on the search
// path: with the plugins found and the warnings (load_study, for expand_cases), or its
// configuration alone (load_yaml). An Engine keeps a reference to the pipeline: keep the pipeline
// alive while it runs.
inline host::LoadedPipeline load_study(const TempDir& dir, const std::string& yaml,
                                       const std::vector<std::string>& overrides = {},
                                       const std::string& name = "pipeline.yaml") {
  const fs::path file = dir.write(name, yaml);
  return host::load_pipeline(file, overrides, {plugin_dir()});
}
inline host::Pipeline load_yaml(const TempDir& dir, const std::string& yaml, const std::vector<std::string>& overrides = {},
                                const std::string& name = "pipeline.yaml") {
  return load_study(dir, yaml, overrides, name).pipeline;
}

// What the diagnostic group `group`, its series `column` or its scalar `name` holds after a run
// (throws if missing).
inline const host::DiagnosticOutput& diagnostic(const host::Engine& e, const std::string& group) {
  for (const auto& d : e.diagnostics())
    if (d.group() == group) return d;
  throw std::runtime_error("no diagnostic group '" + group + "'");
}
inline const std::vector<double>& series(const host::Engine& e, const std::string& group, const std::string& column) {
  const auto& d = diagnostic(e, group);
  for (const auto& c : d.columns)
    if (c.name == column) return c.values;
  throw std::runtime_error("no series '" + column + "' in group '" + group + "'");
}
inline double scalar(const host::Engine& e, const std::string& group, const std::string& name) {
  const auto& d = diagnostic(e, group);
  for (const auto& s : d.scalars)
    if (s.name == name) return s.value;
  throw std::runtime_error("no scalar '" + name + "' in group '" + group + "'");
}

// The pipeline's first diagnostic as the engine holds it, with its sink (group `group`, the bins of
// the system of `particles` particles set), for a test that calls begin, sample, record and finish
// itself; and what the sink then holds, by name (throws if missing).
struct DiagnosticBench {
  host::Pipeline pipeline;
  std::shared_ptr<PluginObject> object;
  Diagnostic* diag = nullptr;
  SystemInfo sys;
  QuantityBoard board;
  std::vector<std::string> summary;
  std::unique_ptr<host::DiagnosticOutput> out;
  DiagnosticBench(const TempDir& dir, const std::string& yaml, const std::string& group, std::size_t particles) {
    pipeline = load_yaml(dir, yaml);
    object = host::create_object(*pipeline.diagnostics.at(0).plugin, pipeline.diagnostics.at(0).params);
    diag = static_cast<Diagnostic*>(object.get());
    sys = host::system_info(pipeline, particles, 0);
    out = std::make_unique<host::DiagnosticOutput>(group, &summary);
    out->set_bins(host::bin_centres_lambda0(sys));
  }
  double scalar(const std::string& name) const {
    for (const auto& s : out->scalars)
      if (s.name == name) return s.value;
    throw std::runtime_error("no scalar " + name);
  }
  const std::vector<double>& series(const std::string& name) const {
    for (const auto& c : out->columns)
      if (c.name == name) return c.values;
    throw std::runtime_error("no series " + name);
  }
  const host::DiagnosticOutput::Histogram& histogram(const std::string& name) const {
    for (const auto& h : out->histograms)
      if (h.name == name) return h;
    throw std::runtime_error("no histogram " + name);
  }
  const std::vector<double>& array(const std::string& name) const {
    for (const auto& a : out->arrays)
      if (a.name == name) return a.data;
    throw std::runtime_error("no array " + name);
  }
};

}  // namespace gdsmc::test
