#include "engine/memory_estimate.hpp"

#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <new>
#include <sstream>

#include "config/units.hpp"
#include "engine/engine.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {

thread_local RunLayout* g_collecting = nullptr;  // set by setup_layout() while it sets a case up

// malloc's bytes in use (arenas and mmapped blocks) of the whole process.
double heap_in_use() {
  const struct mallinfo2 m = ::mallinfo2();
  return static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd);
}
thread_local double g_heap_before = 0;

// A "Key:   123 kB" line of a /proc file, in bytes (-1 if absent).
double proc_kib(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream ss(line.substr(key.size() + 1));
      double kib = -1;
      ss >> kib;
      return kib < 0 ? -1 : kib * 1024;
    }
  return -1;
}

}  // namespace

void report_layout(const std::vector<AttributeSpec>& attributes, const std::vector<DiagnosticOutput>& diagnostics) {
  if (!g_collecting) return;
  RunLayout& l = *g_collecting;
  l = RunLayout{};
  l.setup_bytes = std::max(heap_in_use() - g_heap_before, 0.0);
  for (const auto& a : attributes) l.attribute_values += static_cast<std::size_t>(std::max(a.components, 0));
  for (const auto& d : diagnostics) {
    std::size_t values = 2 + d.columns.size() + d.profiles.size() * d.bins();  // time and s are the host's
    l.values_per_record.push_back(values);
    l.profiles.push_back(d.profiles.size());
    if (!d.profiles.empty()) l.bins = d.bins();
  }
}

RunLayout RunLayout::with_bins(std::size_t n) const {
  RunLayout l = *this;
  for (std::size_t d = 0; d < l.values_per_record.size(); ++d)
    l.values_per_record[d] = l.values_per_record[d] - profiles[d] * bins + profiles[d] * n;
  l.bins = n;
  return l;
}

RunLayout setup_layout(const Pipeline& p) {
  RunLayout layout;
  struct Collect {
    explicit Collect(RunLayout* l) { g_collecting = l; }
    ~Collect() { g_collecting = nullptr; }
  } collect(&layout);
  g_heap_before = heap_in_use();
  Engine::check_setup(p);
  return layout;
}

CaseMemory case_memory(const Pipeline& p, const RunLayout& layout) {
  CaseMemory m;
  m.particles = p.particles;
  // ParticleStore: vx, vy, vz and the identity (4), and the attributes: 28 bytes in a homogeneous
  // system. A slab adds x, y, z, the layer index (4), each layer's member list (4) and the
  // reordering's scratch array (4): 64 bytes, and the sort's count of every layer per block of
  // CellGrid::kSortBlock particles (0.02 bytes a particle with 100 layers).
  m.bytes_per_particle = 3 * 8 + 4 + 8.0 * static_cast<double>(layout.attribute_values);
  if (p.geometry == Geometry::slab)
    m.bytes_per_particle += 3 * 8 + 4 + 4 + 4 + 4.0 * static_cast<double>(p.layers) / CellGrid::kSortBlock;
  // A mixture: the species index (4), and each collision group's species-sorted list of its
  // particles (4, one group per thread at a time: counted once per particle, an upper bound).
  if (!p.species.empty()) m.bytes_per_particle += 4 + 4;
  // Records are kept for the whole run. s grows by about dt/sqrt(pi) per step of dt tau0 (each
  // hard sphere collides once per mean free time sqrt(pi)/2 tau0 at T0, and a collision counts for
  // two particles; an elastic gas to s = 20 at dt = 0.02 tau0 takes 1769 steps, this gives 1773).
  // A gas that cools at a fixed step takes more: study.cpp checks what the first run kept.
  double stop = std::numeric_limits<double>::infinity();
  if (p.stop_time_tau0) stop = *p.stop_time_tau0;
  if (p.stop_collisions_per_particle) stop = std::min(stop, *p.stop_collisions_per_particle * 2 * kMeanFreeTimeTau0);
  m.steps = std::isfinite(stop) && p.time_step_tau0 > 0 ? std::ceil(stop / p.time_step_tau0) : 0;
  for (std::size_t d = 0; d < layout.values_per_record.size() && d < p.diagnostics.size(); ++d) {
    const double records = std::floor(m.steps / static_cast<double>(p.diagnostics[d].record_every)) + 2;
    m.records_bytes += records * static_cast<double>(layout.values_per_record[d]) * 8;
  }
  // While a case runs: the running engine's particles, plugins and records (grown by doubling: up
  // to twice their size), the earlier realizations' records, the case's first output; then the
  // average (mean and standard error) is built beside them.
  const double k = p.realizations;
  // Below 1 MiB the measurement is the noise of the host's own first allocations: not counted.
  m.setup_bytes = layout.setup_bytes >= 1024.0 * 1024 ? layout.setup_bytes : 0;
  m.peak = std::max(static_cast<double>(m.particles) * m.bytes_per_particle + m.setup_bytes + (k + 3) * m.records_bytes,
                    (k + 3) * m.records_bytes);
  m.kept = (k > 1 ? 2 : 1) * m.records_bytes + (p.output_realizations ? k * m.records_bytes : 0);
  return m;
}

