// Reading HDF5 files back (C API): `gdsmc inspect`, an output's pipeline text (read_root_text) and
// the tests read outputs through these functions. Errors are not printed by the library.
#pragma once
#include <hdf5.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gdsmc::host::h5 {

// An HDF5 identifier, closed with its close function on scope exit (negative: none).
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle();
  hid_t id() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }
  operator hid_t() const { return id_; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

// Whether `file` is an HDF5 file (false also when it cannot be read).
bool is_hdf5(const std::filesystem::path& file);

// `file` opened read-only; an empty handle when it cannot be opened.
Handle open_read_only(const std::filesystem::path& file);

// Whether the object `path` exists under `loc` (every group on the way is checked).
bool exists(hid_t loc, const std::string& path);
// Whether `path` under `loc` is a group (a dataset).
bool is_group(hid_t loc, const std::string& path);
bool is_dataset(hid_t loc, const std::string& path);

// Names of the direct members of a group, and of the attributes of an object, by name.
std::vector<std::string> members(hid_t group);
std::vector<std::string> attribute_names(hid_t object);

// The dimensions of a dataset (none for a scalar).
std::vector<hsize_t> shape(hid_t dataset);

// The attribute `name` of `object` as text (a string attribute) or as a number (a numeric one);
// nullopt when it is absent, of the other class, or cannot be read.
std::optional<std::string> text_attribute(hid_t object, const std::string& name);
std::optional<double> number_attribute(hid_t object, const std::string& name);

// The dataset `path` under `loc` converted to double (rank 0 gives one value), or as text (fixed
// or variable-length strings). Throw std::runtime_error naming the dataset.
std::vector<double> read_doubles(hid_t loc, const std::string& path);
std::vector<std::string> read_strings(hid_t loc, const std::string& path);

// The raw bytes of a dataset or attribute `object` of file type `type` over `space`, in that type
// (variable-length strings as their characters, each followed by a NUL). Throws on a failed read.
std::string value_bytes(hid_t object, hid_t type, hid_t space, bool attribute);

}  // namespace gdsmc::host::h5
