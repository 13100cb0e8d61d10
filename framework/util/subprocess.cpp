#include "util/subprocess.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <system_error>
#include <thread>

extern char** environ;

namespace gdsmc::host {

namespace {

// The environment without the variables named in `unset`.
std::vector<std::string> environment_without(const std::vector<std::string>& unset) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    const std::string name = entry.substr(0, entry.find('='));
    if (std::find(unset.begin(), unset.end(), name) == unset.end()) env.push_back(entry);
  }
  return env;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
  std::vector<char*> v;
  for (auto& s : strings) v.push_back(s.data());
  v.push_back(nullptr);
  return v;
}

// `path` opened for writing on descriptor `fd` (nothing when path is empty); async-signal-safe.
bool redirect(const char* path, int fd, int flags) {
  if (!*path) return true;
  const int opened = ::open(path, flags, 0644);
  return opened >= 0 && ::dup2(opened, fd) >= 0;
}

}  // namespace

std::string ExitStatus::text() const {
  return signal ? "was killed by signal " + std::to_string(signal) : "exited with status " + std::to_string(exit_code);
}

Subprocess::Subprocess(const std::vector<std::string>& argv_in, const SubprocessOptions& o) {
  // Everything the child needs is prepared before fork: only async-signal-safe calls after it
  // (other threads may hold locks).
  std::vector<std::string> args = argv_in, env = environment_without(o.unset_environment);
  std::vector<char*> argv = c_strings(args), envp = c_strings(env);
  const std::string cwd = o.cwd.string(), out = o.stdout_file.string(), err = o.stderr_file.string();
  const rlimit memory{o.address_space, o.address_space}, no_core{0, 0};
  const int create = O_WRONLY | O_CREAT | O_TRUNC;
  int pipe_fds[2] = {-1, -1};
  if (o.stdout_to_pipe && ::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
  std::cout.flush();  // buffered output would otherwise be written by both processes
  std::cerr.flush();
  std::fflush(nullptr);
  pid_ = ::fork();
  if (pid_ != 0) {
    const int fork_error = errno;
    if (o.stdout_to_pipe) ::close(pipe_fds[1]);
    if (pid_ < 0) {
      if (o.stdout_to_pipe) ::close(pipe_fds[0]);
      throw std::system_error(fork_error, std::generic_category(), "fork");
    }
    output_ = pipe_fds[0];
    return;
  }
  if ((o.stdout_to_pipe && ::dup2(pipe_fds[1], 1) < 0) || !redirect(out.c_str(), 1, create) ||
      !redirect(err.c_str(), 2, create) ||
      (o.stderr_to_stdout && ::dup2(1, 2) < 0) || (o.stdin_from_null && !redirect("/dev/null", 0, O_RDONLY)) ||
      (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ||
      (o.address_space != RLIM_INFINITY && ::setrlimit(RLIMIT_AS, &memory) != 0) ||
      (!o.core_dumps && ::setrlimit(RLIMIT_CORE, &no_core) != 0))
    ::_exit(127);
  ::execve(argv[0], argv.data(), envp.data());
  ::_exit(127);
}

Subprocess::~Subprocess() {
  if (output_ >= 0) ::close(output_);
  if (pid_ > 0 && !reaped_) {
    ::kill(pid_, SIGKILL);
    while (::wait4(pid_, &status_, 0, &usage_) < 0 && errno == EINTR) {
    }
  }
}

void Subprocess::send(int signal) const { ::kill(pid_, signal); }

std::string Subprocess::read_output() {
  std::string out;
  char buf[4096];
  for (ssize_t n; output_ >= 0 && ((n = ::read(output_, buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR));)
    if (n > 0) out.append(buf, static_cast<std::size_t>(n));
  return out;
}

bool Subprocess::ended() {
  if (!reaped_ && ::wait4(pid_, &status_, WNOHANG, &usage_) == pid_) reaped_ = true;
  return reaped_;
}

ExitStatus Subprocess::wait() {
  while (!reaped_) {
    const pid_t w = ::wait4(pid_, &status_, 0, &usage_);
    if (w == pid_ || (w < 0 && errno != EINTR)) reaped_ = true;
  }
  return status();
}

ExitStatus Subprocess::wait_for(double seconds) {
  const auto start = std::chrono::steady_clock::now();
  while (!ended()) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
      ::kill(pid_, SIGKILL);
      timed_out_ = true;
      return wait();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return status();
}

ExitStatus Subprocess::status() const {
  ExitStatus s;
  if (WIFEXITED(status_)) s.exit_code = WEXITSTATUS(status_);
  if (WIFSIGNALED(status_)) s.signal = WTERMSIG(status_);
  s.timed_out = timed_out_;
  return s;
}

}  // namespace gdsmc::host
