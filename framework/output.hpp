// Results held in memory during a run and written to one HDF5 file at the end, under a temporary
// name that is renamed only on success.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gdsmc/output.hpp>

namespace gdsmc::host {

// What one diagnostic wrote through the SDK sink.
class DiagnosticOutput final : public OutputSink {
 public:
  struct Column {
    std::string name, unit, doc;
    std::vector<double> values;
  };
  struct Array {
    std::string name, unit, doc;
    std::vector<double> data;
    std::vector<std::size_t> shape;
  };
  struct Histogram {
    std::string name, edge_unit, value_unit, doc;
    std::vector<double> edges, values;
  };
  struct Scalar {
    std::string name, unit, doc;
    double value;
  };

  DiagnosticOutput(std::string group, std::vector<std::string>* summary) : group_(std::move(group)), summary_(summary) {}

  std::size_t series(const std::string& name, const std::string& unit, const std::string& doc) override;
  void append(std::size_t id, double value) override;
  void array(const std::string& name, const std::vector<double>& data, const std::vector<std::size_t>& shape,
             const std::string& unit, const std::string& doc) override;
  void histogram(const std::string& name, const std::vector<double>& edges, const std::vector<double>& values,
                 const std::string& edge_unit, const std::string& value_unit, const std::string& doc) override;
  void scalar(const std::string& name, double value, const std::string& unit, const std::string& doc) override;
  void attribute(const std::string& name, const std::string& value) override;
  void summary(const std::string& line) override;

  // The host's own columns, one entry per record: mean time (tau0) and s of the window's samples.
  void begin_record(double time_tau0, double s);
  // Throws if a record left a column shorter or longer than the time column.
  void check_record(const std::string& plugin) const;

  const std::string& group() const { return group_; }
  std::vector<double> time, collisions_per_particle;
  std::vector<Column> columns;
  std::vector<Array> arrays;
  std::vector<Histogram> histograms;
  std::vector<Scalar> scalars;
  std::map<std::string, std::string> attributes;

 private:
  void check_name(const std::string& name) const;
  std::string group_;
  std::vector<std::string>* summary_;
};

struct PluginProvenance {
  std::string role, instance, plugin, version, file;
  std::map<std::string, std::string> parameters;  // as resolved, reduced units
};

// A per-particle dataset of the final state: shape [components, N] (or [N] for one component).
struct ParticleDataset {
  std::string name, unit, doc;
  int components = 1;
  std::vector<double> data;
};

// One simulated case (one point of a sweep; all its realizations averaged).
struct CaseOutput {
  std::string group;                            // "" for a single case (written at the root), else "cases/<k>"
  std::map<std::string, std::string> attributes;  // e.g. the sweep values of this case
  std::map<std::string, double> system;         // /system attributes
  std::map<std::string, double> run;            // /run attributes
  std::vector<PluginProvenance> plugins;
  std::vector<DiagnosticOutput> diagnostics;
  std::vector<ParticleDataset> particles;       // empty unless output.particles (realization 0)
};

// A column of the /summary table of a sweep: one entry per case.
struct SummaryColumn {
  std::string name, unit, doc;
  std::vector<double> values;       // numeric column, or
  std::vector<std::string> labels;  // text column (when values is empty)
};

struct StudyOutput {
  std::map<std::string, std::string> root_attributes;
  std::map<std::string, double> root_numbers;
  std::vector<CaseOutput> cases;
  std::vector<SummaryColumn> summary;
};

// Write under "<file>.partial-<pid>" and rename to `file` on success. On failure, no file is left
// under either name and the error is thrown.
void write_hdf5(const std::filesystem::path& file, const StudyOutput& out);

}  // namespace gdsmc::host
