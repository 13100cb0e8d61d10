#include "output/hdf5_file.hpp"

#include <algorithm>
#include <string>

#include <gdsmc/physics/units.hpp>

#include "output/hdf5_reader.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

// The definition of s, the host's clock of collisions (paper 000's s(t)).
constexpr const char* kCollisionsPerParticle =
    "s(t), collisions per particle: accepted collisions / N (paper 000's s(t)); each collision involves two "
    "particles, so a particle has taken part in 2s collisions on average";

// Where staged particle datasets wait for their case group (removed by commit).
constexpr const char* kStaging = ".gdsmc-staging";

// Particles per write of a particle dataset: bounds the scaled copy (1 MiB).
constexpr std::size_t kParticleChunk = std::size_t(1) << 17;


void init_hdf5() {
  static const bool done = [] {
    // No library clean-up at exit: HDF5 1.10 crashes there (H5F__close_cb) on a file whose close
    // failed, e.g. on a full disk. Every file is closed, or removed, before exit anyway.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions, not printed
    return true;
  }();
  (void)done;
}

// The system's message in the HDF5 error stack (a failed read or write: "No space left on
// device", "File too large"), else "".
herr_t find_system_error(unsigned, const H5E_error2_t* e, void* data) {
  const std::string desc = e && e->desc ? e->desc : "";
  const std::string key = "error message = '";
  const auto at = desc.find(key);
  if (at != std::string::npos) {
    const auto end = desc.find('\'', at + key.size());
    *static_cast<std::string*>(data) = desc.substr(at + key.size(), end == std::string::npos ? end : end - at - key.size());
  }
  return 0;
}

[[noreturn]] void fail(const std::string& what) {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, find_system_error, &reason);
  H5Eclear2(H5E_DEFAULT);
  throw OutputWriteError(reason.empty() ? "HDF5 could not " + what : reason + " (HDF5 could not " + what + ")");
}

void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

// Minimal RAII over HDF5 identifiers.
struct Id {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  Id(hid_t i, herr_t (*c)(hid_t), const std::string& what) : id(i), close(c) {
    if (id < 0) fail(what);
  }
  Id(const Id&) = delete;
  ~Id() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

// The writing of one file: every dataset written checks the interrupt flag first.
class Writer {
 public:
  explicit Writer(const std::atomic<bool>* interrupt) : interrupt_(interrupt) {}

  void poll() const {
    if (interrupt_ && interrupt_->load()) throw OutputInterrupted("interrupted while writing the output file");
  }

  void attr_string(hid_t obj, const std::string& name, const std::string& value) const {
    Id type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
    check(H5Tset_size(type, H5T_VARIABLE), "set string size");
    check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
    Id space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar space");
    Id attr(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, "create attribute " + name);
    const char* p = value.c_str();
    check(H5Awrite(attr, type, &p), "write attribute " + name);
  }

  void attr_double(hid_t obj, const std::string& name, double value) const {
    Id space(H5Screate(H5S_SCALAR), H5Sclose, "create scalar space");
    Id attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
            "create attribute " + name);
    check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
  }

