#include "plugins/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <thread>

namespace gdsmc::host {

namespace {

// A message is its length (8 bytes) and its bytes; this length marks the end of fn, so that a
// child that plugin code ends early (exit(0) in a constructor) is not taken for a finished one.
constexpr std::uint64_t kFinished = ~std::uint64_t{0};

void write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) ::_exit(3);  // the parent is gone
    data += w;
    n -= static_cast<std::size_t>(w);
  }
}

// The child's side: its output to /dev/null when quiet, fn, then the end marker; never returns.
[[noreturn]] void run_as_child(int fd, const std::function<void(ChildReport&)>& fn, bool quiet) {
  if (quiet) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);
    }
  }
  ChildReport report(fd);
  fn(report);
  write_all(fd, reinterpret_cast<const char*>(&kFinished), sizeof kFinished);
  std::cout.flush();
  std::fflush(nullptr);
  ::_exit(0);
}

// The complete messages at the front of `data` moved into `messages`, up to the end marker (which
// sets `ended`). Returns how many messages and markers were taken.
std::size_t take_messages(std::string& data, std::vector<std::string>& messages, bool& ended) {
  std::size_t taken = 0;
  std::uint64_t n;
  while (!ended && data.size() >= sizeof n) {
    std::memcpy(&n, data.data(), sizeof n);
    if (n == kFinished) {
      ended = true;
    } else if (data.size() - sizeof n >= n) {
      messages.push_back(data.substr(sizeof n, n));
    } else {
      break;
    }
    data.erase(0, sizeof n + (ended ? 0 : n));
    ++taken;
  }
  return taken;
}

}  // namespace

void ChildReport::send(const std::string& message) {
  const std::uint64_t n = message.size();
  write_all(fd_, reinterpret_cast<const char*>(&n), sizeof n);
  write_all(fd_, message.data(), message.size());
}

ChildOutcome run_in_child(const std::function<void(ChildReport&)>& fn, double timeout_seconds, bool quiet) {
  ChildOutcome out;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    out.failure = std::string("cannot create a pipe: ") + std::strerror(errno);
    return out;
  }
  // Buffered output would otherwise be written twice, once by each process.
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    out.failure = std::string("cannot fork: ") + std::strerror(errno);
    ::close(fds[0]);
    ::close(fds[1]);
    return out;
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_as_child(fds[1], fn, quiet);
  }
  ::close(fds[1]);
  // The time limit is kept here, not by alarm() in the child: plugin code may block or catch SIGALRM.
  using clock = std::chrono::steady_clock;
  const auto limit = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(timeout_seconds));
  auto deadline = clock::now() + limit;
  auto ms_left = [&] {
    return static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - clock::now()).count());
  };
  bool kill_it = false, ended = false;
  std::string data;
  char buf[4096];
  while (!ended) {
    const int left = ms_left();
    pollfd pfd{fds[0], POLLIN, 0};
    const int ready = left <= 0 ? 0 : ::poll(&pfd, 1, left);
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0) {
      kill_it = true;
      break;
    }
    const ssize_t r = ready < 0 ? -1 : ::read(fds[0], buf, sizeof buf);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;  // end of file: the child closed the pipe (or exited)
    data.append(buf, static_cast<std::size_t>(r));
    // Take the complete messages; each one restarts the clock.
    if (take_messages(data, out.messages, ended) > 0) deadline = clock::now() + limit;
  }
  ::close(fds[0]);
  if (kill_it) ::kill(pid, SIGKILL);
  int status = 0;
  for (;;) {
    const pid_t w = ::waitpid(pid, &status, kill_it ? 0 : WNOHANG);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) break;
    if (w == 0 && ms_left() <= 0) {  // it closed the pipe but does not end
      kill_it = true;
      ::kill(pid, SIGKILL);
    } else if (w == 0) {
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  }
  if (WIFSIGNALED(status)) {
    out.signal = WTERMSIG(status);
    out.timed_out = kill_it && out.signal == SIGKILL;
  } else if (WIFEXITED(status)) {
    out.exit_status = WEXITSTATUS(status);
  }
  out.finished = ended && !out.signal && out.exit_status == 0;
  return out;
}

}  // namespace gdsmc::host
