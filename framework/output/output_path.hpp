// Where a run writes its file: the checks made before anything runs, and the temporary file the
// output is written to and renamed from. gdsmc replaces only a regular file (or the symbolic link
// named, never its target) and removes only files it created itself.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace gdsmc::host {

// An output path that cannot be written; the message names the path and what would be valid
// (the caller prefixes where the path came from: --output, or output.file at file:line).
class OutputPathError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file the run reads (the pipeline, a plugin library): never written over.
struct RunInput {
  std::filesystem::path file;
  std::string what;  // e.g. "the pipeline", "the library of plugin 'temperature'"
};

// What a run will write to, as checked before it starts.
struct OutputTarget {
  enum class Existing { none, regular_file, symlink };
  std::filesystem::path file;       // as given
  std::filesystem::path directory;  // where the temporary file is created: file's directory
  Existing existing = Existing::none;
  std::filesystem::path link_target;  // Existing::symlink: what the link points to

  // The one line saying what the run will replace, e.g. "out.h5 exists and will be replaced when
  // the run completes" (`run`; validate: "a run would replace it"); "" for a new name.
  std::string replacement_notice(bool run) const;
};

// Checks that `file` can be written by renaming a temporary file over it: a valid file name of
// its filesystem (not "", ".", "..", no trailing '/', not longer than the filesystem allows), in an
// existing directory, and nothing there now or a regular file or a symbolic link (the link is
// replaced, not its target), and neither one of `inputs` nor a link to one. Throws
// OutputPathError. Creates nothing: probe_temporary() checks that the directory is writable.
OutputTarget check_output_path(const std::filesystem::path& file, const std::vector<RunInput>& inputs);

// The checkpoint directory a run with run.checkpoint creates beside the output (`directory`, the
// output's name + ".checkpoint") and the longest name it writes there: within the filesystem's
// limits of name and path length, and a directory if it exists. Throws OutputPathError naming the
// directory and the limit (run and validate both check it before anything runs).
void check_checkpoint_directory(const OutputTarget& target, const std::filesystem::path& directory,
                                const std::string& longest_file);

// A temporary file beside the output, created (never opened over an existing file) with a name
// that cannot collide: ".NAME.gdsmc-partial-HOST-NS-PID-XXXXXX" (NS identifies the PID namespace).
// It is removed on destruction unless renamed, and only while the name still refers to the file
// this object created.
class TemporaryFile {
 public:
  // Throws OutputPathError (e.g. "cannot create a file in DIR: Permission denied").
  explicit TemporaryFile(const OutputTarget& target);
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile();

  const std::filesystem::path& path() const { return path_; }
  int fd() const { return fd_; }
  // Whether the open descriptor `other_fd` is this file (the same inode).
  bool is(int other_fd) const;
  // fsync, check the target is still replaceable, rename over target.file, fsync the directory.
  // Throws OutputPathError.
  void rename_over(const OutputTarget& target);
  // Remove the file now (if it is still ours) and close it.
  void remove();

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  dev_t dev_ = 0;
  ino_t ino_ = 0;
  int live_slot_ = -1;  // where a signal handler finds this file (see remove_live_temporaries_from_signal_handler)
};

// The lock of an output name while a run writes it: ".NAME.gdsmc-lock" beside the output, held
// with flock(2) (released by the kernel when the process ends, however it ends, so that a lock
// left by a killed run never blocks) and removed when the run ends. A second run that would write
// the same output while the first is alive is refused at start, naming the first.
class OutputLock {
 public:
  // Throws OutputPathError: "another gdsmc run is writing 'out.h5' now (process 123 on host h, ...)".
  // Where the lock file cannot be created (the temporary file then says why) or the file system
  // has no locks, the run goes on without one.
  explicit OutputLock(const OutputTarget& target);
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  int live_slot_ = -1;  // removed by remove_live_temporaries_from_signal_handler too
};

// The lock file of `file`: ".NAME.gdsmc-lock" in its directory.
std::filesystem::path output_lock_path(const std::filesystem::path& file);

// Remove every TemporaryFile (and OutputLock) still alive, from a signal handler: only async-signal-safe calls
// (lstat, unlink) on paths kept in static storage. For a run ended by _exit.
void remove_live_temporaries_from_signal_handler() noexcept;

// Create a temporary file beside the target and remove it at once: that the directory is
// writable and the name fits, for `validate`. Throws OutputPathError.
void probe_temporary(const OutputTarget& target);

// Remove the temporary files of `target` left by gdsmc processes of this host and PID namespace
// that no longer exist (killed during a run); never another host's, a live process's or a file
// that is not a regular file owned by this user. Returns one line per file removed. An output lock
// that no live process holds is removed too (silently: it says nothing about the results).
std::vector<std::string> remove_stale_temporaries(const OutputTarget& target);

// The prefix of every temporary file name of `file` (".NAME.gdsmc-partial-"), NAME cut to keep
// the whole name within the usual 255-byte limit.
std::string temporary_prefix(const std::filesystem::path& file);

}  // namespace gdsmc::host
