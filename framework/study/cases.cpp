#include "study/cases.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <new>
#include <thread>

#include "util/text.hpp"

namespace gdsmc::host {

namespace {

using AxisValues = std::vector<std::pair<std::string, std::string>>;  // axis name -> value label, one per axis

// Calls `progress` every 2 s once a stage has taken 2 s.
class Ticker {
 public:
  Ticker(const CheckProgress& progress, const char* stage) : progress_(progress), stage_(stage) {}
  void operator()(std::size_t done, std::size_t total) {
    if (!progress_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return;
    progress_(stage_, done, total);
    next_ = now + kInterval;
  }

 private:
  static constexpr std::chrono::seconds kInterval{2};
  const CheckProgress& progress_;
  const char* stage_;
  std::chrono::steady_clock::time_point next_ = std::chrono::steady_clock::now() + kInterval;
};

std::string label_of(const AxisValues& values) {
  std::string label;
  for (const auto& [axis, value] : values) label += (label.empty() ? "" : ", ") + axis + "=" + value;
  return label;
}

// Problems found in the cases, each reported once with the cases it occurs in (a problem a value
// of one axis causes shows in every case with that value; one of the base pipeline in every case).
// Each keeps its fields (key path, plugin, parameter, ...), with the cases in sweep_cases.
class CaseProblems {
 public:
  explicit CaseProblems(std::vector<AxisValues> cases) : cases_(std::move(cases)) {}
  void add(std::size_t c, const ConfigError& error) {
    auto [it, fresh] = hits_.try_emplace(error.text());
    if (fresh) order_.push_back(error);
    it->second.push_back(c);
  }
  void add(std::size_t c, const PipelineError& e) {
    for (const auto& error : e.errors()) add(c, error);
  }
  void add(std::size_t c, const std::string& message) { add(c, PipelineError({message})); }
  bool empty() const { return order_.empty(); }
  PipelineError error() const {
    std::vector<ConfigError> errors = order_;
    for (auto& error : errors) error.sweep_cases = in_cases(hits_.at(error.text()));
    return PipelineError(std::move(errors));
  }

 private:
  std::string in_cases(const std::vector<std::size_t>& hit) const {
    const std::size_t total = cases_.size();
    if (total == 0 || cases_[0].empty()) return "";  // no sweep
    auto one = [&](std::size_t c) { return std::to_string(c) + " (" + label_of(cases_[c]) + ")"; };
    if (hit.size() == 1) return "in sweep case " + one(hit[0]);
    if (hit.size() == total) return "in all " + std::to_string(total) + " sweep cases";
    // The values every case with the problem shares: when exactly the cases with them have it, say so.
    AxisValues common;
    for (std::size_t a = 0; a < cases_[hit[0]].size(); ++a) {
      bool shared = true;
      for (std::size_t c : hit) shared = shared && cases_[c][a].second == cases_[hit[0]][a].second;
      if (shared) common.push_back(cases_[hit[0]][a]);
    }
    if (!common.empty()) {
      std::size_t matching = 0;
      for (const auto& values : cases_) {
        bool match = true;
        for (const auto& [axis, value] : common)
          for (const auto& [a, v] : values) match = match && (a != axis || v == value);
        matching += match ? 1 : 0;
      }
      if (matching == hit.size())
        return "in the " + std::to_string(hit.size()) + " sweep cases with " + label_of(common) + " (of " +
               std::to_string(total) + ")";
    }
    std::string s = "in " + std::to_string(hit.size()) + " of " + std::to_string(total) + " sweep cases: ";
    for (std::size_t k = 0; k < hit.size() && k < 3; ++k) s += (k ? ", " : "") + one(hit[k]);
    if (hit.size() > 3) s += " and " + std::to_string(hit.size() - 3) + " more";
    return s;
  }

