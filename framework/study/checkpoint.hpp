// Checkpoints of a study (run.checkpoint, `gdsmc run --resume`): a directory beside the output,
// <output>.checkpoint/, holding `study` (what the checkpoint belongs to: the pipeline, gdsmc and
// every plugin version) and one file per run (case x realization) that has started: the engine's
// whole state (Engine::save), the latest one written atomically (a temporary file, fsync, rename),
// so a kill at any moment leaves the previous complete state. A finished run's file holds its
// results. Every run depends on (case, realization) alone, so runs resumed from different points
// still give the output of the uninterrupted study, to the bit.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/engine.hpp"
#include "study/cases.hpp"

namespace gdsmc::host {

// A checkpoint that cannot be used: it belongs to another pipeline, gdsmc or plugin version,
// or is damaged. The message says what differs.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CheckpointStore {
 public:
  // The directory of the checkpoints of `output`.
  static std::filesystem::path directory_for(const std::filesystem::path& output);

  // Fresh study: refuses (CheckpointError) when `dir` already holds a checkpoint, then creates it
  // and writes its `study` file. Resume: checks `dir`'s study file against these cases (throws
  // CheckpointError naming every difference) and removes temporaries of killed writes.
  CheckpointStore(std::filesystem::path dir, const std::vector<StudyCase>& cases, bool resume);

  const std::filesystem::path& directory() const { return dir_; }
  // True when run `index` (study order: cases, realizations within a case) has a state to resume.
  bool has_run(std::size_t index) const;
  // What the checkpoint holds, for the resume message: "12 runs: 3 finished, 2 under way (at
  // t = 1.2 to 3.4 tau0, s = ...), 7 not started".
  std::string describe(const std::vector<StudyCase>& cases) const;
  // Resume: every run file there is, read as a resume reads it: its checksums, whose run it is
  // and, with `restore`, the whole engine state (validate --resume). Throws CheckpointError
  // naming the file ("... is damaged: entry 12 of 40, 'particles.velocity', ..."), before anything
  // runs.
  void check_runs(const std::vector<StudyCase>& cases, bool restore) const;
  // After a failure to write the output: which runs' results the checkpoint keeps (their file
  // holds the finished run) and which will run again at --resume (a final checkpoint that was
  // not written: from their last saved state or their start), read from the files.
  // `all_kept`: set when every run's results are kept (--resume then only writes the file).
  std::string kept_text(bool* all_kept = nullptr) const;
  // The pipeline text as it decides the results (run.threads and run.checkpoint aside): what a
  // checkpoint, or a finished output's "pipeline" attribute, must match to be this run's.
  static std::string pipeline_identity(const std::string& resolved_text);
  // The engine of run `index`, restored from its file (CheckpointError on a foreign or damaged one).
  std::unique_ptr<Engine> restore(std::size_t index, const StudyCase& c, std::uint32_t realization,
                                  unsigned threads) const;
  // Writes run `index`'s state atomically. Safe to call from several threads for different runs.
  void write(std::size_t index, const StudyCase& c, std::uint32_t realization, const Engine& engine) const;
  // After the output is complete: the directory and everything in it.
  void remove() const;

 private:
  std::filesystem::path run_file(std::size_t index) const;
  // Fresh study: refuses a checkpoint already in the directory, creates it and writes `study`.
  void create_study(const std::string& plugins) const;
  // Resume: checks the directory's `study` against this run (CheckpointError naming every
  // difference) and removes temporaries of killed writes.
  void check_study(const std::string& plugins, const std::map<std::string, std::string>& libraries) const;
  // Run `index`'s file checked (checksums, header) and, with `restore`, its engine restored.
  std::unique_ptr<Engine> read_run(std::size_t index, const StudyCase& c, std::uint32_t realization, unsigned threads,
                                   bool restore) const;
  std::filesystem::path dir_;
  std::string gdsmc_version_, pipeline_;
  std::size_t runs_ = 0;
};

}  // namespace gdsmc::host
