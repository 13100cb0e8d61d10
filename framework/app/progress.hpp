// The terminal side of a run: the progress line, and the flag SIGINT/SIGTERM set.
#pragma once
#include <atomic>
#include <functional>
#include <string>

#include "study/study.hpp"

namespace gdsmc::host {

// "42s", "3m07s", "1.5h", "12d", ">1000d" (however large, infinite included); "?" for a negative
// or NaN (unknown) time.
std::string format_seconds(double s);

// Prints the progress line on stderr (percentage, elapsed time and time left of the whole study;
// s, t and T of the current run): refreshed in place on a terminal (tty), one line per call otherwise.
std::function<void(const StudyProgress&)> progress_reporter(bool tty);

// Set by SIGINT and SIGTERM once install_interrupt_handlers() has run; a second signal while it is
// set ends the process at once with status 130.
extern std::atomic<bool> g_interrupted;
void install_interrupt_handlers();

}  // namespace gdsmc::host
