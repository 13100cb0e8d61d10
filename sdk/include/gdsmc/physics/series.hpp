// gdsmc SDK: the usual shape of a time-series diagnostic: declare columns, add one value per
// column at each sample, and at each record append the mean of the samples since the last one.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "gdsmc/output.hpp"
#include "gdsmc/state.hpp"

namespace gdsmc {

class WindowAverage {
 public:
  struct Column {
    std::string name, unit, doc;
  };
  // Declare the columns in the sink (call from Diagnostic::begin).
  void declare(OutputSink& out, const std::vector<Column>& columns) {
    ids_.clear();
    for (const auto& c : columns) ids_.push_back(out.series(c.name, c.unit, c.doc));
    sums_.assign(columns.size(), 0.0);
    samples_ = 0;
  }
  // One sample: values in the order of the declared columns.
  void add(const std::vector<double>& values) {
    for (std::size_t k = 0; k < sums_.size() && k < values.size(); ++k) sums_[k] += values[k];
    ++samples_;
  }
  // Checkpoints: the open window (the columns are declared again by begin()), under `prefix`.
  void save(StateWriter& out, const std::string& prefix = "window") const {
    out.write(prefix + ".sums", sums_);
    out.write(prefix + ".samples", static_cast<std::uint64_t>(samples_));
  }
  void load(StateReader& in, const std::string& prefix = "window") {
    const std::size_t columns = sums_.size();
    in.read(prefix + ".sums", sums_);
    if (sums_.size() != columns)
      throw StateError("checkpoint entry '" + prefix + ".sums': " + std::to_string(sums_.size()) + " columns where " +
                       std::to_string(columns) + " are declared");
    std::uint64_t samples = 0;
    in.read(prefix + ".samples", samples);
    samples_ = static_cast<std::size_t>(samples);
  }
  // Append the window means (NaN for an empty window) and start a new window.
  void commit(OutputSink& out) {
    for (std::size_t k = 0; k < ids_.size(); ++k)
      out.append(ids_[k], samples_ ? sums_[k] / static_cast<double>(samples_) : std::nan(""));
    sums_.assign(sums_.size(), 0.0);
    samples_ = 0;
  }

