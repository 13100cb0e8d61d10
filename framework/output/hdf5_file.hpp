// Writing a study's results to one HDF5 file, under a temporary name renamed only on success.
#pragma once
#include <filesystem>

#include "output/records.hpp"

namespace gdsmc::host {

// Write under "<file>.partial-<pid>" and rename to `file` on success. On failure, no file is left
// under either name and the error is thrown.
void write_hdf5(const std::filesystem::path& file, const StudyOutput& out);

}  // namespace gdsmc::host