  std::vector<AxisValues> cases_;
  std::vector<ConfigError> order_;  // first seen first
  std::map<std::string, std::vector<std::size_t>> hits_;  // by the error's text
};

// n rounded down to two significant digits (a figure to suggest, not a promise).
std::size_t round_down(double n) {
  if (n < 100) return static_cast<std::size_t>(std::max(n, 0.0));
  const double unit = std::pow(10.0, std::floor(std::log10(n)) - 1);
  return static_cast<std::size_t>(std::floor(n / unit) * unit);
}

// The message when the study needs more memory than is available: where, how much and what to change.
std::string memory_message(const std::vector<StudyCase>& cases, const MemoryEstimate& estimate,
                           const MemoryAvailable& available) {
  const StudyCase& peak = cases[estimate.peak_case];
  const CaseMemory& m = estimate.at_peak;
  const double particles = estimate.concurrent * static_cast<double>(m.particles) * m.bytes_per_particle,
               others = estimate.bytes - particles;
  // Located at run.particles, unless the records are what does not fit.
  std::string message = particles >= others ? peak.pipeline.particles_where.str() + ": run.particles: "
                                            : peak.pipeline.file.string() + ": diagnostics: ";
  message += std::string(cases.size() > 1 || estimate.concurrent > 1 ? "this study needs about " : "this run needs about ") +
             bytes_text(estimate.bytes) + " of memory";
  if (!peak.label.empty())
    message += " (at its peak, in sweep case " + std::to_string(estimate.peak_case) + " (" + peak.label + "))";
  message += " but " + bytes_text(available.bytes) + " is available (" + available.source + "); the estimate: " +
             estimate.drivers();
  if (estimate.concurrent * m.setup_bytes > 0.5 * others)
    message += "; the plugins allocate about " + bytes_text(m.setup_bytes) + " at setup" +
               (peak.pipeline.geometry == Geometry::slab && (peak.pipeline.bins ? peak.pipeline.bins : peak.pipeline.layers) > kProbeBins
                    ? fmt(" (measured with %zu and %zu sampling bins, for %zu): use fewer system.bins", kProbeBins,
                          2 * kProbeBins, peak.pipeline.bins ? peak.pipeline.bins : peak.pipeline.layers)
                    : std::string());
  else if (others < available.bytes)
    message += "; at most about " +
               std::to_string(round_down((available.bytes - others) / (estimate.concurrent * m.bytes_per_particle))) +
               " particles fit" + (estimate.concurrent > 1 ? " per run" : "");
  else
    message += "; the records alone need " + bytes_text(others) +
               ": record less often (record_every), stop sooner (run.stop) or run fewer realizations";
  return message;
}

}  // namespace

double sweep_case_count(const Pipeline& p) {
  double n = 1;
  for (const auto& axis : p.sweep) n *= static_cast<double>(axis.values.size());
  return n;
}

std::vector<StudyCase> expand_cases(const LoadedPipeline& loaded, const CheckProgress& progress) {
  const Pipeline& base = loaded.pipeline;
  std::vector<StudyCase> cases;
  if (base.sweep.empty()) {
    cases.push_back(StudyCase{"", {}, base});
    return cases;
  }
  // Counted before anything is expanded: every case is a whole pipeline, loaded, set up and kept.
  if (const double n = sweep_case_count(base); n > kMaxSweepCases) {
    std::string sizes;
    for (const auto& axis : base.sweep)
      sizes += (sizes.empty() ? "" : " x ") + std::to_string(axis.values.size()) + " (" + axis.name + ")";
    const auto& first = base.sweep.front().values.front();
    const std::string where = first.where.empty() ? base.file.string() : first.where.front().str();
    throw PipelineError({where + ": sweep: " + sizes + " make " + fmt("%.4g", n) + " cases; at most " +
                         std::to_string(static_cast<std::size_t>(kMaxSweepCases)) +
                         " are allowed (each case is a whole run, loaded and checked before anything runs): "
                         "sweep fewer values or fewer keys, or split the study into several pipelines"});
  }
  // The points of the Cartesian product of the axes, the last axis varying fastest.
  std::vector<std::vector<const SweepAxis::Value*>> points;
  std::vector<AxisValues> values;
  std::vector<std::size_t> index(base.sweep.size(), 0);
  while (true) {
    points.emplace_back();
    values.emplace_back();
    for (std::size_t a = 0; a < base.sweep.size(); ++a) {
      const SweepAxis::Value& v = base.sweep[a].values[index[a]];
      points.back().push_back(&v);
      values.back().emplace_back(base.sweep[a].name, v.label);
    }
    std::size_t a = base.sweep.size();
    while (a-- > 0) {
      if (++index[a] < base.sweep[a].values.size()) break;
      index[a] = 0;
    }
    if (a == static_cast<std::size_t>(-1)) break;
  }
  CaseProblems problems(values);
  const SweepCaseLoader loader(loaded);
  Ticker tick(progress, "loaded");
  cases.reserve(points.size());
  for (std::size_t c = 0; c < points.size(); ++c) {
    try {
      cases.push_back(StudyCase{label_of(values[c]), values[c], loader.load(points[c])});
    } catch (const PipelineError& e) {
      problems.add(c, e);
    }
    tick(c + 1, points.size());
  }
  if (!problems.empty()) throw problems.error();
  cases.front().pipeline.source_text = base.source_text;
  cases.front().pipeline.resolved_text = base.resolved_text;
  return cases;
}

std::uint32_t total_threads(const std::vector<StudyCase>& cases) {
  const std::uint32_t threads = cases.front().pipeline.threads;
  return threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : threads;
}

std::size_t study_runs(const std::vector<StudyCase>& cases) {
  std::size_t runs = 0;
  for (const auto& c : cases) runs += c.pipeline.realizations;
  return runs;
}

std::uint32_t study_threads(const std::vector<StudyCase>& cases, std::size_t runs) {
  return static_cast<std::uint32_t>(std::max<std::size_t>(1, std::min<std::size_t>(total_threads(cases), runs)));
}
std::uint32_t study_threads(const std::vector<StudyCase>& cases) { return study_threads(cases, study_runs(cases)); }

std::uint32_t threads_per_run(const std::vector<StudyCase>& cases, std::size_t runs) {
  return std::max(1u, total_threads(cases) / study_threads(cases, runs));
}
std::uint32_t threads_per_run(const std::vector<StudyCase>& cases) { return threads_per_run(cases, study_runs(cases)); }

MemoryEstimate check_cases(const std::vector<StudyCase>& cases, const CheckProgress& progress) {
  std::vector<AxisValues> values;
  for (const auto& c : cases) values.push_back(c.axis_values);
  CaseProblems problems(std::move(values));
  std::vector<CaseMemory> memory;
  std::vector<std::size_t> deferred;  // cases set up with kProbeBins first, and for real once the estimate fits
  Ticker tick(progress, "set up");
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const Pipeline& p = cases[c].pipeline;
    try {
      // Plugins may keep arrays per sampling bin: a case of many bins is set up with a few first,
      // and its profiles' records are estimated for its own number before it is set up for real.
      const std::size_t bins = p.geometry == Geometry::slab ? (p.bins ? p.bins : p.layers) : 0;
      if (bins > kProbeBins) {
        // Set up with kProbeBins and twice as many: what the plugins allocate per bin, measured,
        // extrapolated to the case's own bins.
        Pipeline probe = p;
        probe.bins = kProbeBins;
        RunLayout layout = setup_layout(probe);
        probe.bins = 2 * kProbeBins;
        const double per_bin = std::max(setup_layout(probe).setup_bytes - layout.setup_bytes, 0.0) / kProbeBins;
        const double setup_bytes = layout.setup_bytes + per_bin * static_cast<double>(bins - kProbeBins);
        layout = layout.with_bins(bins);
        layout.setup_bytes = setup_bytes;
        memory.push_back(case_memory(p, layout));
        deferred.push_back(c);
      } else {
        memory.push_back(case_memory(p, setup_layout(p)));
      }
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const PipelineError& e) {
      problems.add(c, e);
    } catch (const std::exception& e) {
      problems.add(c, p.file.string() + ": " + failure_text(e, nullptr));
    }
    tick(c + 1, cases.size());
  }
  if (!problems.empty()) throw problems.error();

  const MemoryEstimate estimate = study_memory(memory, study_threads(cases));
  const MemoryAvailable available = available_memory();
  if (estimate.bytes <= available.bytes) {
    for (const std::size_t c : deferred) {
      try {
        setup_layout(cases[c].pipeline);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const PipelineError& e) {
        problems.add(c, e);
      } catch (const std::exception& e) {
        problems.add(c, cases[c].pipeline.file.string() + ": " + failure_text(e, &estimate));
      }
    }
    if (!problems.empty()) throw problems.error();
    return estimate;
  }
  throw PipelineError({memory_message(cases, estimate, available)});
}

}  // namespace gdsmc::host
