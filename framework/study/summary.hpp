// What a study reports: lines for stdout and the /summary table of a sweep.
#pragma once
#include <string>
#include <vector>

#include "output/records.hpp"
#include "study/cases.hpp"

namespace gdsmc::host {

// "group: name = mean +- stderr (mean over K realizations)" for every scalar with a "_stderr" companion.
void add_realization_lines(const std::vector<DiagnosticOutput>& diagnostics, std::uint32_t realizations, bool sweep,
                           std::vector<std::string>& lines);

// /summary: the sweep values and every scalar (steady averages included), one row per case.
std::vector<SummaryColumn> summary_table(const std::vector<StudyCase>& cases, const std::vector<CaseOutput>& outputs);

}  // namespace gdsmc::host