 private:
  std::vector<std::size_t> ids_;
  std::vector<double> sums_;
  std::size_t samples_ = 0;
};

// The integrated autocorrelation time of n values, in units of their spacing: tau = 1 + 2 sum_t rho(t),
// so that the variance of their mean is Gamma(0) tau / n (Gamma(0) their variance about their own
// mean, divided by n). By Wolff's Gamma method (U. Wolff, Comput. Phys. Commun. 156 (2004) 143):
// autocovariances over their n - t pairs, summed up to the automatic window W (the first W at which
// exp(-W/tau_W) < tau_W / sqrt(W n), tau_W = S / ln((2 tau_s + 1)/(2 tau_s - 1)), tau_s = tau(W)/2 and
// S = 1.5), then corrected for the bias of subtracting the values' own mean: times 1 + (2W + 1)/n.
// Over independent seeds of AR(1) series its errors of the mean hold to about 10 % in variance from
// 10 autocorrelation times up, and are about 1.3 times too small at 5 (tests/sdk/physics_toolkit_test.cpp);
// the old Sokal window without the correction was 2.1 and 3.2 times too small there. 1 for fewer
// than 2 values or no spread; never below 1/n.
inline double integrated_autocorrelation_time(const double* v, std::size_t n) {
  if (n < 2) return 1.0;
  double m = 0;
  for (std::size_t i = 0; i < n; ++i) m += v[i];
  m /= static_cast<double>(n);
  const auto autocovariance = [&](std::size_t t) {
    double c = 0;
    for (std::size_t i = 0; i + t < n; ++i) c += (v[i] - m) * (v[i + t] - m);
    return c / static_cast<double>(n - t);
  };
  const double c0 = autocovariance(0);
  if (!(c0 > 0)) return 1.0;
  constexpr double S = 1.5;
  const double dn = static_cast<double>(n);
  double sum = c0;  // Gamma(0) + 2 sum_{t <= W} Gamma(t)
  std::size_t W = 0;
  for (std::size_t t = 1; t < n / 2; ++t) {
    sum += 2 * autocovariance(t);
    W = t;
    const double tau_s = 0.5 * sum / c0;  // Sokal's tau_int, 1/2 for independent values
    if (tau_s <= 0.5) break;              // no correlation left to sum
    const double tau_w = S / std::log((2 * tau_s + 1) / (2 * tau_s - 1));
    if (std::exp(-static_cast<double>(t) / tau_w) < tau_w / std::sqrt(static_cast<double>(t) * dn)) break;
  }
  const double tau = sum / c0 * (1 + static_cast<double>(2 * W + 1) / dn);
  return std::max(tau, 1.0 / dn);
}

// Mean and standard error of a correlated sequence of samples by batch means: at most
// max_batches batches, merged pairwise (batch length doubled) when full, so memory is fixed and
// nothing is allocated while sampling. The error is that of the complete batches.
class BatchMeans {
 public:
  static constexpr std::size_t max_batches = 64;
  void add(double x) {
    sum_ += x;
    ++count_;
    current_ += x;
    if (++in_current_ == batch_length_) {
      batch_[batches_++] = current_ / static_cast<double>(batch_length_);
      current_ = 0;
      in_current_ = 0;
      if (batches_ == max_batches) {
        for (std::size_t k = 0; k < max_batches / 2; ++k) batch_[k] = 0.5 * (batch_[2 * k] + batch_[2 * k + 1]);
        batches_ = max_batches / 2;
        batch_length_ *= 2;
      }
    }
  }
  std::size_t count() const { return count_; }
  std::size_t batches() const { return batches_; }
  // Checkpoints: every batch and the open one, under `prefix`.
  void save(StateWriter& out, const std::string& prefix) const {
    out.write(prefix + ".batch", batch_, max_batches);
    const std::uint64_t counts[4] = {batches_, batch_length_, in_current_, count_};
    out.write(prefix + ".counts", counts, 4);
    const double sums[2] = {current_, sum_};
    out.write(prefix + ".sums", sums, 2);
  }
  void load(StateReader& in, const std::string& prefix) {
    in.read(prefix + ".batch", batch_, max_batches);
    std::uint64_t counts[4];
    in.read(prefix + ".counts", counts, 4);
    if (counts[0] > max_batches || counts[1] == 0 || counts[2] >= counts[1])
      throw StateError("checkpoint entry '" + prefix + ".counts': not a batch-means state");
    batches_ = counts[0];
    batch_length_ = counts[1];
    in_current_ = counts[2];
    count_ = counts[3];
    double sums[2];
    in.read(prefix + ".sums", sums, 2);
    current_ = sums[0];
    sum_ = sums[1];
  }
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : std::nan(""); }
  // Standard error of the mean: the variance of the batch means times their integrated
  // autocorrelation time over their number (integrated_autocorrelation_time above: batches shorter
  // than the correlation time of the samples are correlated, and its bias correction stands for
  // the batches' own mean). Over independent seeds of AR(1) series the variance of the means is
  // 1.0-1.1 times the mean squared error from 10 autocorrelation times up and 1.3 times at 5
  // (tests/sdk/physics_toolkit_test.cpp): below about 10 autocorrelation times, realizations give the
  // honest error. NaN with fewer than 4 batches.
  double standard_error() const {
    if (batches_ < 4) return std::nan("");
    double m = 0;
    for (std::size_t k = 0; k < batches_; ++k) m += batch_[k];
    m /= static_cast<double>(batches_);
    double v = 0;
    for (std::size_t k = 0; k < batches_; ++k) v += (batch_[k] - m) * (batch_[k] - m);
    v /= static_cast<double>(batches_);
    return std::sqrt(v * batch_autocorrelation_time() / static_cast<double>(batches_));
  }
  // The integrated autocorrelation time of the complete batches' means, in batches (1 when they are
  // independent).
  double batch_autocorrelation_time() const { return integrated_autocorrelation_time(batch_, batches_); }

 private:
  double batch_[max_batches] = {};
  std::size_t batches_ = 0, batch_length_ = 1, in_current_ = 0, count_ = 0;
  double current_ = 0, sum_ = 0;
};

}  // namespace gdsmc
