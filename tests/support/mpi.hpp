// Test support: gdsmc under mpirun (the `mpi` tests), and two output files compared byte for byte.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/hdf5.hpp"
#include "support/process.hpp"

namespace gdsmc::test {

// The arguments of mpirun for `ranks` ranks of gdsmc on this (two-core, root-run) machine.
inline std::vector<std::string> mpirun_args(int ranks, const std::vector<std::string>& gdsmc_args) {
  std::vector<std::string> a{"-np", std::to_string(ranks), "--oversubscribe", "--allow-run-as-root",
                             executable().string()};
  a.insert(a.end(), gdsmc_args.begin(), gdsmc_args.end());
  return a;
}

// Why the MPI tests cannot run here ("" when they can). GDSMC_MPIEXEC: tests/CMakeLists.txt.
inline std::string why_no_mpi() {
  if (std::string(GDSMC_MPIEXEC).empty()) return "no mpirun was found when the build was configured";
  const ShellResult version = shell(executable().string() + " --version");
  if (!contains(version.out, "with MPI")) return "the host was built without MPI: " + version.out;
  return "";
}

inline ProcessResult mpirun(int ranks, const std::vector<std::string>& gdsmc_args, const fs::path& cwd) {
  Process p(mpirun_args(ranks, gdsmc_args), cwd, {}, GDSMC_MPIEXEC);
  return p.wait(300);
}

// Every dataset and attribute of `got_file` has the bytes of `expected_file`'s (wall times aside:
// h5::contents), and there are at least `min_entries` of them.
inline void expect_same_contents(const fs::path& expected_file, const fs::path& got_file, std::size_t min_entries) {
  const auto expected = h5::contents(expected_file), got = h5::contents(got_file);
  EXPECT_GE(expected.size(), min_entries);
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [key, bytes] : expected) {
    const auto it = got.find(key);
    ASSERT_NE(it, got.end()) << key << " missing from " << got_file.filename().string();
    EXPECT_TRUE(it->second == bytes) << key << " differs between " << expected_file.filename().string() << " and "
                                     << got_file.filename().string();
  }
}

}  // namespace gdsmc::test
