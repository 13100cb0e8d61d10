// `gdsmc inspect`: the provenance of a gdsmc output file and every dataset with its shape and unit
// (HDF5 C API; docs/output-format.md describes the layout).
#include <hdf5.h>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "engine/engine.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

const char* const kInspectHelp = R"(gdsmc inspect OUTPUT.h5 [options]

Prints what a gdsmc output file holds, readably in a terminal (no Python needed):
  - its provenance: the gdsmc version and SDK ABI that wrote it, the pipeline file, the seed, the
    --set overrides, the number of realizations, the run's totals (/run) and where its steps' time
    went (flight, sort, collisions, ...: /run/stage_seconds.*), the first lines of the
    pipeline as run (after --set), and every plugin with its version, library and parameters
    (/plugins; in a sweep, those of each case, with the case's label);
  - every dataset, in tree order, with its shape and its unit (the `unit` attribute).
Use h5py, h5dump or `gdsmc plot` for the values (docs/output-format.md).

Options:
  -l, --long             also the whole pipeline text and each dataset's description
  -h, --help             this text

Exit status: 0 printed, 1 not an HDF5 file or not a gdsmc output, 2 bad command line.
)";

namespace {

constexpr int kPipelineLines = 12;

// An HDF5 identifier closed on scope exit.
struct Id {
  hid_t id;
  herr_t (*close)(hid_t);
  Id(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  Id(const Id&) = delete;
  ~Id() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

// An attribute of obj as text (a string as is, a number with `format`); empty if absent.
std::string attribute(hid_t obj, const std::string& name, const char* format = "%.10g") {
  if (H5Aexists(obj, name.c_str()) <= 0) return "";
  Id a(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (a < 0) return "";
  Id type(H5Aget_type(a), H5Tclose);
  if (H5Tget_class(type) == H5T_STRING) {
    if (H5Tis_variable_str(type) > 0) {
      Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(mem, H5T_VARIABLE);
      H5Tset_cset(mem, H5Tget_cset(type));
      char* s = nullptr;
      if (H5Aread(a, mem, &s) < 0 || !s) return "";
      std::string out = s;
      H5free_memory(s);
      return out;
    }
    std::string buf(H5Tget_size(type), '\0');
    if (H5Aread(a, type, buf.data()) < 0) return "";
    return buf.substr(0, buf.find('\0'));
  }
  double v = 0;
  if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::vector<std::string> attribute_names(hid_t obj) {
  std::vector<std::string> names;
  auto cb = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &names);
  return names;
}

std::vector<std::string> members(hid_t group) {
  std::vector<std::string> names;
  auto cb = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &names);
  return names;
}

bool has_group(hid_t loc, const std::string& path) {
  if (H5Lexists(loc, path.c_str(), H5P_DEFAULT) <= 0) return false;
  H5O_info_t info;
  return H5Oget_info_by_name(loc, path.c_str(), &info, H5P_DEFAULT) >= 0 && info.type == H5O_TYPE_GROUP;
}

void field(const std::string& name, const std::string& value) {
  std::string pad(name.size() < 16 ? 16 - name.size() : 1, ' ');
  std::istringstream lines(value.empty() ? "(none)" : value);
  std::string line;
  bool first = true;
  while (std::getline(lines, line)) {
    std::cout << "  " << (first ? name + pad : std::string(name.size() + pad.size(), ' ')) << line << "\n";
    first = false;
  }
}

// The plugins of /plugins under `root` (the file, or /cases/<k>).
void print_plugins(hid_t root, const std::string& indent) {
  if (!has_group(root, "plugins")) return;
  Id plugins(H5Gopen2(root, "plugins", H5P_DEFAULT), H5Gclose);
  for (const auto& role : members(plugins)) {
    Id g(H5Gopen2(plugins, role.c_str(), H5P_DEFAULT), H5Gclose);
    std::string params;
    for (const auto& a : attribute_names(g))
      if (a.rfind("param.", 0) == 0) params += (params.empty() ? "" : ", ") + a.substr(6) + "=" + attribute(g, a);
    std::string line = indent + role;
    line += std::string(line.size() < indent.size() + 16 ? indent.size() + 16 - line.size() : 1, ' ');
    line += attribute(g, "plugin") + " " + attribute(g, "version");
    const std::string instance = attribute(g, "instance");
    if (!instance.empty() && instance != attribute(g, "plugin")) line += " (name: " + instance + ")";
    std::cout << line << "\n" << indent << "                library " << attribute(g, "library");
    const std::string hash = attribute(g, "library_hash");
    if (!hash.empty()) std::cout << " (content hash " << hash << ")";
    std::cout << "\n";
    if (!params.empty()) std::cout << indent << "                params  " << params << "\n";
  }
}

void print_run(hid_t root) {
  if (!has_group(root, "run")) return;
  Id run(H5Gopen2(root, "run", H5P_DEFAULT), H5Gclose);
  auto number = [&](const char* name) { return attribute(run, name, "%.6g"); };
  // The counts are realization 0's; the wall time is that of every realization (output-format.md).
  const std::string realizations = attribute(run, "realizations", "%.0f");
  const bool several = !realizations.empty() && realizations != "1";
  field(several ? "run (realization 0)" : "run",
        number("steps") + " steps to t = " + number("final_time_tau0") + " tau0, s = " +
            number("collisions_per_particle") + " collisions per particle, " + number("collisions") + " collisions");
  field(several ? "wall time (all " + realizations + " realizations)" : "wall time", number("wall_seconds") + " s");
  // Where the steps' time went (/run/stage_seconds.*; files from before them have none).
  StageSeconds stages{};
  bool any = false;
  for (std::size_t k = 0; k < kStages; ++k) {
    const std::string text = attribute(run, stage_attribute(static_cast<Stage>(k)));
    if (text.empty()) continue;
    stages[k] = std::strtod(text.c_str(), nullptr);
    any = true;
  }
  if (any) field("steps' time [s]", stage_times_text(stages));
}

struct Entry {
  std::string path, shape, unit, description;
};

std::vector<Entry> datasets(hid_t file) {
  std::vector<Entry> out;
  auto cb = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    H5O_info_t info;
    if (H5Oget_info_by_name(group, name, &info, H5P_DEFAULT) < 0 || info.type != H5O_TYPE_DATASET) return 0;
    Id d(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    Id space(H5Dget_space(d), H5Sclose);
    Id type(H5Dget_type(d), H5Tclose);
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(rank > 0 ? rank : 0);
    if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    std::string shape = rank == 0 ? "scalar" : "[";
    for (int k = 0; k < rank; ++k) shape += (k ? " x " : "") + std::to_string(dims[k]);
    if (rank > 0) shape += "]";
    if (H5Tget_class(type) == H5T_STRING) shape += " text";
    const std::string unit = attribute(d, "unit");
    static_cast<std::vector<Entry>*>(data)->push_back(
        {"/" + std::string(name), shape, H5Tget_class(type) == H5T_STRING && unit.empty() ? "-" : unit, attribute(d, "description")});
    return 0;
  };
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, cb, &out);
  return out;
}

}  // namespace

int cmd_inspect(int argc, char** argv) {
  Args args;
  std::string error;
  if (!parse_args(argc, argv, 2, command_options("inspect"), args, error)) return usage_error("inspect: " + error);
  if (args.has("--help")) return std::cout << kInspectHelp, 0;
  if (args.positional.size() != 1) return usage_error("inspect takes one OUTPUT.h5 (a file written by `gdsmc run`)");
  const bool full = args.has("--long");
  const std::string path = args.positional[0];
  const std::string expected = " (expected a gdsmc output file, OUTPUT.h5 written by `gdsmc run`)";
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::cerr << "gdsmc inspect: " << path << ": no such file" << expected << "\n", 1;
  if (!fs::is_regular_file(path, ec))
    return std::cerr << "gdsmc inspect: " << path << ": not a regular file" << expected << "\n", 1;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (H5Fis_hdf5(path.c_str()) <= 0)
    return std::cerr << "gdsmc inspect: " << path << ": not an HDF5 file" << expected << "\n", 1;
  Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) return std::cerr << "gdsmc inspect: " << path << ": cannot open it as HDF5" << expected << "\n", 1;
  if (H5Aexists(file, "gdsmc_version") <= 0 || H5Aexists(file, "seed") <= 0)
    return std::cerr << "gdsmc inspect: " << path
                     << ": an HDF5 file but not a gdsmc output: its root has no gdsmc_version and seed attributes "
                        "(the provenance every output of `gdsmc run` carries)\n",
           1;

