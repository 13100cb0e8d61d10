// The YAML pipeline: parsed once, checked against every plugin's schema, converted to reduced
// units. Every error is collected (file:line:column, the key path, what would be valid) before
// the pipeline is refused.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/params.hpp>

#include "config/errors.hpp"
#include "config/suggest.hpp"
#include "config/units.hpp"
#include "plugins/registry.hpp"

namespace gdsmc::host {

// One plugin as the pipeline uses it.
struct PluginUse {
  std::string path;           // key path in the pipeline, e.g. "diagnostics[1]"
  std::string instance_name;  // output group name (the plugin name unless `name:` is given)
  // The library the entry resolved to; holding it keeps its registry, and so the library, loaded.
  std::shared_ptr<const LoadedPlugin> plugin;
  Params params;              // validated, defaults filled, reduced units
  SourceLocation where;
  std::uint64_t sample_every = 1;  // diagnostics only (steps)
  std::uint64_t record_every = 1;  // diagnostics only (steps)
};

// "plugin 'NAME' (PATH, FILE:LINE:COLUMN, library LIBRARY.so)": how an error names the pipeline entry
// it is about and the library file that made it (a plugin shadowed by another file shows at once).
std::string where_text(const PluginUse& use);

// One axis of a parameter sweep: a list of values, each a set of overrides (key.path=value).
struct SweepAxis {
  std::string name;  // the key path (value axis) or the axis name (named variants)
  struct Value {
    std::string label;                   // the value as text, or the variant name
    std::vector<std::string> overrides;  // "key.path=value" assignments
    std::vector<SourceLocation> where;   // of each assignment: its entry in the sweep
  };
  std::vector<Value> values;
};

// Stop when a diagnostic series is steady: the means over the last two windows of `window`
// collisions per particle differ by at most `tolerance` times the latest mean.
struct SteadyStop {
  std::string group, column;  // the series "group/column"
  double window = 0;          // in collisions per particle s
  double tolerance = 0;
};

// A dimensional value given as a bare number, read in the reference unit of its dimension
// (config/units.hpp): what the verdict says it was read as.
struct BareValue {
  std::string path;   // "forcings[0].acceleration", "system.box.y"
  SourceLocation where;
  double value = 0;   // as written, in reference_unit(dimension)
  Dimensions dimension;
};

// One entry of system.species: a species of a granular mixture (mass in units of the reference
// mass m, diameter in units of sigma; a number fraction or a count, whichever the file gave).
struct SpeciesSpec {
  std::string name;
  double mass = 1, diameter = 1;
  double fraction = 0;     // N_s / N as given, or count / run.particles
  std::uint64_t count = 0;  // as given (0: from the fraction)
  SourceLocation where;
};
// SystemInfo's view of the species (names owned here, so that SpeciesInfo::name stays valid for as
// long as any copy of the pipeline holds the table).
struct SpeciesTable {
  std::vector<std::string> names;
  std::vector<SpeciesInfo> info;
};

struct Pipeline {
  std::filesystem::path file;
  std::string source_text;    // the file as read
  std::string resolved_text;  // after --set, as YAML
  std::vector<std::string> overrides;

  // run
  std::uint64_t seed = 1;
  std::size_t particles = 0;
  SourceLocation particles_where;  // where run.particles was given (file:line:column or --set)
  double time_step_tau0 = 0;       // c in dt = c tau0 [sqrt(T0/T)]
  bool time_step_follows_temperature = false;
  std::optional<double> stop_collisions_per_particle;
  std::optional<double> stop_time_tau0;
  std::optional<SteadyStop> stop_steady;
  std::uint64_t sample_every = 1, record_every = 1, moments_every = 4;
  std::uint32_t realizations = 1;
  // run.threads (or --threads): threads of the study; 0 = every core. Runs (cases x realizations)
  // go at once, and the threads left over when there are fewer runs than threads work inside each
  // run (layers, sub-populations, blocks of particles). Results do not depend on it.
  std::uint32_t threads = 0;
  // run.checkpoint: write each run's state every so many wall-clock seconds and/or collisions per
  // particle (0: not by that clock), at SIGINT/SIGTERM and when it finishes (study/checkpoint.hpp).
  bool checkpoint = false;
  double checkpoint_every_seconds = 0;
  double checkpoint_every_collisions_per_particle = 0;
  // run.subpopulation: particles per collision sub-population of a homogeneous system (0: one
  // population of all N). See CollisionStage; the default keeps each group's pairs in cache.
  std::size_t subpopulation = 32768;
  // run.candidate_pairs: false = distinct (N_c (N_c - 1)/2 pairs per cell), true = squared (N_c^2/2,
  // 000 Eq. 4.13 as written).
  bool candidate_pairs_squared = false;
  // run.pair_selection (slab layers, hard-sphere form): 0 = uniform, 1 = weighted, 2 = auto (the
  // default: weighted in a layer only where its uniform candidates would be many; CollisionStage).
  std::uint32_t pair_selection = 2;
  // run.sampling: true = bracketed (the default: a diagnostic that offers BracketedSampling is
  // sampled before and after the collision stage, so its means carry no O(dt) splitting bias),
  // false = after_step (every diagnostic once, after the step: the rule before SDK 6.1).
  bool sampling_bracketed = true;
  // Steady-state averages of every series over the records with s >= this (or t/tau0 >= this).
  std::optional<double> average_after_collisions_per_particle;
  std::optional<double> average_after_time_tau0;
  std::vector<SweepAxis> sweep;

