// Test support: the gdsmc executable (or a launcher, or sh) run as a child process through the
// host's own runner (util/subprocess.hpp).
#pragma once
#include <sys/resource.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/files.hpp"
#include "util/subprocess.hpp"

namespace gdsmc::test {

struct ProcessResult {
  int exit_code = -1;  // exit status, or -1 if killed by a signal
  int signal = 0;      // the signal that ended it, if any
  bool timed_out = false;
  std::string out, err;
  std::string describe() const {
    std::ostringstream s;
    s << "exit " << exit_code << (signal ? " (signal " + std::to_string(signal) + ")" : "")
      << (timed_out ? " (timed out)" : "") << "\n--- stdout ---\n" << out << "\n--- stderr ---\n" << err;
    return s.str();
  }
};

// Limits set in the child before exec.
struct ProcessLimits {
  rlim_t address_space = RLIM_INFINITY;  // RLIMIT_AS, bytes
  bool core_dumps = true;                // false: RLIMIT_CORE 0
};

// A running gdsmc process: started in `cwd` with GDSMC_PLUGIN_PATH removed from the environment
// (the host then finds the build's plugins beside the executable) and stdin from /dev/null; stdout
// and stderr go to files in a private directory (not `cwd`, so that tests can check what the run
// left in `cwd`).
class Process {
 public:
  // `program` instead of gdsmc: a launcher (mpirun) whose arguments name gdsmc.
  Process(const std::vector<std::string>& args, const fs::path& cwd, const ProcessLimits& limits = {},
          const fs::path& program = executable())
      : child_(command(program, args), options(cwd, limits)) {}
  void send(int sig) { child_.send(sig); }
  pid_t pid() const { return child_.pid(); }
  // Whether the process has installed a handler for `sig` (Linux: SigCgt in /proc/<pid>/status).
  bool catches(int sig) const {
    std::ifstream status("/proc/" + std::to_string(pid()) + "/status");
    std::string line;
    while (std::getline(status, line))
      if (line.rfind("SigCgt:", 0) == 0) {
        const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
        return (mask >> (sig - 1)) & 1ull;
      }
    return false;
  }
  // Wait until the process catches `sig` (true), or until it exits or `timeout_s` passes (false).
  bool wait_until_catches(int sig, double timeout_s = 30) {
    const auto start = std::chrono::steady_clock::now();
    while (seconds_since(start) < timeout_s) {
      if (catches(sig)) return true;
      if (ended()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  // Whether the process has ended (never blocks; wait() then returns at once).
  bool ended() { return child_.ended(); }
  // Wait up to `timeout_s` seconds (then SIGKILL it and report a timeout).
  ProcessResult wait(double timeout_s = 120) {
    const host::ExitStatus s = child_.wait_for(timeout_s);
    return {s.exit_code, s.signal, s.timed_out, read_text(capture_ / "stdout"), read_text(capture_ / "stderr")};
  }
  // The stderr written so far.
  std::string err_so_far() const { return read_text(capture_ / "stderr"); }

 private:
  static std::vector<std::string> command(const fs::path& program, const std::vector<std::string>& args) {
    std::vector<std::string> argv{program.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
  }
  host::SubprocessOptions options(const fs::path& cwd, const ProcessLimits& limits) const {
    host::SubprocessOptions o;
    o.cwd = cwd;
    o.stdout_file = capture_ / "stdout";
    o.stderr_file = capture_ / "stderr";
    o.stdin_from_null = true;
    o.unset_environment = {"GDSMC_PLUGIN_PATH"};
    o.address_space = limits.address_space;
    o.core_dumps = limits.core_dumps;
    return o;
  }
  TempDir capture_;  // before child_: the files exist before it starts
  host::Subprocess child_;
};

// A shell command line (sh -c), with GDSMC_PLUGIN_PATH cleared; stdout and stderr together, read
// through a pipe (so that a `ulimit -f` of the command does not limit them).
struct ShellResult {
  int status = -1;  // exit status, or -1 if it did not exit normally
  std::string out;
};
inline ShellResult shell(const std::string& command) {
  host::SubprocessOptions o;
  o.stdout_to_pipe = true;
  o.stderr_to_stdout = true;
  o.unset_environment = {"GDSMC_PLUGIN_PATH"};
  host::Subprocess sh({"/bin/sh", "-c", command}, o);
  ShellResult r;
  r.out = sh.read_output();
  r.status = sh.wait().exit_code;
  return r;
}

inline ProcessResult run_gdsmc(const std::vector<std::string>& args, const fs::path& cwd, double timeout_s = 120) {
  Process p(args, cwd);
  return p.wait(timeout_s);
}

// `gdsmc <command> pipeline.yaml [args]` in a fresh directory; what it printed and what it left there.
struct Outcome {
  ProcessResult result;
  std::vector<std::string> left;  // entries other than the pipeline
};
inline Outcome gdsmc_in_dir(const std::string& command, const std::string& yaml, const std::vector<std::string>& args,
                            double timeout_s = 30) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", yaml);
  std::vector<std::string> argv = {command, file.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  Outcome o;
  o.result = run_gdsmc(argv, dir.path(), timeout_s);
  o.left = dir.entries_except({"pipeline.yaml"});
  return o;
}

}  // namespace gdsmc::test
