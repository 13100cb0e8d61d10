// A program run in a child process (fork and exec): `gdsmc plot` and `output.plots` run the plotter
// this way, and the tests run gdsmc, mpirun and sh this way. (Plugin code that must not take the
// host down runs in a forked child without exec: plugins/child_process.hpp.)
#pragma once
#include <sys/resource.h>
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace gdsmc::host {

struct SubprocessOptions {
  std::filesystem::path cwd;                   // empty: the parent's working directory
  std::filesystem::path stdout_file;           // empty: the parent's stdout; else created or truncated
  std::filesystem::path stderr_file;           // likewise for stderr
  bool stdout_to_pipe = false;                 // stdout is a pipe the parent reads (read_output)
  bool stderr_to_stdout = false;               // stderr goes where stdout goes
  bool stdin_from_null = false;                // stdin reads /dev/null
  std::vector<std::string> unset_environment;  // variables left out of the child's environment
  rlim_t address_space = RLIM_INFINITY;        // the child's RLIMIT_AS, in bytes
  bool core_dumps = true;                      // false: the child's RLIMIT_CORE is 0
};

// How a child ended.
struct ExitStatus {
  int exit_code = -1;       // its exit status; -1 when a signal ended it
  int signal = 0;           // the signal that ended it (0: it exited)
  bool timed_out = false;   // killed with SIGKILL when the time wait_for gave it had passed
  std::string text() const;  // "exited with status N" or "was killed by signal N"
};

class Subprocess {
 public:
  // Starts argv[0] (a path; PATH is not searched) with the arguments argv[1...]. A child that
  // cannot set up its redirections and limits or exec exits with status 127. Throws
  // std::system_error when no child can be started (fork fails).
  explicit Subprocess(const std::vector<std::string>& argv, const SubprocessOptions& options = {});
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;
  // A child still running is killed (SIGKILL) and reaped.
  ~Subprocess();

  pid_t pid() const { return pid_; }
  void send(int signal) const;
  // With stdout_to_pipe: everything the child writes to stdout, until it closes it (blocks).
  std::string read_output();
  // Whether the child has ended (never blocks; it is then reaped).
  bool ended();
  // Waits until the child ends.
  ExitStatus wait();
  // Waits at most `seconds`, then kills it (SIGKILL) and reports a timeout.
  ExitStatus wait_for(double seconds);
  // The child's resource usage (its peak resident size, ru_maxrss in KiB), once it has ended.
  const rusage& usage() const { return usage_; }

 private:
  ExitStatus status() const;
  pid_t pid_ = -1;
  int output_ = -1;  // the read end of the stdout pipe
  int status_ = 0;
  bool reaped_ = false, timed_out_ = false;
  rusage usage_{};
};

}  // namespace gdsmc::host
