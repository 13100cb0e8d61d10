// Results of checks and their isolation in a child process (fork, pipe, alarm).
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Results and isolation

const char* status_text(Status s) {
  switch (s) {
    case Status::pass: return "PASS";
    case Status::fail: return "FAIL";
    case Status::skip: return "SKIP";
    case Status::crash: return "CRASH";
  }
  return "?";
}

std::string vec_text(const Vec3& v) { return fmt("(%.6g, %.6g, %.6g)", v.x, v.y, v.z); }

Result guarded(const std::function<Result()>& fn) {
  try {
    return fn();
  } catch (const PipelineError& e) {
    std::string m;
    for (const auto& s : e.messages()) m += (m.empty() ? "" : "; ") + s;
    return fail("the test pipeline was refused: " + m);
  } catch (const std::exception& e) {
    return fail(std::string("threw: ") + e.what());
  } catch (...) {
    return fail("threw an exception that is not a std::exception");
  }
}

// Runs fn in a child process; a signal or an exit without a result is a crash.
Result isolated(const std::function<Result()>& fn, bool use_fork, int timeout_seconds) {
  if (!use_fork) return guarded(fn);
  int fds[2];
  if (::pipe(fds) != 0) return fail(std::string("cannot create a pipe: ") + std::strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return fail(std::string("cannot fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    ::alarm(static_cast<unsigned>(timeout_seconds));
    const Result r = guarded(fn);
    std::string out(1, static_cast<char>('0' + static_cast<int>(r.status)));
    out += r.message;
    std::size_t off = 0;
    while (off < out.size()) {
      const ssize_t w = ::write(fds[1], out.data() + off, out.size() - off);
      if (w <= 0) break;
      off += static_cast<std::size_t>(w);
    }
    ::close(fds[1]);
    std::cout.flush();
    std::fflush(nullptr);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string data;
  char buf[4096];
  for (;;) {
    const ssize_t r = ::read(fds[0], buf, sizeof buf);
    if (r > 0) data.append(buf, static_cast<std::size_t>(r));
    else if (r < 0 && errno == EINTR) continue;
    else break;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGALRM) return fail(fmt("did not finish within %d s (--timeout)", timeout_seconds));
    return {Status::crash, fmt("crashed: the check's process died of signal %d (%s)", sig, strsignal(sig))};
  }
  if (data.empty())
    return {Status::crash, fmt("crashed: the check's process exited (status %d) without reporting", WEXITSTATUS(status))};
  Result r;
  r.status = static_cast<Status>(data[0] - '0');
  r.message = data.substr(1);
  return r;
}

}  // namespace gdsmc::host::conformance
