#include "study.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <gdsmc/series.hpp>

namespace gdsmc::host {

std::vector<StudyCase> expand_cases(const Pipeline& base, const std::vector<std::string>& overrides,
                                    const std::vector<std::filesystem::path>& extra_plugin_paths) {
  std::vector<StudyCase> cases;
  if (base.sweep.empty()) {
    cases.push_back(StudyCase{"", {}, base});
    return cases;
  }
  // Cartesian product of the axes, the last axis varying fastest.
  std::vector<std::size_t> index(base.sweep.size(), 0);
  std::vector<std::string> errors;
  while (true) {
    StudyCase c;
    std::vector<std::string> sets = overrides;
    for (std::size_t a = 0; a < base.sweep.size(); ++a) {
      const auto& value = base.sweep[a].values[index[a]];
      c.axis_values.emplace_back(base.sweep[a].name, value.label);
      c.label += (c.label.empty() ? "" : ", ") + base.sweep[a].name + "=" + value.label;
      for (const auto& o : value.overrides) sets.push_back(o);
    }
    try {
      c.pipeline = load_pipeline(base.file, sets, extra_plugin_paths);
      c.pipeline.sweep.clear();
      c.pipeline.output_file = base.output_file;
      cases.push_back(std::move(c));
    } catch (const PipelineError& e) {
      for (const auto& m : e.messages()) errors.push_back("sweep case " + std::to_string(cases.size() + errors.size()) +
                                                          " (" + c.label + "): " + m);
    }
    std::size_t a = base.sweep.size();
    while (a-- > 0) {
      if (++index[a] < base.sweep[a].values.size()) break;
      index[a] = 0;
    }
    if (a == static_cast<std::size_t>(-1)) break;
  }
  if (!errors.empty()) throw PipelineError(errors);
  return cases;
}

namespace {

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}
// Standard error of the mean of v (sample standard deviation / sqrt(n)).
double stderr_of(const std::vector<double>& v) {
  const double m = mean_of(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
}

}  // namespace

std::vector<DiagnosticOutput> average_realizations(const std::vector<std::vector<DiagnosticOutput>>& runs,
                                                   std::vector<std::string>* summary) {
  if (runs.size() == 1) return runs[0];
  const std::size_t K = runs.size();
  std::vector<DiagnosticOutput> avg;
  for (std::size_t d = 0; d < runs[0].size(); ++d) {
    const DiagnosticOutput& first = runs[0][d];
    DiagnosticOutput out(first.group(), summary);
    out.attributes = first.attributes;
    out.attributes["realizations"] = std::to_string(K);
    std::size_t records = first.time.size();
    for (const auto& r : runs) records = std::min(records, r[d].time.size());
    std::vector<double> values(K);
    auto combine = [&](auto get) {  // mean and standard error over realizations
      for (std::size_t r = 0; r < K; ++r) values[r] = get(runs[r][d]);
      return std::pair{mean_of(values), stderr_of(values)};
    };
    for (std::size_t k = 0; k < records; ++k) {
      out.time.push_back(combine([&](const DiagnosticOutput& o) { return o.time[k]; }).first);
      out.collisions_per_particle.push_back(combine([&](const DiagnosticOutput& o) { return o.collisions_per_particle[k]; }).first);
    }
    for (std::size_t c = 0; c < first.columns.size(); ++c) {
      DiagnosticOutput::Column mean{first.columns[c].name, first.columns[c].unit, first.columns[c].doc, {}};
      DiagnosticOutput::Column se{first.columns[c].name + "_stderr", first.columns[c].unit,
                                  "standard error over realizations of " + first.columns[c].name, {}};
      for (std::size_t k = 0; k < records; ++k) {
        auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.columns[c].values[k]; });
        mean.values.push_back(m);
        se.values.push_back(e);
      }
      out.columns.push_back(std::move(mean));
      out.columns.push_back(std::move(se));
    }
    for (std::size_t s = 0; s < first.scalars.size(); ++s) {
      auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.scalars[s].value; });
      out.scalars.push_back({first.scalars[s].name, first.scalars[s].unit, first.scalars[s].doc, m});
      out.scalars.push_back({first.scalars[s].name + "_stderr", first.scalars[s].unit,
                             "standard error over realizations of " + first.scalars[s].name, e});
    }
    for (std::size_t a = 0; a < first.arrays.size(); ++a) {
      DiagnosticOutput::Array mean = first.arrays[a], se = first.arrays[a];
      se.name += "_stderr";
      se.doc = "standard error over realizations of " + first.arrays[a].name;
      for (std::size_t i = 0; i < mean.data.size(); ++i) {
        auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.arrays[a].data[i]; });
        mean.data[i] = m;
        se.data[i] = e;
      }
      out.arrays.push_back(std::move(mean));
      out.arrays.push_back(std::move(se));
    }
    for (std::size_t h = 0; h < first.histograms.size(); ++h) {
      DiagnosticOutput::Histogram mean = first.histograms[h], se = first.histograms[h];
      se.name += "_stderr";
      se.doc = "standard error over realizations of " + first.histograms[h].name;
      for (std::size_t i = 0; i < mean.values.size(); ++i) {
        auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.histograms[h].values[i]; });
        mean.values[i] = m;
        se.values[i] = e;
      }
      out.histograms.push_back(std::move(mean));
      out.histograms.push_back(std::move(se));
    }
    avg.push_back(std::move(out));
  }
  return avg;
}

