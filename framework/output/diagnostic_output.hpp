// What one diagnostic writes through the SDK sink, held in memory until the run ends.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/output.hpp>
#include <gdsmc/state.hpp>

namespace gdsmc::host {

// What one diagnostic wrote through the SDK sink.
class DiagnosticOutput final : public OutputSink {
 public:
  struct Column {
    std::string name, unit, doc;
    std::vector<double> values;
  };
  // A profile series: one row of bins values per record, row-major (record x bin).
  struct Profile {
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
  // A dataset marked as theory (OutputSink::theory): the measured datasets it is theory for (names
  // separated by commas, or "") and the equation it cites.
  struct TheoryTag {
    std::string measured, equation;
  };

  DiagnosticOutput(std::string group, std::vector<std::string>* summary) : group_(std::move(group)), summary_(summary) {}

  std::size_t series(const std::string& name, const std::string& unit, const std::string& doc) override;
  void append(std::size_t id, double value) override;
  std::size_t profile(const std::string& name, const std::string& unit, const std::string& doc) override;
  void append_profile(std::size_t id, const double* values) override;
  void array(const std::string& name, const std::vector<double>& data, const std::vector<std::size_t>& shape,
             const std::string& unit, const std::string& doc) override;
  void histogram(const std::string& name, const std::vector<double>& edges, const std::vector<double>& values,
                 const std::string& edge_unit, const std::string& value_unit, const std::string& doc) override;
  void scalar(const std::string& name, double value, const std::string& unit, const std::string& doc) override;
  void attribute(const std::string& name, const std::string& value) override;
  void summary(const std::string& line) override;
  void theory(const std::string& dataset, const std::string& measured, const std::string& equation) override;
  void axis(const std::string& dataset, const std::string& grid) override;

  // The sampling bins along y of the profiles, their centres in lambda0 (SystemInfo::bins of them).
  // The host calls this before Diagnostic::begin; a profile declared without it is refused.
  void set_bins(std::vector<double> centres_lambda0);
  std::size_t bins() const { return bin_centres.size(); }

  // The host's own columns, one entry per record: mean time (tau0) and s of the window's samples.
  void begin_record(double time_tau0, double s);
  // Throws if a record left a series or a profile with other than one append per record.
  void check_record(const std::string& plugin) const;

  // The host's steady means of theory: "<X>.steady_mean" of a theory series or profile X becomes
  // theory for "<M>.steady_mean" of its measured M (those that have one), with X's equation.
  void tag_steady_means();

  // Checkpoints: everything written so far (not the realizations, which exist only in a study's
  // averages), replaced wholesale on load.
  void save(StateWriter& out) const;
  void load(StateReader& in);

  const std::string& group() const { return group_; }
  std::vector<double> time, collisions_per_particle;
  std::vector<Column> columns;
  std::vector<double> bin_centres;  // [lambda0]
  std::vector<Profile> profiles;
  std::vector<Array> arrays;
  std::vector<Histogram> histograms;
  std::vector<Scalar> scalars;
  std::map<std::string, std::string> attributes;
  std::map<std::string, TheoryTag> theory_tags;  // by dataset name
  std::map<std::string, std::string> axes;        // OutputSink::axis: the grid of each array that has one
  // Each realization's own output (output.realizations), written under <group>/realizations/<k>.
  std::vector<DiagnosticOutput> realizations;

 private:
  void check_name(const std::string& name) const;
  bool written(const std::string& name) const;
  const Array* find_array(const std::string& name) const;
  void load_tags(StateReader& in);
  std::string group_;
  std::vector<std::string>* summary_;
};

// The names of a list separated by commas ("a2, a2_mean"), spaces around them and empty entries dropped.
std::vector<std::string> split_names(const std::string& list);

// The centres of the sampling bins along y, in lambda0: the argument of DiagnosticOutput::set_bins.
std::vector<double> bin_centres_lambda0(const SystemInfo& system);

}  // namespace gdsmc::host
