// Running untrusted plugin code in a forked child: a crash, an abort, an exit or a hang in a
// plugin ends the child, never the host. The registry probes libraries this way before loading
// them, and `gdsmc conformance` runs each check this way.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace gdsmc::host {

// The child's side: each send() reaches the parent at once, so what was sent before the child
// died is kept.
class ChildReport {
 public:
  explicit ChildReport(int fd) : fd_(fd) {}
  void send(const std::string& message);

 private:
  int fd_;
};

struct ChildOutcome {
  std::string failure;                // non-empty: no child ran (fork or pipe failed; the reason)
  std::vector<std::string> messages;  // what the child sent, in order
  bool finished = false;              // fn returned (and the child exited normally)
  int signal = 0;                     // the signal that ended the child (0: it exited)
  int exit_status = 0;                // its exit status, when it exited
  bool timed_out = false;             // killed (SIGKILL): timeout_seconds passed without a message
};

// Runs fn in a forked child and waits for it, at most timeout_seconds before its first message
// and between two messages. fn must not throw. With quiet, the child's stdout and stderr go to
// /dev/null (what a probed library prints would otherwise appear twice).
ChildOutcome run_in_child(const std::function<void(ChildReport&)>& fn, double timeout_seconds, bool quiet);

}  // namespace gdsmc::host
