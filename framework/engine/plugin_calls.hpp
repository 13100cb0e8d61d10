// Which plugin call is under way on each thread, for the handler of a fatal signal (SIGSEGV,
// SIGBUS, SIGFPE, SIGABRT): it prints the plugin, its role, the step and the run, removes the
// temporary output file and the output lock, and ends the process with the signal (exit status
// 128 + its number). The record is a thread-local pair of pointers to data that lives as long as
// the engine: a PluginCall costs a load and two stores on entry, two stores on exit, never a
// system call (the thread's alternate signal stack is set up at its first plugin call).
#pragma once
#include <cstdint>
#include <string>

namespace gdsmc::host {

// One plugin object of one run, as the handler names it. Every pointer stays valid while the
// engine that owns the site exists.
struct PluginCallSite {
  const char* plugin = "";              // its name
  const char* role = "";                // "collision rule", "forcing", "wall", "initial state", "diagnostic"
  const char* where = "";               // "collision, pipeline.yaml:8:12"
  const std::uint64_t* step = nullptr;  // the run's step counter, StepContext::step
  const char* run = "";                 // "run 2 of 4 (alpha=0.5)", "" for a study of one run
};

struct PluginCallRecord {
  const PluginCallSite* site = nullptr;
  const char* call = nullptr;  // the method: "collide_batch", "sample", ...
};

// The call under way on this thread (site null: none). Read by the signal handler.
extern thread_local constinit PluginCallRecord t_plugin_call;
// Plugin calls begun on this thread: a call under way whose count has not changed since an
// interrupt has not returned since (read by the interrupt watchdog).
extern thread_local constinit std::uint64_t t_plugin_calls;
extern thread_local constinit bool t_signal_stack_ready;
void prepare_signal_stack();  // this thread's alternate signal stack (once per thread)

// Marks a plugin call for its scope; nests (restores the enclosing record).
class PluginCall {
 public:
  PluginCall(const PluginCallSite& site, const char* call) noexcept : saved_(t_plugin_call) {
    if (!t_signal_stack_ready) prepare_signal_stack();
    t_plugin_call = PluginCallRecord{&site, call};
    ++t_plugin_calls;
  }
  ~PluginCall() { t_plugin_call = saved_; }
  PluginCall(const PluginCall&) = delete;
  PluginCall& operator=(const PluginCall&) = delete;

 private:
  PluginCallRecord saved_;
};

// The run the engines built on this thread belong to, as the handler names it ("run 2 of 4
// (alpha=0.5)", with "rank R of K, " in an MPI job): set by the study before it builds a run's
// engine, which copies it.
void set_thread_run_name(std::string name);
const std::string& thread_run_name();

// The interrupt watchdog. Called by the handler of the first SIGINT/SIGTERM (async-signal-safe):
// notes the plugin calls under way on every thread and arms a timer of kStuckCallSeconds. When
// it expires and one of those calls has still not returned (the run cannot reach the places where
// it polls the interrupt), it prints the plugin, its role, the call, the step and the run, removes
// the temporary output file and the output lock, and ends the process with status 130. Calls begun
// after the interrupt (a checkpoint's, a diagnostic's last record) are never cut short.
inline constexpr unsigned kStuckCallSeconds = 3;
void watch_interrupt_from_signal_handler() noexcept;

// Installs the handler of SIGSEGV, SIGBUS, SIGFPE and SIGABRT (on an alternate stack, so that a
// stack overflow is reported too). Idempotent.
void install_fatal_signal_handlers();

}  // namespace gdsmc::host
