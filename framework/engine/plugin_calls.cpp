#include "engine/plugin_calls.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <memory>

#include "output/output_path.hpp"

namespace gdsmc::host {

constinit thread_local PluginCallRecord t_plugin_call;
constinit thread_local bool t_signal_stack_ready = false;
constinit thread_local std::uint64_t t_plugin_calls = 0;

namespace {

thread_local std::string t_run_name;

// Every thread that has made a plugin call, for the interrupt watchdog: its record, its call
// count, and the count when the interrupt came (the slot is freed when the thread ends).
struct ThreadSlot {
  std::atomic<PluginCallRecord*> record{nullptr};
  std::atomic<const std::uint64_t*> calls{nullptr};
  std::uint64_t calls_at_interrupt = 0;
  const PluginCallSite* site_at_interrupt = nullptr;
};
constexpr int kThreadSlots = 1024;
ThreadSlot g_thread_slots[kThreadSlots];

// This thread's alternate signal stack and watchdog slot, given back when the thread ends.
struct SignalStack {
  std::unique_ptr<char[]> memory;
  int slot = -1;
  ~SignalStack() {
    if (slot >= 0) {
      g_thread_slots[slot].calls.store(nullptr);
      g_thread_slots[slot].record.store(nullptr);
    }
    if (!memory) return;
    stack_t off{};
    off.ss_flags = SS_DISABLE;
    ::sigaltstack(&off, nullptr);
  }
};
thread_local SignalStack t_signal_stack;
constexpr std::size_t kSignalStackBytes = 128 * 1024;  // above glibc's SIGSTKSZ on every platform

// The message, built with async-signal-safe calls only (no allocation, no stdio).
class Message {
 public:
  Message& operator<<(const char* s) {
    if (!s) return *this;
    while (*s && used_ < sizeof text_ - 1) text_[used_++] = *s++;
    return *this;
  }
  Message& operator<<(std::uint64_t v) {
    char digits[24];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v && n < 24);
    while (n > 0 && used_ < sizeof text_ - 1) text_[used_++] = digits[--n];
    return *this;
  }
  void write() const {
    std::size_t done = 0;
    while (done < used_) {
      const ssize_t w = ::write(STDERR_FILENO, text_ + done, used_ - done);
      if (w <= 0) break;
      done += static_cast<std::size_t>(w);
    }
  }

 private:
  char text_[4096];
  std::size_t used_ = 0;
};

const char* signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV (invalid memory access)";
    case SIGBUS: return "SIGBUS (bus error: unaligned or unmapped memory)";
    case SIGFPE: return "SIGFPE (arithmetic exception, e.g. an integer division by zero)";
    case SIGABRT: return "SIGABRT (abort: a failed assert, an uncaught exception or std::abort)";
  }
  return "a fatal signal";
}

std::atomic<int> g_fatal{0};
pid_t g_installer = 0;  // the process that installed the handler (not a child forked to load a plugin)

void die_of(int sig) {
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);
}

extern "C" void on_fatal_signal(int sig, siginfo_t*, void*) {
  // A child forked to probe a plugin library reports to its parent by its status alone (and
  // removes nothing of the parent's).
  if (::getpid() != g_installer) return die_of(sig);
  // One report: a second thread that crashes meanwhile waits for the first to end the process.
  if (g_fatal.exchange(1)) {
    for (;;) ::pause();
  }
  const PluginCallRecord call = t_plugin_call;
  Message m;
  m << "\ngdsmc: crashed: " << signal_name(sig);
  if (call.site) {
    const PluginCallSite& s = *call.site;
    m << " in the " << s.role << " '" << s.plugin << "' (" << s.where;
    if (call.call) m << "; in " << call.call;
    m << ")";
    if (s.step) m << " at step " << static_cast<std::uint64_t>(*s.step);
    if (s.run && *s.run) m << " of " << s.run;
    m << ": the plugin crashed";
  } else {
    m << " outside any plugin call: a defect of gdsmc itself (please report it with the pipeline)";
  }
  // (Not "the run failed; ...": under mpirun rank 0 says that, once, for the job.)
  m << "\ngdsmc: no output written (the temporary file is removed); the process ends with the signal: exit status "
    << static_cast<std::uint64_t>(128 + sig) << " (128 + the signal)\n";
  m.write();
  remove_live_temporaries_from_signal_handler();
  // End with the signal itself (its default action: the exit status 128 + sig, a core dump where
  // enabled): blocked in this handler, it is delivered as the handler returns.
  die_of(sig);
}