  std::cout << path << ": gdsmc output\n";
  field("gdsmc version", attribute(file, "gdsmc_version") + " (SDK ABI " + attribute(file, "sdk_abi") + ")");
  field("pipeline file", attribute(file, "pipeline_file"));
  field("seed", attribute(file, "seed"));
  field("realizations", attribute(file, "realizations"));
  field("overrides", attribute(file, "overrides"));
  field("units", attribute(file, "units"));
  print_run(file);

  const std::string pipeline = attribute(file, "pipeline");
  std::istringstream lines(pipeline);
  std::vector<std::string> text;
  for (std::string line; std::getline(lines, line);) text.push_back(line);
  const std::size_t shown = full ? text.size() : std::min<std::size_t>(text.size(), kPipelineLines);
  std::cout << "  pipeline as run (root attribute `pipeline`, " << text.size() << " lines"
            << (shown < text.size() ? "; the first " + std::to_string(shown) + ", --long for all" : "") << "):\n";
  for (std::size_t k = 0; k < shown; ++k) std::cout << "    | " << text[k] << "\n";

  if (has_group(file, "cases")) {
    Id cases(H5Gopen2(file, "cases", H5P_DEFAULT), H5Gclose);
    std::vector<std::string> names = members(cases);  // by name: 0, 1, 10, 2 ... -> by number
    std::stable_sort(names.begin(), names.end(),
                     [](const std::string& a, const std::string& b) { return a.size() != b.size() ? a.size() < b.size() : a < b; });
    std::cout << "  sweep: " << names.size() << " cases (/cases/<k>; /summary has one row per case)\n";
    for (const auto& k : names) {
      Id c(H5Gopen2(cases, k.c_str(), H5P_DEFAULT), H5Gclose);
      std::cout << "  case " << k << ": " << attribute(c, "case") << "\n";
      print_run(c);
      print_plugins(c, "    ");
    }
  } else {
    std::cout << "  plugins (/plugins):\n";
    print_plugins(file, "    ");
  }

  const std::vector<Entry> all = datasets(file);
  std::size_t wpath = 0, wshape = 0;
  for (const auto& e : all) {
    wpath = std::max(wpath, std::min<std::size_t>(e.path.size(), 64));
    wshape = std::max(wshape, e.shape.size());
  }
  std::cout << "datasets (" << all.size() << "; path, shape, unit" << (full ? ", description" : "") << "):\n";
  for (const auto& e : all) {
    std::string line = "  " + e.path;
    line += std::string(e.path.size() < wpath ? wpath - e.path.size() + 2 : 2, ' ');
    line += e.shape + std::string(wshape - e.shape.size() + 2, ' ') + e.unit;
    std::cout << line << "\n";
    if (full && !e.description.empty()) std::cout << "      " << e.description << "\n";
  }
  return 0;
}

}  // namespace gdsmc::host
