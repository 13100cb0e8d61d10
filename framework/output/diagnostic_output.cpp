#include "output/diagnostic_output.hpp"

#include <algorithm>
#include <stdexcept>

namespace gdsmc::host {

void DiagnosticOutput::check_name(const std::string& name) const {
  if (name.empty() || name.find('/') != std::string::npos || name == "time" || name == "collisions_per_particle")
    throw std::runtime_error("diagnostic '" + group_ + "' used an invalid output name '" + name +
                             "' (non-empty, no '/', not 'time' or 'collisions_per_particle')");
  auto taken = [&](const auto& v) { return std::any_of(v.begin(), v.end(), [&](const auto& e) { return e.name == name; }); };
  if (taken(columns) || taken(arrays) || taken(histograms) || taken(scalars))
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
}

}  // namespace gdsmc::host
