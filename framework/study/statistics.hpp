// Statistics over the runs of a case: averages over realizations and steady-state averages.
#pragma once
#include <cmath>
#include <cstddef>
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
// t/tau0 >= after_t) and its standard error, as scalars "<series>.steady_mean" and
// "<series>.steady_stderr"; for every profile, the same per bin as arrays of shape (bins)
// "<profile>.steady_mean" and "<profile>.steady_stderr".
// The error: with two or more `runs` (the realizations `diagnostics` averages, in the same order),
// sd / sqrt(K) of the realizations' own time averages over the same records; otherwise batch
// means with batches of at least kBatchTaus integrated autocorrelation times of the series, NaN
// (and said in the description) when the window holds fewer than kMinBatches of them.
void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t, const std::vector<std::vector<DiagnosticOutput>>& runs = {});

// A warning when no record of `diagnostics` lies in the steady window (every steady average is
// then NaN): the window and the last record; "" otherwise.
std::string steady_window_missed(const std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                                 std::optional<double> after_t);

// Warnings for errors that came out NaN although the window holds records, at most one line for the
// host's <series>.steady_stderr of series the diagnostic declares stationary (attribute
// `stationary`; profiles with a NaN bin included) and one for the plugins' own
// *_standard_error / *_error scalars: how many, in which diagnostics, why, and what to do (issue 29:
// no NaN error without a printed reason and the remedy).
std::vector<std::string> nan_error_warnings(const std::vector<DiagnosticOutput>& diagnostics);

// The seed check of an error: K realizations' values x_r with their own errors e_r give
//   chi2/dof = sum_r (x_r - xbar)^2 / <e^2> / (K - 1)       (weighted = false: xbar the plain mean,
//                                                            <e^2> the mean of the e_r^2), or
//   chi2/dof = sum_r (x_r - xbar_w)^2 / e_r^2 / (K - 1)    (weighted = true: xbar_w weighted by 1/e_r^2).
// When the errors hold, the first follows chi2 with K - 1 dof over K - 1 (mean 1): it tests the
// calibration of the errors. The second also carries the noise of each e_r: with nu degrees of
// freedom per error its mean is nu/(nu - 2), above 1 for honest but imprecise errors. NaN for fewer
// than 2 values or an error that is not finite and positive.
double seed_chi2_per_dof(const std::vector<double>& values, const std::vector<double>& errors, bool weighted = false);
// The seed check of every error of diagnostic d over K = runs.size() >= 2 realizations, into `out`
// (the realization average): for each scalar error and its value, <error>_seed_chi2_dof (and
// _weighted) over the realizations whose error is finite and positive, the attribute
// seed_chi2_band_95 and a summary text attribute naming the errors outside the band. `plugin`:
// the errors diagnostics report themselves (X_error or X_standard_error beside X or X_mean; text
// in "seed_check", written by average_realizations). `steady`: the host's steady errors of one
// realization (X.steady_stderr beside X.steady_mean, for the series the diagnostic declares
// stationary; `runs` must hold each realization's own steady averages; text in "seed_check_steady").
enum class SeedErrors { plugin, steady };
void add_seed_checks(const std::vector<std::vector<DiagnosticOutput>>& runs, std::size_t d, DiagnosticOutput& out,
                     SeedErrors kind);
// The central 95 % band of chi2/dof for K realizations (K - 1 dof): the 2.5 % and 97.5 % quantiles
// of chi2 with K - 1 dof over K - 1 (K = 20: [0.469, 1.729]).
struct SeedBand {
  double low = std::nan(""), high = std::nan("");
};
SeedBand seed_chi2_band(std::size_t realizations);

inline constexpr double kBatchTaus = 5.0;
inline constexpr std::size_t kMinBatches = 4, kMaxBatches = 64;

// The integrated autocorrelation time of a series, in records: 1 + 2 sum_t rho(t) by Wolff's Gamma
// method with its bias correction (the SDK's gdsmc::integrated_autocorrelation_time).
double integrated_autocorrelation_time(const std::vector<double>& v);

// Batches for a batch-means error: length >= kBatchTaus tau_int (longer when that would give more
// than kMaxBatches), as many whole batches as fit.
struct BatchSpec {
  double tau = 1;
  std::size_t length = 1, batches = 0;
};
BatchSpec choose_batches(const std::vector<double>& v);

}  // namespace gdsmc::host
