#include "study/summary.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gdsmc/physics/units.hpp>

namespace gdsmc::host {

void add_realization_lines(const std::vector<DiagnosticOutput>& diagnostics, std::uint32_t realizations, bool sweep,
                           std::vector<std::string>& lines) {
  for (const auto& d : diagnostics)
    for (std::size_t s = 0; s + 1 < d.scalars.size(); ++s) {
      const auto& a = d.scalars[s];
      const auto& b = d.scalars[s + 1];
      if (b.name != a.name + "_stderr") continue;
      char buf[256];
      std::snprintf(buf, sizeof buf, "%s%s: %s = %.6g +- %.2g (mean over %u realizations)", sweep ? "  " : "",
                    d.group().c_str(), a.name.c_str(), a.value, b.value, realizations);
      lines.push_back(buf);
    }
}

namespace {

// A sweep axis as a column: numeric when every value reads as a number, else text.
SummaryColumn axis_column(const std::vector<StudyCase>& cases, std::size_t a) {
  const auto& first = cases.front();
  SummaryColumn col{first.axis_values[a].first, "", "sweep axis " + first.axis_values[a].first, {}, {}, {}};
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
    col.unit = units::as_swept;
  }
  return col;
}

}  // namespace

std::vector<SummaryColumn> summary_table(const std::vector<StudyCase>& cases, const std::vector<CaseOutput>& outputs) {
  std::vector<SummaryColumn> table;
  for (std::size_t a = 0; a < cases.front().axis_values.size(); ++a) table.push_back(axis_column(cases, a));
  const auto& d0 = outputs.front().diagnostics;
  for (std::size_t d = 0; d < d0.size(); ++d)
    for (std::size_t s = 0; s < d0[d].scalars.size(); ++s) {
      SummaryColumn col{d0[d].group() + "." + d0[d].scalars[s].name, d0[d].scalars[s].unit, d0[d].scalars[s].doc, {}, {}, {}};
      if (const auto tag = d0[d].theory_tags.find(d0[d].scalars[s].name); tag != d0[d].theory_tags.end()) {
        col.theory.equation = tag->second.equation;
        for (const std::string& m : split_names(tag->second.measured))
          col.theory.measured += (col.theory.measured.empty() ? "" : ",") + d0[d].group() + "." + m;
      }
      for (const auto& c : outputs) {
        const auto& scalars = c.diagnostics[d].scalars;
        col.values.push_back(s < scalars.size() ? scalars[s].value : std::nan(""));
      }
      table.push_back(std::move(col));
    }
  return table;
}

}  // namespace gdsmc::host