void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t) {
  if (!after_s && !after_t) return;
  for (auto& d : diagnostics) {
    const std::size_t n = d.time.size();
    const std::size_t columns = d.columns.size();
    for (std::size_t c = 0; c < columns; ++c) {
      const auto& col = d.columns[c];
      if (col.name.size() > 7 && col.name.compare(col.name.size() - 7, 7, "_stderr") == 0) continue;
      BatchMeans bm;
      for (std::size_t k = 0; k < n; ++k) {
        const bool in = after_s ? d.collisions_per_particle[k] >= *after_s : d.time[k] >= *after_t;
        if (in && std::isfinite(col.values[k])) bm.add(col.values[k]);
      }
      const std::string window = after_s ? "s >= " + std::to_string(*after_s) : "t/tau0 >= " + std::to_string(*after_t);
      d.scalars.push_back({col.name + ".steady_mean", col.unit,
                           "time average of " + col.name + " over the records with " + window + " (" +
                               std::to_string(bm.count()) + " records)",
                           bm.mean()});
      d.scalars.push_back({col.name + ".steady_stderr", col.unit,
                           "batch-means standard error of " + col.name + ".steady_mean (NaN: too few records)",
                           bm.standard_error()});
    }
  }
}

void describe_provenance(const Pipeline& p, StudyOutput& out) {
  out.root_attributes["gdsmc_version"] = version_string;
  out.root_attributes["sdk_abi"] = std::to_string(sdk_abi_major) + "." + std::to_string(sdk_abi_minor);
  out.root_attributes["pipeline"] = p.resolved_text;
  out.root_attributes["pipeline_source"] = p.source_text;
  out.root_attributes["pipeline_file"] = p.file.string();
  std::string sets;
  for (const auto& o : p.overrides) sets += (sets.empty() ? "" : "\n") + o;
  out.root_attributes["overrides"] = sets;
  out.root_attributes["units"] =
      "reduced units: m = 1, k_B = 1, lengths in sigma; time datasets in tau0 = lambda0 / sqrt(2 T0 / m), "
      "lambda0 = 1 / (sqrt(2) pi n sigma^2); each dataset's 'unit' attribute names its unit";
  out.root_numbers["seed"] = static_cast<double>(p.seed);
  out.root_numbers["realizations"] = p.realizations;
}

