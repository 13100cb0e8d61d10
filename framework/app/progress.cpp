#include "app/progress.hpp"

#include "engine/plugin_calls.hpp"
#include "output/output_path.hpp"

#include <unistd.h>

#include <csignal>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace gdsmc::host {

std::atomic<bool> g_interrupted{false};

namespace {
// The first signal sets the flag, which the run polls between steps and inside the collision
// stage, and starts the watchdog: a plugin call under way then that has not returned 3 s later
// ends the run naming the plugin (engine/plugin_calls.hpp). A second one while the first is pending means the run is inside a long plugin call that
// cannot poll it: leave at once (exchange, write, lstat and unlink are async-signal-safe; the
// output is renamed to its final name only once complete, and its temporary file is removed).
extern "C" void on_signal(int) {
  if (g_interrupted.exchange(true)) {
    static const char message[] = "\ngdsmc: interrupted again; stopped at once, no output written\n";
    (void)!::write(STDERR_FILENO, message, sizeof message - 1);
    remove_live_temporaries_from_signal_handler();
    ::_exit(130);
  }
  watch_interrupt_from_signal_handler();  // a plugin call that does not return ends the run anyway
}
}  // namespace

void install_interrupt_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

std::string format_seconds(double s) {
  char buf[64];
  if (!(s >= 0)) return "?";
  const double whole = std::round(s);  // so that 5399.7 s is 90m00s, not 89m60s
  if (s < 90) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 5400) std::snprintf(buf, sizeof buf, "%.0fm%02.0fs", std::floor(whole / 60), std::fmod(whole, 60.0));
  else if (s < 48 * 3600.0) std::snprintf(buf, sizeof buf, "%.1fh", s / 3600);
  else if (s < 1000 * 86400.0) std::snprintf(buf, sizeof buf, "%.0fd", s / 86400);
  else return ">1000d";  // an estimate from a tiny fraction done, or a stop that is out of reach
  return buf;
}

std::function<void(const StudyProgress&)> progress_reporter(bool tty) {
  // Percentage, elapsed and time left are for the whole study (every case and realization).
  return [tty](const StudyProgress& sp) {
    const Progress& pr = sp.progress;
    char line[384];
    std::string run = sp.runs > 1 ? "run " + std::to_string(sp.run + 1) + "/" + std::to_string(sp.runs) + " " : "";
    if (!sp.label.empty()) run += "(" + sp.label + ") ";
    std::snprintf(line, sizeof line, "[%3.0f%%] %ss = %-8.4g t = %-9.4g tau0  T/T0 = %-10.4g elapsed %s, left ~%s",
                  100 * sp.fraction, run.c_str(), pr.collisions_per_particle, pr.time_tau0, pr.temperature_over_T0,
                  format_seconds(sp.elapsed_seconds).c_str(), format_seconds(sp.remaining_seconds).c_str());
    if (tty) std::cerr << "\r" << line << "\033[K" << std::flush;
    else std::cerr << line << "\n";
  };
}

}  // namespace gdsmc::host
