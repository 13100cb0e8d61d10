// Writing a study's results to one HDF5 file: created under a temporary name before the first
// step, renamed over the output name only when complete.
#pragma once
#include <hdf5.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <vector>

#include "output/output_path.hpp"
#include "output/particle_dump.hpp"
#include "output/records.hpp"

namespace gdsmc::host {

// The interrupt flag was set while the file was being written (SIGINT, SIGTERM).
class OutputInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writing failed (disk full, file size limit, I/O error); the message says what and why.
class OutputWriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The run's HDF5 file, open under a temporary name (TemporaryFile) from before the first step.
// Destroyed without commit(), it closes and removes the temporary file.
class OutputFile {
 public:
  // Creates the temporary file beside target.file (throws OutputPathError). `interrupt`, when
  // set during a write, stops it with OutputInterrupted.
  explicit OutputFile(const OutputTarget& target, const std::atomic<bool>* interrupt = nullptr);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();

  // Writes `out` (particle datasets staged before are moved into place) and renames the file over
  // target.file. Throws OutputWriteError, OutputPathError or OutputInterrupted; the temporary
  // file is then removed when this object is destroyed.
  void commit(const StudyOutput& out);

  // Writes the final particles into the file now, in bounded chunks straight from the particle
  // store (no second copy of them), and returns the datasets naming where they are. Runs on
  // several threads call it at once: the calls are serialized (the HDF5 library is not
  // thread-safe; unserialized, two first calls both created the staging group and one failed with
  // "name already exists", once in a clean-clone CI run of tests/framework/study/threads_test.cpp
  // at --threads 3).
  std::vector<ParticleDataset> stage_particles(const std::vector<ParticleColumn>& columns);

  // stage_particles as the engine takes it (Engine::output, through run_study): the final
  // particles go into this file while the store still holds them.
  ParticleStager stager() {
    return [this](const std::vector<ParticleColumn>& columns) { return stage_particles(columns); };
  }

  const std::filesystem::path& temporary_path() const { return tmp_.path(); }

 private:
  OutputTarget target_;
  TemporaryFile tmp_;
  hid_t file_ = -1;
  const std::atomic<bool>* interrupt_;
  std::size_t staged_ = 0;
  std::mutex staging_;  // stage_particles' calls, one at a time
};

// Check `file`, create it under a temporary name and write `out` (no inputs to protect: for tests
// and tools that write a study's output in one go).
void write_hdf5(const std::filesystem::path& file, const StudyOutput& out);

// A string attribute of the root group of an HDF5 file (e.g. an output's "pipeline"); nullopt
// when the file is not an HDF5 file that has it.
std::optional<std::string> read_root_text(const std::filesystem::path& file, const std::string& name);

}  // namespace gdsmc::host