  // units: explicit refuses a dimensional value given as a bare number (default: reference, a
  // bare number is in the reference unit of its dimension). Every bare one read is listed.
  bool units_explicit = false;
  std::vector<BareValue> bare_values;

  // system (reduced units)
  double number_density = 0;
  double sigma = 1;
  double temperature = 1;
  Geometry geometry = Geometry::homogeneous;
  // slab (system.domain: slab): Ly (required), Lx (0: Lx = Lz), M layers, sampling bins (0: M)
  double box_y = 0, box_x = 0;
  std::size_t layers = 1, bins = 0;
  // system.layers: {mean_free_paths: w, after: T}: `layers` = ceil(Ly / (w lambda0)) layers, of
  // equal widths until t = T tau0, then with edges set from the density profile measured over
  // [T/2, T] so that each holds the same share of the particles, i.e. is w' <= w local mean free
  // paths wide (dilute lambda(y) = 1 / (sqrt(2) pi n(y) sigma^2)), and frozen for the rest of the run.
  // 0: uniform layers throughout (layers: M, the default). With max_width: L as well, no layer is
  // wider than L either: layer I gets 1/(n_I/(n-bar w lambda0) + 1/L) of width, the harmonic
  // combination of the two bounds, and `layers` = ceil(Ly/(w lambda0) + Ly/L) (0: no L).
  double layers_mean_free_paths = 0;
  double layers_max_width = 0;
  double layers_after_tau0 = 0;
  // system.species: a mixture of two or more species (empty: one species of mass m and diameter
  // sigma, the default); `species_table` is what SystemInfo::species points into.
  std::vector<SpeciesSpec> species;
  std::shared_ptr<const SpeciesTable> species_table;

  PluginUse initial_state;
  PluginUse collision;
  std::vector<PluginUse> forcings;
  std::vector<PluginUse> boundaries;  // slab: [0] y_min, [1] y_max
  std::vector<PluginUse> diagnostics;

  std::filesystem::path output_file;
  SourceLocation output_file_where;  // where output.file was given (file "": the default name)
  bool output_particles = false;  // write the final particle state (/particles)
  bool output_realizations = false;  // also write each realization's own diagnostics (<group>/realizations/<k>)
  bool output_plots = false;  // after a successful run, draw the output with `gdsmc plot` (PNGs in <output>_plots/)

  double mean_free_path0() const;  // lambda0 = 1 / (sqrt(2) pi n sigma^2)
  double time_unit0() const;       // tau0 = lambda0 / sqrt(2 T0 / m)
  // The plugin entry at a key path ("collision", "forcings[0]", "boundaries.y_min"), or nullptr.
  const PluginUse* use_at(const std::string& path) const;
};

// What loading a pipeline gives: its configuration, every plugin library found on the search path
// (the pipeline's entries point into it; the cases of its sweep are resolved against it, so no
// library is loaded twice), and the warnings (plugin files on the search path that could not be
// used, `plugins:` entries that do not exist, a time step that crosses the slab's gap).
struct LoadedPipeline {
  Pipeline pipeline;
  std::shared_ptr<const PluginRegistry> plugins;
  std::vector<std::string> warnings;
};

// Read, check and resolve a pipeline. `overrides` are "key.path=value" strings (--set);
// `extra_plugin_paths` come first in the search path. Throws PipelineError with every problem found
// (and the warnings).
LoadedPipeline load_pipeline(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                             const std::vector<std::filesystem::path>& extra_plugin_paths = {});

// The cases of a sweep, each loaded in time independent of the size of the sweep (so that
// expanding N cases costs N times one case): the base pipeline's file is not read again and its
// `sweep:` section is never parsed again; each case parses the base text with that section's
// lines emptied (every other location unchanged), applies the base's --set overrides and then the
// case's values, and is checked like load_pipeline with the base's registry. A problem in a value
// the sweep gave is located at that value's entry in the sweep, not phrased as a --set.
class SweepCaseLoader {
 public:
  explicit SweepCaseLoader(const LoadedPipeline& base);  // keeps a reference to `base`
  // The case with these values (one per axis). Throws PipelineError with every problem found.
  // Its source_text and resolved_text are empty (the study's provenance is the base pipeline's).
  Pipeline load(const std::vector<const SweepAxis::Value*>& values) const;

 private:
  const LoadedPipeline& base_;
  std::string text_;  // base.source_text without its sweep section
};

}  // namespace gdsmc::host