// The calls under way at the interrupt that are still under way; if any, say which and end.
extern "C" void on_watchdog_alarm(int) {
  if (::getpid() != g_installer) return;
  Message m;
  int stuck = 0;
  for (auto& slot : g_thread_slots) {
    const PluginCallRecord* record = slot.record.load();
    const std::uint64_t* calls = slot.calls.load();
    if (!record || !calls || !slot.site_at_interrupt) continue;
    const PluginCallRecord call = *record;
    if (call.site != slot.site_at_interrupt || *calls != slot.calls_at_interrupt) continue;  // returned since
    const PluginCallSite& s = *call.site;
    m << (stuck++ ? "\ngdsmc: " : "\ngdsmc: interrupted, but ") << "the " << s.role << " '" << s.plugin << "' (" << s.where;
    if (call.call) m << "; in " << call.call;
    m << ")";
    if (s.step) m << " at step " << static_cast<std::uint64_t>(*s.step);
    if (s.run && *s.run) m << " of " << s.run;
    m << " had not returned " << static_cast<std::uint64_t>(kStuckCallSeconds) << " s after the interrupt";
  }
  if (!stuck) {  // every call under way at the interrupt has returned: the run ends by itself
    ::alarm(kStuckCallSeconds);
    return;
  }
  m << "\ngdsmc: stopped without waiting for it; no output written (the temporary file is removed)\n";
  m.write();
  remove_live_temporaries_from_signal_handler();
  ::_exit(130);
}

}  // namespace

void watch_interrupt_from_signal_handler() noexcept {
  for (auto& slot : g_thread_slots) {
    const PluginCallRecord* record = slot.record.load();
    const std::uint64_t* calls = slot.calls.load();
    slot.site_at_interrupt = record && calls ? record->site : nullptr;
    slot.calls_at_interrupt = calls ? *calls : 0;
  }
  struct sigaction action {};
  action.sa_handler = on_watchdog_alarm;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  ::sigaction(SIGALRM, &action, nullptr);
  ::alarm(kStuckCallSeconds);
}

void prepare_signal_stack() {
  t_signal_stack_ready = true;
  for (int k = 0; k < kThreadSlots && t_signal_stack.slot < 0; ++k) {
    PluginCallRecord* none = nullptr;
    if (g_thread_slots[k].record.compare_exchange_strong(none, &t_plugin_call)) {
      g_thread_slots[k].calls.store(&t_plugin_calls);
      t_signal_stack.slot = k;
    }
  }
  stack_t current{};
  if (::sigaltstack(nullptr, &current) == 0 && !(current.ss_flags & SS_DISABLE)) return;  // one already
  t_signal_stack.memory.reset(new (std::nothrow) char[kSignalStackBytes]);
  if (!t_signal_stack.memory) return;
  stack_t stack{};
  stack.ss_sp = t_signal_stack.memory.get();
  stack.ss_size = kSignalStackBytes;
  if (::sigaltstack(&stack, nullptr) != 0) t_signal_stack.memory.reset();
}

void set_thread_run_name(std::string name) { t_run_name = std::move(name); }
const std::string& thread_run_name() { return t_run_name; }

void install_fatal_signal_handlers() {
  g_installer = ::getpid();
  prepare_signal_stack();
  struct sigaction action {};
  action.sa_sigaction = on_fatal_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_SIGINFO | SA_ONSTACK;
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGABRT}) ::sigaction(sig, &action, nullptr);
}

}  // namespace gdsmc::host
