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
#include "output/hdf5_reader.hpp"

namespace gdsmc::host {

namespace fs = std::filesystem;

const char* const kInspectHelp = R"(gdsmc inspect OUTPUT.h5 [options]

Prints what a gdsmc output file holds, readably in a terminal (no Python needed):
  - its provenance: the gdsmc version and SDK ABI that wrote it, the pipeline file, the seed, the
    --set overrides, the number of realizations, the run's totals (/run) and where its steps' time
    went (flight, sort, collisions, ...: /run/stage_seconds.*), the first lines of the
    pipeline as run (after --set), and every plugin with its version, library and parameters
    (/plugins; in a sweep, those of each case, with the case's label);
  - every dataset, in tree order, with its shape, its unit (the `unit` attribute) and, for theory
    a plugin wrote beside its measurements (OutputSink::theory), its tag from the attributes role,
    theory_of and equation: theory of a2 (001 Eq. 2.16), or theory (EQUATION) when it has no
    measured twin.
Use h5py, h5dump or `gdsmc plot` for the values (docs/output-format.md).

Options:
  -l, --long             also the whole pipeline text and each dataset's description
  -h, --help             this text

Exit status: 0 printed, 1 not an HDF5 file or not a gdsmc output, 2 bad command line.
)";

namespace {

constexpr int kPipelineLines = 12;

using h5::Handle;

// An attribute of obj as text (a string as is, a number with `format`); empty if absent.
std::string attribute(hid_t obj, const std::string& name, const char* format = "%.10g") {
  if (const auto text = h5::text_attribute(obj, name)) return *text;
  const auto value = h5::number_attribute(obj, name);
  if (!value) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, *value);
  return text;
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
  if (!h5::is_group(root, "plugins")) return;
  Handle plugins(H5Gopen2(root, "plugins", H5P_DEFAULT), H5Gclose);
  for (const auto& role : h5::members(plugins)) {
    Handle g(H5Gopen2(plugins, role.c_str(), H5P_DEFAULT), H5Gclose);
    std::string params;
    for (const auto& a : h5::attribute_names(g))
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
  if (!h5::is_group(root, "run")) return;
  Handle run(H5Gopen2(root, "run", H5P_DEFAULT), H5Gclose);
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
  std::string path, shape, unit, description, tag;
};

// The theory tag of OutputSink::theory: "theory of a2 (001 Eq. 2.16)"; "" for an object without role.
std::string theory_tag(hid_t d) {
  const std::string role = attribute(d, "role");
  if (role.empty()) return "";
  const std::string equation = attribute(d, "equation");
  std::string of;  // "a,b" -> "a, b"
  for (const char c : attribute(d, "theory_of")) of += c == ',' ? std::string(", ") : std::string(1, c);
  return role + (of.empty() ? "" : " of " + of) + (equation.empty() ? "" : " (" + equation + ")");
}

std::vector<Entry> datasets(hid_t file) {
  std::vector<Entry> out;
  auto cb = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    H5O_info_t info;
    if (H5Oget_info_by_name(group, name, &info, H5P_DEFAULT) < 0 || info.type != H5O_TYPE_DATASET) return 0;
    Handle d(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    Handle type(H5Dget_type(d), H5Tclose);
    const std::vector<hsize_t> dims = h5::shape(d);
    std::string shape = dims.empty() ? "scalar" : "[";
    for (std::size_t k = 0; k < dims.size(); ++k) shape += (k ? " x " : "") + std::to_string(dims[k]);
    if (!dims.empty()) shape += "]";
    if (H5Tget_class(type) == H5T_STRING) shape += " text";
    const std::string unit = attribute(d, "unit");
    std::string tag = theory_tag(d);
    const std::string path(name);
    if (tag.empty() && path.find('/') != std::string::npos) {  // edges, values of a histogram tagged as a whole
      Handle parent(H5Oopen(group, path.substr(0, path.rfind('/')).c_str(), H5P_DEFAULT), H5Oclose);
      tag = theory_tag(parent);
    }
    static_cast<std::vector<Entry>*>(data)->push_back(
        {"/" + std::string(name), shape, H5Tget_class(type) == H5T_STRING && unit.empty() ? "-" : unit, attribute(d, "description"),
         tag});
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
  if (!h5::is_hdf5(path))
    return std::cerr << "gdsmc inspect: " << path << ": not an HDF5 file" << expected << "\n", 1;
  const Handle file = h5::open_read_only(path);
  if (!file)
    return std::cerr << "gdsmc inspect: " << path << ": cannot open it as HDF5" << expected << "\n", 1;
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

  if (h5::is_group(file, "cases")) {
    Handle cases(H5Gopen2(file, "cases", H5P_DEFAULT), H5Gclose);
    std::vector<std::string> names = h5::members(cases);  // by name: 0, 1, 10, 2 ... -> by number
    std::stable_sort(names.begin(), names.end(),
                     [](const std::string& a, const std::string& b) { return a.size() != b.size() ? a.size() < b.size() : a < b; });
    std::cout << "  sweep: " << names.size() << " cases (/cases/<k>; /summary has one row per case)\n";
    for (const auto& k : names) {
      Handle c(H5Gopen2(cases, k.c_str(), H5P_DEFAULT), H5Gclose);
      std::cout << "  case " << k << ": " << attribute(c, "case") << "\n";
      print_run(c);
      print_plugins(c, "    ");
    }
  } else {
    std::cout << "  plugins (/plugins):\n";
    print_plugins(file, "    ");
  }

  const std::vector<Entry> all = datasets(file);
  std::size_t wpath = 0, wshape = 0, wunit = 0;
  for (const auto& e : all) {
    wpath = std::max(wpath, std::min<std::size_t>(e.path.size(), 64));
    wshape = std::max(wshape, e.shape.size());
    wunit = std::max(wunit, e.unit.size());
  }
  std::cout << "datasets (" << all.size() << "; path, shape, unit, theory tag" << (full ? ", description" : "") << "):\n";
  for (const auto& e : all) {
    std::string line = "  " + e.path;
    line += std::string(e.path.size() < wpath ? wpath - e.path.size() + 2 : 2, ' ');
    line += e.shape + std::string(wshape - e.shape.size() + 2, ' ') + e.unit;
    if (!e.tag.empty()) line += std::string(wunit - e.unit.size() + 2, ' ') + e.tag;
    std::cout << line << "\n";
    if (full && !e.description.empty()) std::cout << "      " << e.description << "\n";
  }
  return 0;
}

}  // namespace gdsmc::host
