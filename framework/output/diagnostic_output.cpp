#include "output/diagnostic_output.hpp"

#include <algorithm>
#include <stdexcept>

namespace gdsmc::host {

void DiagnosticOutput::check_name(const std::string& name) const {
  if (name.empty() || name.find('/') != std::string::npos || name == "time" || name == "collisions_per_particle" ||
      name == "bin_centre")
    throw std::runtime_error("diagnostic '" + group_ + "' used an invalid output name '" + name +
                             "' (non-empty, no '/', not 'time', 'collisions_per_particle' or 'bin_centre')");
  if (written(name)) throw std::runtime_error("diagnostic '" + group_ + "' wrote '" + name + "' twice");
}

bool DiagnosticOutput::written(const std::string& name) const {
  auto taken = [&](const auto& v) { return std::any_of(v.begin(), v.end(), [&](const auto& e) { return e.name == name; }); };
  return taken(columns) || taken(profiles) || taken(arrays) || taken(histograms) || taken(scalars);
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

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> names;
  std::size_t start = 0;
  for (std::size_t comma = 0; comma != std::string::npos; start = comma + 1) {
    comma = list.find(',', start);
    std::string name = list.substr(start, comma == std::string::npos ? comma : comma - start);
    name.erase(0, name.find_first_not_of(' '));
    name.erase(name.find_last_not_of(' ') + 1);
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

void DiagnosticOutput::theory(const std::string& dataset, const std::string& measured, const std::string& equation) {
  const std::string what = "diagnostic '" + group_ + "' marked '" + dataset + "' as theory";
  if (!written(dataset)) throw std::runtime_error(what + ", but it wrote no dataset of that name (write it first)");
  if (theory_tags.count(dataset)) throw std::runtime_error(what + " twice");
  if (equation.empty()) throw std::runtime_error(what + " without its equation (cite it, e.g. \"002 Eq. 27\")");
  std::string list;
  for (const std::string& m : split_names(measured)) {
    if (m == dataset || !written(m))
      throw std::runtime_error(what + " of '" + m + "', " +
                               (m == dataset ? std::string("itself") : "which it has not written (write the measured dataset first)"));
    list += (list.empty() ? "" : ",") + m;
  }
  theory_tags[dataset] = TheoryTag{list, equation};
}

const DiagnosticOutput::Array* DiagnosticOutput::find_array(const std::string& name) const {
  const auto a = std::find_if(arrays.begin(), arrays.end(), [&](const Array& e) { return e.name == name; });
  return a == arrays.end() ? nullptr : &*a;
}

void DiagnosticOutput::axis(const std::string& dataset, const std::string& grid) {
  const std::string what = "diagnostic '" + group_ + "' gave '" + dataset + "' the axis '" + grid + "'";
  const Array *d = find_array(dataset), *g = find_array(grid);
  if (!d || !g) throw std::runtime_error(what + ", but '" + (d ? grid : dataset) + "' is not an array it wrote (write both first)");
  if (axes.count(dataset)) throw std::runtime_error(what + ", but it already has the axis '" + axes[dataset] + "'");
  if (dataset == grid || d->shape.size() != 1 || g->shape.size() != 1 || d->data.size() != g->data.size())
    throw std::runtime_error(what + ": both must be 1-D arrays of the same length, and two arrays (" +
                             std::to_string(d->data.size()) + " and " + std::to_string(g->data.size()) + " values)");
  axes[dataset] = grid;
}

void DiagnosticOutput::tag_steady_means() {
  const std::string suffix = ".steady_mean";
  std::map<std::string, TheoryTag> derived;
  for (const auto& [name, tag] : theory_tags) {
    if (!written(name + suffix)) continue;
    std::string list;
    for (const std::string& m : split_names(tag.measured))
      if (written(m + suffix)) list += (list.empty() ? "" : ",") + m + suffix;
    derived[name + suffix] = TheoryTag{list, tag.equation};
  }
  theory_tags.insert(derived.begin(), derived.end());
}

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

namespace {
// A list's length, checked against what is left of the checkpoint.
std::size_t read_count(StateReader& in, const std::string& name) {
  std::uint64_t n = 0;
  in.read(name, n);
  if (n > in.remaining()) throw StateError("checkpoint entry '" + name + "': a damaged length " + std::to_string(n));
  return static_cast<std::size_t>(n);
}
void write_text3(StateWriter& out, const std::string& prefix, const std::string& a, const std::string& b,
                 const std::string& c) {
  out.write(prefix + ".name", a);
  out.write(prefix + ".unit", b);
  out.write(prefix + ".doc", c);
}
void read_text3(StateReader& in, const std::string& prefix, std::string& a, std::string& b, std::string& c) {
  in.read(prefix + ".name", a);
  in.read(prefix + ".unit", b);
  in.read(prefix + ".doc", c);
}
}  // namespace

void DiagnosticOutput::save(StateWriter& out) const {
  out.write("time", time);
  out.write("collisions_per_particle", collisions_per_particle);
  out.write("bin_centres", bin_centres);
  out.write("columns", static_cast<std::uint64_t>(columns.size()));
  for (const auto& c : columns) {
    write_text3(out, "column", c.name, c.unit, c.doc);
    out.write("column.values", c.values);
  }
  out.write("profiles", static_cast<std::uint64_t>(profiles.size()));
  for (const auto& p : profiles) {
    write_text3(out, "profile", p.name, p.unit, p.doc);
    out.write("profile.values", p.values);
  }
  out.write("arrays", static_cast<std::uint64_t>(arrays.size()));
  for (const auto& a : arrays) {
    write_text3(out, "array", a.name, a.unit, a.doc);
    out.write("array.data", a.data);
    std::vector<std::uint64_t> shape(a.shape.begin(), a.shape.end());
    out.write("array.shape", shape);
  }
  out.write("histograms", static_cast<std::uint64_t>(histograms.size()));
  for (const auto& h : histograms) {
    write_text3(out, "histogram", h.name, h.edge_unit, h.value_unit);
    out.write("histogram.doc", h.doc);
    out.write("histogram.edges", h.edges);
    out.write("histogram.values", h.values);
  }
  out.write("scalars", static_cast<std::uint64_t>(scalars.size()));
  for (const auto& v : scalars) {
    write_text3(out, "scalar", v.name, v.unit, v.doc);
    out.write("scalar.value", v.value);
  }
  out.write("attributes", static_cast<std::uint64_t>(attributes.size()));
  for (const auto& [k, v] : attributes) {
    out.write("attribute.name", k);
    out.write("attribute.value", v);
  }
  out.write("theory_tags", static_cast<std::uint64_t>(theory_tags.size()));  // SDK 6.3 on
  for (const auto& [k, t] : theory_tags) {
    out.write("theory.name", k);
    out.write("theory.measured", t.measured);
    out.write("theory.equation", t.equation);
  }
  out.write("axes", static_cast<std::uint64_t>(axes.size()));  // SDK 6.4 on
  for (const auto& [k, g] : axes) {
    out.write("axis.name", k);
    out.write("axis.grid", g);
  }
}

void DiagnosticOutput::load(StateReader& in) {
  // What begin() declared must be what the checkpoint holds.
  auto names = [](const auto& list) {
    std::string t;
    for (const auto& e : list) t += (t.empty() ? "" : ", ") + e.name;
    return t;
  };
  const std::string declared_columns = names(columns), declared_profiles = names(profiles);
  in.read("time", time);
  in.read("collisions_per_particle", collisions_per_particle);
  in.read("bin_centres", bin_centres);
  columns.assign(read_count(in, "columns"), Column{});
  for (auto& c : columns) {
    read_text3(in, "column", c.name, c.unit, c.doc);
    in.read("column.values", c.values);
  }
  profiles.assign(read_count(in, "profiles"), Profile{});
  for (auto& p : profiles) {
    read_text3(in, "profile", p.name, p.unit, p.doc);
    in.read("profile.values", p.values);
  }
  arrays.assign(read_count(in, "arrays"), Array{});
  for (auto& a : arrays) {
    read_text3(in, "array", a.name, a.unit, a.doc);
    in.read("array.data", a.data);
    std::vector<std::uint64_t> shape;
    in.read("array.shape", shape);
    a.shape.assign(shape.begin(), shape.end());
  }
  histograms.assign(read_count(in, "histograms"), Histogram{});
  for (auto& h : histograms) {
    read_text3(in, "histogram", h.name, h.edge_unit, h.value_unit);
    in.read("histogram.doc", h.doc);
    in.read("histogram.edges", h.edges);
    in.read("histogram.values", h.values);
  }
  scalars.assign(read_count(in, "scalars"), Scalar{});
  for (auto& v : scalars) {
    read_text3(in, "scalar", v.name, v.unit, v.doc);
    in.read("scalar.value", v.value);
  }
  if (names(columns) != declared_columns || names(profiles) != declared_profiles)
    throw StateError("checkpoint of diagnostic '" + group_ + "': it holds the series [" + names(columns) +
                     "] and profiles [" + names(profiles) + "], the diagnostic declares [" + declared_columns + "] and [" +
                     declared_profiles + "]");
  attributes.clear();
  const std::size_t n = read_count(in, "attributes");
  for (std::size_t k = 0; k < n; ++k) {
    std::string key, value;
    in.read("attribute.name", key);
    in.read("attribute.value", value);
    attributes[key] = value;
  }
  load_tags(in);
}

void DiagnosticOutput::load_tags(StateReader& in) {
  // A checkpoint from before SDK 6.3 has no theory tags, one from before 6.4 no axes: those made in begin() stay.
  if (in.peek_name() == "theory_tags") {
    theory_tags.clear();
    for (std::size_t k = read_count(in, "theory_tags"); k > 0; --k) {
      std::string name;
      TheoryTag t;
      in.read("theory.name", name);
      in.read("theory.measured", t.measured);
      in.read("theory.equation", t.equation);
      theory_tags[name] = t;
    }
  }
  if (in.peek_name() != "axes") return;
  axes.clear();
  for (std::size_t k = read_count(in, "axes"); k > 0; --k) {
    std::string name, grid;
    in.read("axis.name", name);
    in.read("axis.grid", grid);
    axes[name] = grid;
  }
}

}  // namespace gdsmc::host
