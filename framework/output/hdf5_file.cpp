#include "output/hdf5_file.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

// The definition of s, the host's clock of collisions (paper 000's s(t)).
constexpr const char* kCollisionsPerParticle =
    "s(t), collisions per particle: accepted collisions / N (paper 000's s(t)); each collision involves two "
    "particles, so a particle has taken part in 2s collisions on average";

// Minimal RAII over HDF5 identifiers.
struct Id {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  Id(hid_t i, herr_t (*c)(hid_t), const std::string& what) : id(i), close(c) {
    if (id < 0) throw std::runtime_error("HDF5: cannot " + what);
  }
  Id(const Id&) = delete;
  ~Id() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
}

void attr_string(hid_t obj, const std::string& name, const std::string& value) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  check(H5Tset_size(type, H5T_VARIABLE), "set string size");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
  Id space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar space");
  Id attr(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, "create attribute " + name);
  const char* p = value.c_str();
  check(H5Awrite(attr, type, &p), "write attribute " + name);
}

void attr_double(hid_t obj, const std::string& name, double value) {
  Id space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar space");
  Id attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
          "create attribute " + name);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
}

void dataset(hid_t group, const std::string& name, const std::vector<double>& data, std::vector<hsize_t> shape,
             const std::string& unit, const std::string& doc) {
  Id space(shape.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
           H5Sclose, "create dataspace for " + name);
  Id set(H5Dcreate2(group, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
         "create dataset " + name);
  if (!data.empty()) check(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "write " + name);
  attr_string(set, "unit", unit);
  attr_string(set, "description", doc);
}

Id group(hid_t parent, const std::string& name) {
  return Id(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create group " + name);
}

void string_dataset(hid_t group, const std::string& name, const std::vector<std::string>& labels, const std::string& doc) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
  check(H5Tset_size(type, H5T_VARIABLE), "set string size");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
  const hsize_t n = labels.size();
  Id space(H5Screate_simple(1, &n, nullptr), H5Sclose, "create dataspace for " + name);
  Id set(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, "create dataset " + name);
  std::vector<const char*> p;
  for (const auto& l : labels) p.push_back(l.c_str());
  if (!p.empty()) check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "write " + name);
  attr_string(set, "unit", "");
  attr_string(set, "description", doc);
}

