// Statistics over the runs of a case: averages over realizations and steady-state averages.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "output/diagnostic_output.hpp"

namespace gdsmc::host {

// Average diagnostics over realizations, record by record (truncated to the shortest run):
// every series, profile (element by element), scalar and array gets its mean, and with more than
// one realization a "<name>_stderr" companion (standard error of the mean over realizations).
std::vector<DiagnosticOutput> average_realizations(const std::vector<std::vector<DiagnosticOutput>>& runs,
                                                   std::vector<std::string>* summary);

// Steady-state averages: for every series, the mean over the records with s >= after_s (or
// t/tau0 >= after_t) and its batch-means standard error, as scalars "<series>.steady_mean" and
// "<series>.steady_stderr"; for every profile, the same per bin as arrays of shape (bins)
// "<profile>.steady_mean" and "<profile>.steady_stderr".
void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t);

}  // namespace gdsmc::host
