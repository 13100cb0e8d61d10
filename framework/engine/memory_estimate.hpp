// The memory a study needs, estimated when it is checked (particles, attributes, cells, the
// diagnostics' records, what each case keeps until the file is written), and the memory this
// process can still take: a study that cannot fit is refused before it starts, with both figures.
#pragma once
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include <gdsmc/particles.hpp>

#include "config/pipeline.hpp"
#include "output/diagnostic_output.hpp"

namespace gdsmc::host {

// What the plugins of one case declared when they were set up.
struct RunLayout {
  std::size_t attribute_values = 0;              // doubles per particle, over every declared attribute
  std::vector<std::size_t> values_per_record;    // per diagnostic: time, s, each series, each profile's bins
  std::vector<std::size_t> profiles;             // per diagnostic: its profiles (each a value per bin)
  std::size_t bins = 0;                          // the sampling bins the profiles were set up with
  // The heap the plugins (and the host's setup) held once the diagnostics had begun, measured
  // (malloc's bytes in use) while they were alive: what plugins allocate themselves at setup.
  double setup_bytes = 0;

  // The layout the same plugins declare with `bins` sampling bins instead (a profile holds a value
  // per bin): what check_cases() estimates from before it sets a case up with many bins.
  RunLayout with_bins(std::size_t bins) const;
};

// The engine reports what its plugins declared once its diagnostics have begun; setup_layout()
// collects it (elsewhere the call does nothing).
void report_layout(const std::vector<AttributeSpec>& attributes, const std::vector<DiagnosticOutput>& diagnostics);

// Set up the plugins of `p` as validate does (Engine::check_setup; throws like it) and return what
// they declared.
RunLayout setup_layout(const Pipeline& p);

// One case: its particles, and the records of its diagnostics.
struct CaseMemory {
  std::size_t particles = 0;
  double bytes_per_particle = 0;  // positions, velocities, identity, cell, attributes; slab: layer lists, reorder scratch
  double steps = 0;               // estimated: the stop time, or s at dt/sqrt(pi) per step (hard spheres at T0)
  double records_bytes = 0;       // one realization's records, every diagnostic
  double setup_bytes = 0;         // what its plugins allocated at setup (measured), per run
  double peak = 0;                // while the case runs (besides what earlier cases keep)
  double kept = 0;                // what the case keeps until the file is written (its averaged records)
};
CaseMemory case_memory(const Pipeline& p, const RunLayout& layout);

// The memory a study needs at its peak, and what drives it.
struct MemoryEstimate {
  double bytes = 0;
  std::uint32_t concurrent = 1;  // runs at once (run.threads): each holds its particles and records
  std::size_t peak_case = 0;  // the case during which the peak is reached
  double kept_before = 0;     // what the cases before it keep at that time
  CaseMemory at_peak;
  // "4000000000 particles x 28 bytes = 104 GiB; diagnostics' records about 12 MiB (about 5000
  // steps); 3 MiB kept from earlier cases"
  std::string drivers() const;
};
// The study's peak: the cases run one after another, each keeping its outputs until the end; with
// `concurrent` runs at once (run.threads), that many of the largest run's peak on top of
// everything the cases keep.
MemoryEstimate study_memory(const std::vector<CaseMemory>& cases, std::uint32_t concurrent = 1);

// The bytes the values of `diagnostics` hold (series, profiles, arrays, histograms): what a finished
// run keeps until its case is averaged.
double diagnostics_bytes(const std::vector<DiagnosticOutput>& diagnostics);

// What this process can still allocate: the smaller of MemAvailable (/proc/meminfo) and what the
// address-space and data limits (RLIMIT_AS, RLIMIT_DATA) leave of what is in use.
struct MemoryAvailable {
  double bytes = 0;      // +infinity when nothing is known
  std::string source;    // "MemAvailable 21 GiB", "the address-space limit (ulimit -v) 977 MiB less 150 MiB in use"
};
MemoryAvailable available_memory();

// What a failure says, with an out-of-memory one (std::bad_alloc, or an error a plugin's
// std::bad_alloc was wrapped into) explained: memory ran out, and the estimate when known.
std::string failure_text(const std::exception& e, const MemoryEstimate* estimate);

}  // namespace gdsmc::host
