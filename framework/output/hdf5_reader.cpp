#include "output/hdf5_reader.hpp"

#include <algorithm>
#include <stdexcept>

namespace gdsmc::host::h5 {

namespace {

// Failures are reported by return values and exceptions, not printed by the library.
void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// The type to read a variable-length string of file type `type` into (HDF5 does not convert
// between ASCII and UTF-8, so the character set is the file's).
Handle variable_string_type(hid_t type) {
  Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem, H5T_VARIABLE);
  H5Tset_cset(mem, H5Tget_cset(type));
  return mem;
}

herr_t collect_name(hid_t, const char* name, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

Handle open_dataset(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d) throw std::runtime_error("no dataset " + path);
  return d;
}

}  // namespace

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    if (id_ >= 0) close_(id_);
    id_ = other.id_;
    close_ = other.close_;
    other.id_ = -1;
  }
  return *this;
}

Handle::~Handle() {
  if (id_ >= 0) close_(id_);
}

bool is_hdf5(const std::filesystem::path& file) {
  quiet();
  return H5Fis_hdf5(file.c_str()) > 0;
}

Handle open_read_only(const std::filesystem::path& file) {
  quiet();
  return Handle(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
}

bool exists(hid_t loc, const std::string& path) {
  // Every prefix: H5Lexists fails on a path whose intermediate group is missing.
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (!prefix.empty() && prefix != "/" && H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

namespace {
bool has_type(hid_t loc, const std::string& path, H5O_type_t type) {
  if (!exists(loc, path)) return false;
  H5O_info_t info;
  return H5Oget_info_by_name(loc, path.c_str(), &info, H5P_DEFAULT) >= 0 && info.type == type;
}
}  // namespace

bool is_group(hid_t loc, const std::string& path) { return has_type(loc, path, H5O_TYPE_GROUP); }
bool is_dataset(hid_t loc, const std::string& path) { return has_type(loc, path, H5O_TYPE_DATASET); }

std::vector<std::string> members(hid_t group) {
  std::vector<std::string> names;
  auto cb = [](hid_t g, const char* name, const H5L_info_t*, void* data) -> herr_t { return collect_name(g, name, data); };
  H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &names);
  return names;
}

std::vector<std::string> attribute_names(hid_t object) {
  std::vector<std::string> names;
  auto cb = [](hid_t o, const char* name, const H5A_info_t*, void* data) -> herr_t { return collect_name(o, name, data); };
  H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &names);
  return names;
}

std::vector<hsize_t> shape(hid_t dataset) {
  Handle space(H5Dget_space(dataset), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

std::optional<std::string> text_attribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return std::nullopt;
  Handle a(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a) return std::nullopt;
  Handle type(H5Aget_type(a), H5Tclose);
  if (H5Tget_class(type) != H5T_STRING) return std::nullopt;
  if (H5Tis_variable_str(type) > 0) {
    const Handle mem = variable_string_type(type);
    char* s = nullptr;
    if (H5Aread(a, mem, &s) < 0 || !s) return std::nullopt;
    std::string text = s;
    H5free_memory(s);
    return text;
  }
  std::string buf(H5Tget_size(type), '\0');
  if (H5Aread(a, type, buf.data()) < 0) return std::nullopt;
  return buf.substr(0, buf.find('\0'));
}

std::optional<double> number_attribute(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return std::nullopt;
  Handle a(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  double v = 0;
  if (!a || H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) return std::nullopt;
  return v;
}

std::vector<double> read_doubles(hid_t loc, const std::string& path) {
  const Handle d = open_dataset(loc, path);
  Handle s(H5Dget_space(d), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (!v.empty() && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw std::runtime_error("cannot read " + path + " as double");
  return v;
}

std::vector<std::string> read_strings(hid_t loc, const std::string& path) {
  const Handle d = open_dataset(loc, path);
  Handle type(H5Dget_type(d), H5Tclose), space(H5Dget_space(d), H5Sclose);
  if (H5Tget_class(type) != H5T_STRING) throw std::runtime_error(path + " is not text");
  const bool variable = H5Tis_variable_str(type) > 0;
  const std::string bytes = value_bytes(d, type, space, false);
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  const std::size_t len = variable ? 0 : H5Tget_size(type);
  std::vector<std::string> out;
  for (std::size_t k = 0, at = 0; k < n; ++k) {
    const std::size_t end = variable ? bytes.find('\0', at) : at + len;
    out.emplace_back(std::string(bytes, at, end - at).c_str());  // a fixed-length string ends at its first NUL
    at = variable ? end + 1 : end;
  }
  return out;
}

std::string value_bytes(hid_t object, hid_t type, hid_t space, bool attribute) {
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n <= 0) return "";
  if (H5Tis_variable_str(type) > 0) {
    std::vector<char*> strings(static_cast<std::size_t>(n), nullptr);
    const Handle mem = variable_string_type(type);
    const herr_t r = attribute ? H5Aread(object, mem, strings.data())
                               : H5Dread(object, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, strings.data());
    if (r < 0) throw std::runtime_error("cannot read a string value");
    std::string out;
    for (char* s : strings) out += std::string(s ? s : "") + '\0';
    H5Dvlen_reclaim(mem, space, H5P_DEFAULT, strings.data());
    return out;
  }
  std::string out(static_cast<std::size_t>(n) * H5Tget_size(type), '\0');
  const herr_t r = attribute ? H5Aread(object, type, out.data())
                             : H5Dread(object, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  if (r < 0) throw std::runtime_error("cannot read a value");
  return out;
}

}  // namespace gdsmc::host::h5
