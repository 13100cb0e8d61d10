// Results of checks and their isolation in a child process (plugins/child_process.hpp).
#include "conformance/internal.hpp"
#include "plugins/child_process.hpp"

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
  const ChildOutcome c = run_in_child(
      [&](ChildReport& report) {
        const Result r = guarded(fn);
        report.send(std::string(1, static_cast<char>('0' + static_cast<int>(r.status))) + r.message);
      },
      timeout_seconds, false);
  if (!c.failure.empty()) return fail(c.failure);
  if (c.timed_out) return fail(fmt("did not finish within %d s (--timeout)", timeout_seconds));
  if (c.signal)
    return {Status::crash, fmt("crashed: the check's process died of signal %d (%s)", c.signal, strsignal(c.signal))};
  if (!c.finished || c.messages.empty())
    return {Status::crash, fmt("crashed: the check's process exited (status %d) without reporting", c.exit_status)};
  Result r;
  r.status = static_cast<Status>(c.messages[0][0] - '0');
  r.message = c.messages[0].substr(1);
  return r;
}

}  // namespace gdsmc::host::conformance