MemoryEstimate study_memory(const std::vector<CaseMemory>& cases, std::uint32_t concurrent) {
  MemoryEstimate e;
  double kept = 0;
  if (concurrent > 1) {  // any runs may overlap: bound by the largest run, that many times
    for (std::size_t c = 0; c < cases.size(); ++c) {
      if (c == 0 || cases[c].peak > e.at_peak.peak) {
        e.peak_case = c;
        e.at_peak = cases[c];
      }
      kept += cases[c].kept;
    }
    e.concurrent = concurrent;
    e.kept_before = kept;
    e.bytes = kept + concurrent * e.at_peak.peak;
    return e;
  }
  for (std::size_t c = 0; c < cases.size(); ++c) {
    if (kept + cases[c].peak > e.bytes || c == 0) {
      e.bytes = kept + cases[c].peak;
      e.peak_case = c;
      e.kept_before = kept;
      e.at_peak = cases[c];
    }
    kept += cases[c].kept;
  }
  return e;
}

std::string MemoryEstimate::drivers() const {
  const CaseMemory& c = at_peak;
  std::string s = concurrent > 1 ? std::to_string(concurrent) + " runs at once (run.threads; --threads 1 runs one at a time), each " : "";
  s += std::to_string(c.particles) + " particles x " + fmt("%.0f", c.bytes_per_particle) + " bytes = " +
       bytes_text(static_cast<double>(c.particles) * c.bytes_per_particle);
  if (c.setup_bytes >= 1024 * 1024) s += "; what the plugins allocate at setup " + bytes_text(c.setup_bytes);
  s += "; diagnostics' records about " + bytes_text(c.records_bytes) + fmt(" (about %.0f steps)", c.steps);
  if (kept_before > 0)
    s += "; " + bytes_text(kept_before) + (concurrent > 1 ? " kept from the cases until the file is written"
                                                           : " kept from earlier cases until the file is written");
  return s;
}

double diagnostics_bytes(const std::vector<DiagnosticOutput>& diagnostics) {
  double values = 0;
  for (const auto& d : diagnostics) {
    values += static_cast<double>(d.time.size() + d.collisions_per_particle.size());
    for (const auto& c : d.columns) values += static_cast<double>(c.values.size());
    for (const auto& p : d.profiles) values += static_cast<double>(p.values.size());
    for (const auto& a : d.arrays) values += static_cast<double>(a.data.size());
    for (const auto& h : d.histograms) values += static_cast<double>(h.edges.size() + h.values.size());
  }
  return 8 * values;
}

MemoryAvailable available_memory() {
  MemoryAvailable a;
  a.bytes = std::numeric_limits<double>::infinity();
  const double meminfo = proc_kib("/proc/meminfo", "MemAvailable");
  if (meminfo >= 0) {
    a.bytes = meminfo;
    a.source = "MemAvailable " + bytes_text(meminfo);
  }
  auto limit = [&](int resource, const char* in_use_key, const char* name) {
    rlimit rl{};
    if (::getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return;
    const double cap = static_cast<double>(rl.rlim_cur), used = std::max(proc_kib("/proc/self/status", in_use_key), 0.0);
    const double left = std::max(cap - used, 0.0);
    const std::string what = std::string(name) + " " + bytes_text(cap) + " less " + bytes_text(used) + " in use";
    if (left < a.bytes) {
      a.source = what + (a.source.empty() ? "" : "; " + a.source);
      a.bytes = left;
    } else {
      a.source += "; " + what;
    }
  };
  limit(RLIMIT_AS, "VmSize", "the address-space limit (ulimit -v)");
  limit(RLIMIT_DATA, "VmData", "the data limit (ulimit -d)");
  return a;
}

std::string failure_text(const std::exception& e, const MemoryEstimate* estimate) {
  std::string text = e.what();
  const std::string bad_alloc = std::bad_alloc().what();
  if (dynamic_cast<const std::bad_alloc*>(&e))
    text.clear();
  else if (text.size() >= bad_alloc.size() && text.compare(text.size() - bad_alloc.size(), bad_alloc.size(), bad_alloc) == 0)
    text.erase(text.size() - bad_alloc.size());  // a plugin's failure wrapped around it
  else
    return text;
  const MemoryAvailable available = available_memory();
  text += "memory ran out (" + bytes_text(available.bytes) + " is available now: " + available.source;
  if (estimate)
    text += "; the estimate was about " + bytes_text(estimate->bytes) + ": " + estimate->drivers() +
            ", without what plugins allocate themselves";
  return text + ")";
}

}  // namespace gdsmc::host
