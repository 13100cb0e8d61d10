// The results of a study as they are written to the HDF5 file: per case, per plugin, per sweep.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "output/diagnostic_output.hpp"

namespace gdsmc::host {

struct PluginProvenance {
  std::string role, instance, plugin, version, file;
  std::string library_hash;  // the library file's content hash (16 hex digits, util/content_hash.hpp)
  std::map<std::string, std::string> parameters;  // as resolved, reduced units
};

// A per-particle dataset of the final state: shape [components, N] (or [N] for one component).
// While a run's output file is open its data is written there at once (`staged`: where), so
// that no second copy of the particles is held; otherwise (tests, tools) it is held in `data`.
struct ParticleDataset {
  std::string name, unit, doc;
  int components = 1;
  std::vector<double> data;
  std::string staged;  // the dataset's path in the open output file, or "" (in `data`)
};

// A per-particle quantity as the particle store holds it: components x count values,
// component-major, written divided by `scale`.
struct ParticleColumn {
  std::string name, unit, doc;
  int components = 1;
  const double* values = nullptr;
  std::size_t count = 0;
  double scale = 1;
};

// One simulated case (one point of a sweep; all its realizations averaged).
struct CaseOutput {
  std::string group;                            // "" for a single case (written at the root), else "cases/<k>"
  std::map<std::string, std::string> attributes;  // e.g. the sweep values of this case
  std::map<std::string, double> system;         // /system attributes
  std::map<std::string, double> run;            // /run attributes
  std::vector<ParticleDataset> system_arrays;   // /system datasets (the layers' edges; held in `data`)
  std::vector<PluginProvenance> plugins;
  std::vector<DiagnosticOutput> diagnostics;
  std::vector<ParticleDataset> particles;       // empty unless output.particles (realization 0)
};

// A column of the /summary table of a sweep: one entry per case.
struct SummaryColumn {
  std::string name, unit, doc;
  std::vector<double> values;       // numeric column, or
  std::vector<std::string> labels;  // text column (when values is empty)
  DiagnosticOutput::TheoryTag theory;  // a theory scalar's tag, its measured as columns "<group>.<name>"
};

struct StudyOutput {
  std::map<std::string, std::string> root_attributes;
  std::map<std::string, double> root_numbers;
  std::vector<CaseOutput> cases;
  std::vector<SummaryColumn> summary;
};

}  // namespace gdsmc::host
