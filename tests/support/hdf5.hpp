// Test support: HDF5 files read back through the host's reader (output/hdf5_reader.hpp), with
// paths under a location and errors that throw.
#pragma once
#include <hdf5.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "output/hdf5_reader.hpp"
#include "support/files.hpp"

namespace gdsmc::test::h5 {

using host::h5::exists;
using host::h5::Handle;
using host::h5::is_dataset;
using host::h5::read_doubles;
using host::h5::read_strings;
using host::h5::value_bytes;

class File {
 public:
  explicit File(const fs::path& p) : h_(host::h5::open_read_only(p)) {
    if (!h_) throw std::runtime_error("cannot open HDF5 file " + p.string());
  }
  hid_t id() const { return h_.id(); }

 private:
  Handle h_;
};

inline std::vector<hsize_t> shape(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d) throw std::runtime_error("no dataset " + path);
  return host::h5::shape(d);
}

inline double read_scalar(hid_t loc, const std::string& path) {
  const auto v = read_doubles(loc, path);
  if (v.size() != 1) throw std::runtime_error(path + " is not a scalar");
  return v[0];
}

// The raw content of a dataset, for bit-for-bit comparison: numbers as their bytes in the
// native layout of their own type, strings as text.
inline std::string content_bytes(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d) throw std::runtime_error("no dataset " + path);
  Handle ftype(H5Dget_type(d), H5Tclose);
  if (H5Tget_class(ftype) == H5T_STRING) return join(read_strings(loc, path), std::string(1, '\0'));
  Handle mtype(H5Tget_native_type(ftype, H5T_DIR_ASCEND), H5Tclose), space(H5Dget_space(d), H5Sclose);
  return value_bytes(d, mtype, space, false);
}

// The object `object` under `loc` (throws if missing).
inline Handle open_object(hid_t loc, const std::string& object) {
  Handle o(H5Oopen(loc, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (!o) throw std::runtime_error("no object " + object);
  return o;
}

inline bool has_attribute(hid_t loc, const std::string& object, const std::string& name) {
  return exists(loc, object) && H5Aexists(open_object(loc, object), name.c_str()) > 0;
}

inline std::string read_string_attribute(hid_t loc, const std::string& object, const std::string& name) {
  const auto text = host::h5::text_attribute(open_object(loc, object), name);
  if (!text) throw std::runtime_error("no text attribute " + object + "@" + name);
  return *text;
}

inline double read_number_attribute(hid_t loc, const std::string& object, const std::string& name) {
  const auto value = host::h5::number_attribute(open_object(loc, object), name);
  if (!value) throw std::runtime_error("no number attribute " + object + "@" + name);
  return *value;
}

// Every object of the file: "/a/b" -> type.
inline std::map<std::string, H5O_type_t> objects(hid_t file) {
  std::map<std::string, H5O_type_t> out;
  auto cb = [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    const std::string n = name;
    if (n != ".") (*static_cast<std::map<std::string, H5O_type_t>*>(data))["/" + n] = info->type;
    return 0;
  };
  if (H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC, cb, &out) < 0) throw std::runtime_error("H5Ovisit failed");
  return out;
}

inline std::vector<std::string> datasets(hid_t file) {
  std::vector<std::string> v;
  for (const auto& [name, type] : objects(file))
    if (type == H5O_TYPE_DATASET) v.push_back(name);
  return v;
}

// Names of the direct members of a group.
inline std::vector<std::string> members(hid_t loc, const std::string& group) {
  Handle g(H5Gopen2(loc, group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g) throw std::runtime_error("no group " + group);
  return host::h5::members(g);
}

// Every dataset (path -> bytes) and every attribute (path@name -> bytes) of a file, but the wall
// times, wall_seconds and stage_seconds.* (the only values that may differ between two runs of
// the same pipeline).
inline std::map<std::string, std::string> contents(const fs::path& file) {
  File f(file);
  std::map<std::string, std::string> out;
  auto attributes = [&](hid_t object, const std::string& path) {
    for (const std::string& name : host::h5::attribute_names(object)) {
      if (name == "wall_seconds" || name.rfind("stage_seconds.", 0) == 0) continue;
      Handle a(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
      Handle type(H5Aget_type(a), H5Tclose), space(H5Aget_space(a), H5Sclose);
      out[path + "@" + name] = value_bytes(a, type, space, true);
    }
  };
  attributes(f.id(), "/");
  for (const auto& [path, kind] : objects(f.id())) {
    Handle o = open_object(f.id(), path);
    attributes(o, path);
    if (kind != H5O_TYPE_DATASET) continue;
    Handle type(H5Dget_type(o), H5Tclose), space(H5Dget_space(o), H5Sclose);
    out[path] = value_bytes(o, type, space, false);
  }
  return out;
}

}  // namespace gdsmc::test::h5