  void dataset(hid_t group, const std::string& name, const std::vector<double>& data, std::vector<hsize_t> shape,
               const std::string& unit, const std::string& doc) const {
    poll();
    Id space(shape.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
             H5Sclose, "create dataspace for " + name);
    Id set(H5Dcreate2(group, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
           "create dataset " + name);
    if (!data.empty()) check(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "write dataset " + name);
    attr_string(set, "unit", unit);
    attr_string(set, "description", doc);
  }

  // A per-particle dataset written from the store's arrays, kParticleChunk values at a time.
  void particle_dataset(hid_t group, const ParticleColumn& c) const {
    const hsize_t n = c.count, components = static_cast<hsize_t>(c.components);
    std::vector<hsize_t> shape = components == 1 ? std::vector<hsize_t>{n} : std::vector<hsize_t>{components, n};
    Id space(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose, "create dataspace for " + c.name);
    Id set(H5Dcreate2(group, c.name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
           "create dataset " + c.name);
    std::vector<double> scaled(c.scale != 1 ? std::min<std::size_t>(c.count, kParticleChunk) : 0);
    for (hsize_t comp = 0; comp < components; ++comp)
      for (std::size_t first = 0; first < c.count; first += kParticleChunk) {
        poll();
        const std::size_t m = std::min(kParticleChunk, c.count - first);
        const double* values = c.values + comp * c.count + first;
        if (c.scale != 1) {
          for (std::size_t k = 0; k < m; ++k) scaled[k] = values[k] / c.scale;
          values = scaled.data();
        }
        const hsize_t count[2] = {1, m}, start[2] = {comp, first};
        const hsize_t mem_count = m;
        Id memory(H5Screate_simple(1, &mem_count, nullptr), H5Sclose, "create dataspace for " + c.name);
        check(H5Sselect_hyperslab(space, H5S_SELECT_SET, components == 1 ? start + 1 : start, nullptr,
                                  components == 1 ? count + 1 : count, nullptr),
              "select part of " + c.name);
        check(H5Dwrite(set, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, values), "write dataset " + c.name);
      }
    attr_string(set, "unit", c.unit);
    attr_string(set, "description", c.doc);
  }

  Id group(hid_t parent, const std::string& name) const {
    return Id(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create group " + name);
  }

  void string_dataset(hid_t group, const std::string& name, const std::vector<std::string>& labels, const std::string& doc) const {
    poll();
    Id type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type");
    check(H5Tset_size(type, H5T_VARIABLE), "set string size");
    check(H5Tset_cset(type, H5T_CSET_UTF8), "set string charset");
    const hsize_t n = labels.size();
    Id space(H5Screate_simple(1, &n, nullptr), H5Sclose, "create dataspace for " + name);
    Id set(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, "create dataset " + name);
    std::vector<const char*> p;
    for (const auto& l : labels) p.push_back(l.c_str());
    if (!p.empty()) check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "write dataset " + name);
    attr_string(set, "unit", "");
    attr_string(set, "description", doc);
  }

  // Create every group along "a/b/c" under parent (those that do not exist yet).
  Id open_or_create(hid_t parent, const std::string& path) const {
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

  // The attributes of a theory dataset (OutputSink::theory) on the object `name` of g: a dataset,
  // or a histogram's group.
  void theory_tag(hid_t g, const std::string& name, const DiagnosticOutput::TheoryTag& tag) const {
    Id obj(H5Oopen(g, name.c_str(), H5P_DEFAULT), H5Oclose, "open " + name);
    attr_string(obj, "role", "theory");
    attr_string(obj, "theory_of", tag.measured);
    attr_string(obj, "equation", tag.equation);
  }

  // One diagnostic's datasets (and its host columns) into g.
  void diagnostic(hid_t g, const DiagnosticOutput& d) const {
    for (const auto& [k, v] : d.attributes) attr_string(g, k, v);
    const hsize_t n = d.time.size();
    dataset(g, "time", d.time, {n}, units::time, "time t / tau0 (mean over the samples of each record)");
    dataset(g, "collisions_per_particle", d.collisions_per_particle, {n}, units::dimensionless,
            std::string(kCollisionsPerParticle) + "; per record, the mean over the record's samples");
    for (const auto& c : d.columns) dataset(g, c.name, c.values, {c.values.size()}, c.unit, c.doc);
    if (!d.profiles.empty())
      dataset(g, "bin_centre", d.bin_centres, {d.bins()}, units::length,
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
    for (const auto& [name, tag] : d.theory_tags) theory_tag(g, name, tag);
    for (const auto& [name, grid] : d.axes) {  // OutputSink::axis
      Id obj(H5Oopen(g, name.c_str(), H5P_DEFAULT), H5Oclose, "open " + name);
      attr_string(obj, "axis", grid);
    }
  }

  void write_case(hid_t file_id, const CaseOutput& out) const {
    Id root = open_or_create(file_id, out.group);
    hid_t file = root;
    for (const auto& [k, v] : out.attributes) attr_string(file, k, v);
    {
      Id g = group(file, "system");
      for (const auto& [k, v] : out.system) attr_double(g, k, v);
      for (const auto& d : out.system_arrays) dataset(g, d.name, d.data, {d.data.size()}, d.unit, d.doc);
    }
    {
      Id g = group(file, "run");
      for (const auto& [k, v] : out.run) attr_double(g, k, v);
      if (out.run.count("collisions_per_particle"))
        attr_string(g, "collisions_per_particle.description",
                    std::string(kCollisionsPerParticle) + "; the value at the end of the run (realization 0)");
    }
    {
      Id plugins = group(file, "plugins");
      for (const auto& p : out.plugins) {
        Id g = group(plugins, p.role);
        attr_string(g, "plugin", p.plugin);
        attr_string(g, "version", p.version);
        attr_string(g, "instance", p.instance);
        attr_string(g, "library", p.file);
        attr_string(g, "library_hash", p.library_hash);
        for (const auto& [k, v] : p.parameters) attr_string(g, "param." + k, v);
      }
    }
    if (!out.particles.empty()) {
      Id g = group(file, "particles");
      for (const auto& d : out.particles) {
        if (!d.staged.empty()) {
          check(H5Lmove(file_id, d.staged.c_str(), g, d.name.c_str(), H5P_DEFAULT, H5P_DEFAULT), "move dataset " + d.name);
          continue;
        }
        const hsize_t n = d.data.size() / static_cast<hsize_t>(d.components);
        std::vector<hsize_t> shape = d.components == 1 ? std::vector<hsize_t>{n}
                                                       : std::vector<hsize_t>{static_cast<hsize_t>(d.components), n};
        dataset(g, d.name, d.data, shape, d.unit, d.doc);
      }
    }
    Id diags = group(file, "diagnostics");
    for (const auto& d : out.diagnostics) {
      Id g = group(diags, d.group());
      diagnostic(g, d);
      if (!d.realizations.empty()) {
        Id rg = group(g, "realizations");
        attr_string(rg, "description",
                    "each realization's own output, realizations/<k> for realization k (output.realizations: true); "
                    "its steady averages use the realization alone (batch means)");
        for (std::size_t k = 0; k < d.realizations.size(); ++k) {
          Id kg = group(rg, std::to_string(k));
          diagnostic(kg, d.realizations[k]);
        }
      }
    }
  }

  void write_file(hid_t file, const StudyOutput& out) const {
    for (const auto& [k, v] : out.root_attributes) attr_string(file, k, v);
    for (const auto& [k, v] : out.root_numbers) attr_double(file, k, v);
    for (const auto& c : out.cases) write_case(file, c);
    if (!out.summary.empty()) {
      Id g = group(file, "summary");
      attr_string(g, "description", "one row per case of the sweep (cases/<k>), in case order");
      for (const auto& col : out.summary) {
        if (col.values.empty() && !col.labels.empty()) string_dataset(g, col.name, col.labels, col.doc);
        else dataset(g, col.name, col.values, {col.values.size()}, col.unit, col.doc);
        if (!col.theory.equation.empty()) theory_tag(g, col.name, col.theory);
      }
    }
    if (H5Lexists(file, kStaging, H5P_DEFAULT) > 0) check(H5Ldelete(file, kStaging, H5P_DEFAULT), "remove group " + std::string(kStaging));
  }

 private:
  const std::atomic<bool>* interrupt_;
};

}  // namespace

OutputFile::OutputFile(const OutputTarget& target, const std::atomic<bool>* interrupt)
    : target_(target), tmp_(target), interrupt_(interrupt) {
  init_hdf5();
  file_ = H5Fcreate(tmp_.path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  void* handle = nullptr;
  const bool ours = file_ >= 0 && H5Fget_vfd_handle(file_, H5P_DEFAULT, &handle) >= 0 && handle &&
                    tmp_.is(*static_cast<int*>(handle));
  if (!ours) {
    std::string why;
    try {
      if (file_ < 0) fail("create " + tmp_.path().string());
    } catch (const OutputWriteError& e) {
      why = e.what();
    }
    if (file_ >= 0) H5Fclose(file_);
    file_ = -1;
    throw OutputPathError("cannot create the HDF5 file " + tmp_.path().string() +
                          (why.empty() ? ": the name was taken by another file" : ": " + why));
  }
}

OutputFile::~OutputFile() {
  if (file_ >= 0) H5Fclose(file_);  // may fail (disk full): the file is removed anyway
  // tmp_ removes the temporary file unless it was renamed.
}

std::vector<ParticleDataset> OutputFile::stage_particles(const std::vector<ParticleColumn>& columns) {
  const std::lock_guard<std::mutex> one_at_a_time(staging_);
  const Writer w(interrupt_);
  const std::string where = std::string(kStaging) + "/" + std::to_string(staged_++);
  Id g = w.open_or_create(file_, where);
  std::vector<ParticleDataset> out;
  for (const auto& c : columns) {
    w.particle_dataset(g, c);
    out.push_back(ParticleDataset{c.name, c.unit, c.doc, c.components, {}, "/" + where + "/" + c.name});
  }
  return out;
}

void OutputFile::commit(const StudyOutput& out) {
  const Writer w(interrupt_);
  w.write_file(file_, out);
  w.poll();
  const hid_t file = file_;
  file_ = -1;  // closed below, even when closing fails
  check(H5Fclose(file), "complete the file");
  w.poll();
  tmp_.rename_over(target_);
}

void write_hdf5(const fs::path& file, const StudyOutput& out) {
  OutputFile f(check_output_path(file, {}));
  f.commit(out);
}

std::optional<std::string> read_root_text(const fs::path& file, const std::string& name) {
  init_hdf5();
  if (!h5::is_hdf5(file)) return std::nullopt;
  const h5::Handle f = h5::open_read_only(file);
  if (!f) return std::nullopt;
  std::optional<std::string> text = h5::text_attribute(f, name);
  H5Eclear2(H5E_DEFAULT);
  return text;
}

}  // namespace gdsmc::host