StudyResult run_study(const std::vector<StudyCase>& cases, const std::function<void(const StudyProgress&)>& report,
                      double report_interval, const std::atomic<bool>* interrupt) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  StudyResult result;
  describe_provenance(cases.front().pipeline, result.output);
  std::size_t total_runs = 0;
  for (const auto& c : cases) total_runs += c.pipeline.realizations;
  std::size_t run_index = 0;
  const bool sweep = cases.size() > 1 || !cases.front().label.empty();

  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    const StudyCase& sc = cases[ci];
    const Pipeline& p = sc.pipeline;
    std::vector<std::vector<DiagnosticOutput>> runs;
    CaseOutput case_out;
    std::vector<std::string> case_summary;
    for (std::uint32_t r = 0; r < p.realizations; ++r, ++run_index) {
      Engine engine(p, r);
      std::string label = sc.label;
      if (p.realizations > 1) label += (label.empty() ? "" : ", ") + std::string("realization ") + std::to_string(r);
      std::function<void(const Progress&)> inner;
      if (report) {
        inner = [&, label](const Progress& pr) {
          StudyProgress sp;
          sp.run = run_index;
          sp.runs = total_runs;
          sp.label = label;
          sp.progress = pr;
          sp.fraction = (static_cast<double>(run_index) + pr.fraction) / static_cast<double>(total_runs);
          const double elapsed = std::chrono::duration<double>(clock::now() - start).count();
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
    add_steady_averages(case_out.diagnostics, p.average_after_collisions_per_particle, p.average_after_time_tau0);
    if (sweep) {
      case_out.group = "cases/" + std::to_string(ci);
      case_out.attributes["case"] = sc.label;
      for (const auto& [axis, value] : sc.axis_values) case_out.attributes["sweep." + axis] = value;
      result.summary.push_back("case " + std::to_string(ci) + ": " + sc.label);
      for (const auto& line : case_summary) result.summary.push_back("  " + line);
    } else {
      for (const auto& line : case_summary) result.summary.push_back(line);
    }
    if (p.realizations > 1) {
      for (const auto& d : case_out.diagnostics)
        for (std::size_t s = 0; s + 1 < d.scalars.size(); ++s) {
          const auto& a = d.scalars[s];
          const auto& b = d.scalars[s + 1];
          if (b.name != a.name + "_stderr") continue;
          char buf[256];
          std::snprintf(buf, sizeof buf, "%s%s: %s = %.6g +- %.2g (mean over %u realizations)", sweep ? "  " : "",
                        d.group().c_str(), a.name.c_str(), a.value, b.value, p.realizations);
          result.summary.push_back(buf);
        }
    }
    result.output.cases.push_back(std::move(case_out));
  }

  if (sweep) {
    // /summary: the sweep values and every scalar (steady averages included), one row per case.
    auto& table = result.output.summary;
    const auto& first = cases.front();
    for (std::size_t a = 0; a < first.axis_values.size(); ++a) {
      SummaryColumn col{first.axis_values[a].first, "", "sweep axis " + first.axis_values[a].first, {}, {}};
      bool numeric = true;
      std::vector<double> numbers;
      for (const auto& c : cases) {
        const std::string& v = c.axis_values[a].second;
        col.labels.push_back(v);
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        numeric = numeric && end && *end == '\0' && !v.empty();
        numbers.push_back(x);
      }
      if (numeric) {
        col.values = numbers;
        col.labels.clear();
        col.unit = "as given in the sweep";
      }
      table.push_back(std::move(col));
    }
    const auto& d0 = result.output.cases.front().diagnostics;
    for (std::size_t d = 0; d < d0.size(); ++d)
      for (std::size_t s = 0; s < d0[d].scalars.size(); ++s) {
        SummaryColumn col{d0[d].group() + "." + d0[d].scalars[s].name, d0[d].scalars[s].unit, d0[d].scalars[s].doc, {}, {}};
        for (const auto& c : result.output.cases) {
          const auto& scalars = c.diagnostics[d].scalars;
          col.values.push_back(s < scalars.size() ? scalars[s].value : std::nan(""));
        }
        table.push_back(std::move(col));
      }
  }
  result.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  return result;
}

}  // namespace gdsmc::host