// Create every group along "a/b/c" under parent (those that do not exist yet).
Id open_or_create(hid_t parent, const std::string& path) {
  if (path.empty()) return Id(H5Gopen2(parent, "/", H5P_DEFAULT), H5Gclose, "open /");
  std::string sofar;
  std::size_t start = 0;
  while (true) {
    const auto slash = path.find('/', start);
    sofar = path.substr(0, slash);
    if (H5Lexists(parent, sofar.c_str(), H5P_DEFAULT) <= 0) {
      Id g(H5Gcreate2(parent, sofar.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create group " + sofar);
    }
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return Id(H5Gopen2(parent, path.c_str(), H5P_DEFAULT), H5Gclose, "open group " + path);
}

// One diagnostic's datasets (and its host columns) into g.
void write_diagnostic(hid_t g, const DiagnosticOutput& d) {
  for (const auto& [k, v] : d.attributes) attr_string(g, k, v);
  const hsize_t n = d.time.size();
  dataset(g, "time", d.time, {n}, "tau0", "time t / tau0 (mean over the samples of each record)");
  dataset(g, "collisions_per_particle", d.collisions_per_particle, {n}, "1",
          std::string(kCollisionsPerParticle) + "; per record, the mean over the record's samples");
  for (const auto& c : d.columns) dataset(g, c.name, c.values, {c.values.size()}, c.unit, c.doc);
  if (!d.profiles.empty())
    dataset(g, "bin_centre", d.bin_centres, {d.bins()}, "lambda0",
            "centre y of each sampling bin of the profiles (the slab spans y in [-Ly/2, Ly/2])");
  for (const auto& p : d.profiles) dataset(g, p.name, p.values, {p.values.size() / d.bins(), d.bins()}, p.unit, p.doc);
  for (const auto& a : d.arrays) {
    std::vector<hsize_t> shape(a.shape.begin(), a.shape.end());
    dataset(g, a.name, a.data, shape, a.unit, a.doc);
  }
  for (const auto& s : d.scalars) dataset(g, s.name, {s.value}, {}, s.unit, s.doc);
  for (const auto& h : d.histograms) {
    Id hg = group(g, h.name);
    attr_string(hg, "description", h.doc);
    dataset(hg, "edges", h.edges, {h.edges.size()}, h.edge_unit, "bin edges");
    dataset(hg, "values", h.values, {h.values.size()}, h.value_unit, h.doc);
  }
}

void write_case(hid_t file_id, const CaseOutput& out) {
  Id root = open_or_create(file_id, out.group);
  hid_t file = root;
  for (const auto& [k, v] : out.attributes) attr_string(file, k, v);
  {
    Id g = group(file, "system");
    for (const auto& [k, v] : out.system) attr_double(g, k, v);
  }
  {
    Id g = group(file, "run");
    for (const auto& [k, v] : out.run) attr_double(g, k, v);
    if (out.run.count("collisions_per_particle"))
      attr_string(g, "collisions_per_particle.description", std::string(kCollisionsPerParticle) + "; the value at the end of the run (realization 0)");
  }
  {
    Id plugins = group(file, "plugins");
    for (const auto& p : out.plugins) {
      Id g = group(plugins, p.role);
      attr_string(g, "plugin", p.plugin);
      attr_string(g, "version", p.version);
      attr_string(g, "instance", p.instance);
      attr_string(g, "library", p.file);
      for (const auto& [k, v] : p.parameters) attr_string(g, "param." + k, v);
    }
  }
  if (!out.particles.empty()) {
    Id g = group(file, "particles");
    for (const auto& d : out.particles) {
      const hsize_t n = d.data.size() / static_cast<hsize_t>(d.components);
      std::vector<hsize_t> shape = d.components == 1 ? std::vector<hsize_t>{n}
                                                     : std::vector<hsize_t>{static_cast<hsize_t>(d.components), n};
      dataset(g, d.name, d.data, shape, d.unit, d.doc);
    }
  }
  Id diags = group(file, "diagnostics");
  for (const auto& d : out.diagnostics) {
    Id g = group(diags, d.group());
    write_diagnostic(g, d);
    if (!d.realizations.empty()) {
      Id rg = group(g, "realizations");
      attr_string(rg, "description",
                  "each realization's own output, realizations/<k> for realization k (output.realizations: true); "
                  "its steady averages use the realization alone (batch means)");
      for (std::size_t k = 0; k < d.realizations.size(); ++k) {
        Id kg = group(rg, std::to_string(k));
        write_diagnostic(kg, d.realizations[k]);
      }
    }
  }
}

void write_file(const fs::path& path, const StudyOutput& out) {
  Id file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "create " + path.string());
  for (const auto& [k, v] : out.root_attributes) attr_string(file, k, v);
  for (const auto& [k, v] : out.root_numbers) attr_double(file, k, v);
  for (const auto& c : out.cases) write_case(file, c);
  if (!out.summary.empty()) {
    Id g = group(file, "summary");
    attr_string(g, "description", "one row per case of the sweep (cases/<k>), in case order");
    for (const auto& col : out.summary) {
      if (col.values.empty() && !col.labels.empty()) string_dataset(g, col.name, col.labels, col.doc);
      else dataset(g, col.name, col.values, {col.values.size()}, col.unit, col.doc);
    }
  }
  check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush " + path.string());
}

}  // namespace

void write_hdf5(const fs::path& file, const StudyOutput& out) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions, not printed
  fs::path tmp = file;
  tmp += ".partial-" + std::to_string(::getpid());
  try {
    write_file(tmp, out);
    fs::rename(tmp, file);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace gdsmc::host
