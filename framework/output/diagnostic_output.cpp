#include "output/diagnostic_output.hpp"

#include <algorithm>
#include <stdexcept>

namespace gdsmc::host {

void DiagnosticOutput::check_name(const std::string& name) const {
  if (name.empty() || name.find('/') != std::string::npos || name == "time" || name == "collisions_per_particle" ||
      name == "bin_centre")
    throw std::runtime_error("diagnostic '" + group_ + "' used an invalid output name '" + name +
                             "' (non-empty, no '/', not 'time', 'collisions_per_particle' or 'bin_centre')");
  auto taken = [&](const auto& v) { return std::any_of(v.begin(), v.end(), [&](const auto& e) { return e.name == name; }); };
  if (taken(columns) || taken(profiles) || taken(arrays) || taken(histograms) || taken(scalars))
    throw std::runtime_error("diagnostic '" + group_ + "' wrote '" + name + "' twice");
}

std::size_t DiagnosticOutput::series(const std::string& name, const std::string& unit, const std::string& doc) {
  check_name(name);
  columns.push_back(Column{name, unit, doc, {}});
  return columns.size() - 1;
}
void DiagnosticOutput::append(std::size_t id, double value) {
  if (id >= columns.size()) throw std::runtime_error("diagnostic '" + group_ + "' appended to an undeclared series");
  columns[id].values.push_back(value);
}
std::size_t DiagnosticOutput::profile(const std::string& name, const std::string& unit, const std::string& doc) {
  check_name(name);
  if (bin_centres.empty())
    throw std::runtime_error("diagnostic '" + group_ + "' declared profile '" + name +
                             "' but the host set no sampling bins (DiagnosticOutput::set_bins)");
  profiles.push_back(Profile{name, unit, doc, {}});
  return profiles.size() - 1;
}
void DiagnosticOutput::append_profile(std::size_t id, const double* values) {
  if (id >= profiles.size()) throw std::runtime_error("diagnostic '" + group_ + "' appended to an undeclared profile");
  if (!values) throw std::runtime_error("diagnostic '" + group_ + "' appended no values to profile '" + profiles[id].name + "'");
  profiles[id].values.insert(profiles[id].values.end(), values, values + bins());
}
void DiagnosticOutput::set_bins(std::vector<double> centres_lambda0) {
  if (!profiles.empty())
    throw std::runtime_error("diagnostic '" + group_ + "': the sampling bins were set after a profile was declared");
  bin_centres = std::move(centres_lambda0);
}
void DiagnosticOutput::array(const std::string& name, const std::vector<double>& data, const std::vector<std::size_t>& shape,
                             const std::string& unit, const std::string& doc) {
  check_name(name);
  std::size_t n = 1;
  for (auto s : shape) n *= s;
  if (n != data.size()) throw std::runtime_error("diagnostic '" + group_ + "': array '" + name + "' shape does not match its data");
  arrays.push_back(Array{name, unit, doc, data, shape});
}
void DiagnosticOutput::histogram(const std::string& name, const std::vector<double>& edges, const std::vector<double>& values,
                                 const std::string& edge_unit, const std::string& value_unit, const std::string& doc) {
  check_name(name);
  if (edges.size() != values.size() + 1)
    throw std::runtime_error("diagnostic '" + group_ + "': histogram '" + name + "' needs one more edge than values");
  histograms.push_back(Histogram{name, edge_unit, value_unit, doc, edges, values});
}
void DiagnosticOutput::scalar(const std::string& name, double value, const std::string& unit, const std::string& doc) {
  check_name(name);
  scalars.push_back(Scalar{name, unit, doc, value});
}
void DiagnosticOutput::attribute(const std::string& name, const std::string& value) { attributes[name] = value; }
void DiagnosticOutput::summary(const std::string& line) { summary_->push_back(line); }

void DiagnosticOutput::begin_record(double time_tau0, double s) {
  time.push_back(time_tau0);
  collisions_per_particle.push_back(s);
}
void DiagnosticOutput::check_record(const std::string& plugin) const {
  for (const auto& c : columns)
    if (c.values.size() != time.size())
      throw std::runtime_error("diagnostic plugin '" + plugin + "' (group '" + group_ + "') appended " +
                               std::to_string(c.values.size()) + " values to series '" + c.name + "' after " +
                               std::to_string(time.size()) + " records: exactly one per record is expected");
  for (const auto& p : profiles)
    if (p.values.size() != time.size() * bins())
      throw std::runtime_error("diagnostic plugin '" + plugin + "' (group '" + group_ + "') appended " +
                               std::to_string(p.values.size() / bins()) + " records to profile '" + p.name + "' after " +
                               std::to_string(time.size()) + " records: exactly one append_profile per record is expected");
}

std::vector<double> bin_centres_lambda0(const SystemInfo& system) {
  std::vector<double> centres(system.bins);
  for (std::size_t b = 0; b < system.bins; ++b) centres[b] = system.bin_centre(b) / system.mean_free_path0;
  return centres;
}

}  // namespace gdsmc::host
