#include "study/study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "study/summary.hpp"

namespace gdsmc::host {

namespace {

using Clock = std::chrono::steady_clock;

// Where the study is, for progress reports of the runs.
struct StudyClock {
  Clock::time_point start = Clock::now();
  Clock::time_point last_report = start;  // of the study: runs shorter than the interval share it
  std::size_t run_index = 0, total_runs = 0;
};

// One case: every realization run, the diagnostics averaged and the steady averages added.
CaseOutput run_case(const StudyCase& sc, StudyClock& clock, StudyResult& result, std::vector<std::string>& case_summary,
                    const std::function<void(const StudyProgress&)>& report, double report_interval,
                    const std::atomic<bool>* interrupt) {
  const Pipeline& p = sc.pipeline;
  std::vector<std::vector<DiagnosticOutput>> runs;
  CaseOutput case_out;
  for (std::uint32_t r = 0; r < p.realizations; ++r, ++clock.run_index) {
    Engine engine(p, r);
    std::string label = sc.label;
    if (p.realizations > 1) label += (label.empty() ? "" : ", ") + std::string("realization ") + std::to_string(r);
    std::function<void(const Progress&)> inner;
    if (report) {
      inner = [&, label](const Progress& pr) {
        // At most one report per interval over the whole study (thousands of short realizations
        // each end with a report), and the very last one.
        const auto now = Clock::now();
        const bool last = pr.final && clock.run_index + 1 == clock.total_runs;
        if (!last && std::chrono::duration<double>(now - clock.last_report).count() < report_interval) return;
        clock.last_report = now;
        StudyProgress sp;
        sp.run = clock.run_index;
        sp.runs = clock.total_runs;
        sp.label = label;
        sp.progress = pr;
        sp.fraction = (static_cast<double>(clock.run_index) + std::clamp(pr.fraction, 0.0, 1.0)) /
                      static_cast<double>(clock.total_runs);
        const double elapsed = std::chrono::duration<double>(now - clock.start).count();
        sp.elapsed_seconds = elapsed;
        sp.remaining_seconds = sp.fraction > 0 ? elapsed * (1 - sp.fraction) / sp.fraction : -1;
        report(sp);
      };
    }
    engine.run(inner, report_interval, interrupt);
    result.collisions += engine.context().collisions;
    result.steps += engine.context().step;
    if (r == 0) {
      case_out = engine.output();
      for (const auto& line : engine.summary())
        case_summary.push_back((p.realizations > 1 ? "[realization 0] " : "") + line);
    } else {
      case_out.run["wall_seconds"] += engine.wall_seconds();
      case_out.run["reached_steady_state"] = std::min(case_out.run["reached_steady_state"],
                                                      engine.reached_steady_state() ? 1.0 : 0.0);
    }
    runs.push_back(engine.diagnostics());
  }
  case_out.run["realizations"] = p.realizations;
  case_out.diagnostics = average_realizations(runs, nullptr);
  add_steady_averages(case_out.diagnostics, p.average_after_collisions_per_particle, p.average_after_time_tau0, runs);
  const std::string missed =
      steady_window_missed(case_out.diagnostics, p.average_after_collisions_per_particle, p.average_after_time_tau0);
  if (!missed.empty()) case_summary.push_back("warning: " + missed);
  if (p.output_realizations) {
    for (auto& run : runs) add_steady_averages(run, p.average_after_collisions_per_particle, p.average_after_time_tau0);
    for (std::size_t d = 0; d < case_out.diagnostics.size(); ++d)
      for (auto& run : runs) case_out.diagnostics[d].realizations.push_back(std::move(run[d]));
  }
  return case_out;
}

}  // namespace

StudyResult run_study(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                      double report_interval, const std::atomic<bool>* interrupt) {
  StudyClock clock;
  StudyResult result;
  describe_provenance(cases.front().pipeline, result.output);
  for (const auto& c : cases) clock.total_runs += c.pipeline.realizations;
  const bool sweep = cases.size() > 1 || !cases.front().label.empty();

  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    const StudyCase& sc = cases[ci];
    const Pipeline& p = sc.pipeline;
    std::vector<std::string> case_summary;
    CaseOutput case_out = run_case(sc, clock, result, case_summary, report, report_interval, interrupt);
    if (sweep) {
      case_out.group = "cases/" + std::to_string(ci);
      case_out.attributes["case"] = sc.label;
      for (const auto& [axis, value] : sc.axis_values) case_out.attributes["sweep." + axis] = value;
      result.summary.push_back("case " + std::to_string(ci) + ": " + sc.label);
      for (const auto& line : case_summary) result.summary.push_back("  " + line);
    } else {
      for (const auto& line : case_summary) result.summary.push_back(line);
    }
    if (p.realizations > 1) add_realization_lines(case_out.diagnostics, p.realizations, sweep, result.summary);
    result.output.cases.push_back(std::move(case_out));
  }
  if (sweep) result.output.summary = summary_table(cases, result.output.cases);
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - clock.start).count();
  return result;
}

}  // namespace gdsmc::host
