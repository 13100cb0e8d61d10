// gdsmc SDK: the usual shape of a time-series diagnostic: declare columns, add one value per
// column at each sample, and at each record append the mean of the samples since the last one.
#pragma once
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

// The integrated autocorrelation time of n values, in units of their spacing: 1 + 2 sum_t rho(t),
// summed up to Sokal's automatic window (the smallest W >= 5 tau(W)); at least 1 (1 for
// uncorrelated values, and for fewer than 2 values or no spread). With a window of n values it is
// biased low by about tau/n and uncertain by about sqrt(2(2W + 1)/n) relative: trust it when the
// values span 20 autocorrelation times or more.
inline double integrated_autocorrelation_time(const double* v, std::size_t n) {
  if (n < 2) return 1.0;
  double m = 0;
  for (std::size_t i = 0; i < n; ++i) m += v[i];
  m /= static_cast<double>(n);
  double c0 = 0;
  for (std::size_t i = 0; i < n; ++i) c0 += (v[i] - m) * (v[i] - m);
  c0 /= static_cast<double>(n);
  if (!(c0 > 0)) return 1.0;
  double tau = 1;
  for (std::size_t t = 1; t < n; ++t) {
    double ct = 0;
    for (std::size_t i = 0; i + t < n; ++i) ct += (v[i] - m) * (v[i + t] - m);
    ct /= static_cast<double>(n);
    tau += 2 * ct / c0;
    if (static_cast<double>(t) >= 5.0 * tau) break;
  }
  return tau > 1.0 ? tau : 1.0;
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
  // Standard error of the mean from the spread of the batch means, times the square root of their
  // integrated autocorrelation time (consecutive batches shorter than the correlation time of the
  // samples are correlated; taken as independent, AR(1) series spanning 20 autocorrelation times
  // scattered 4 times the variance their errors claimed, 1.7 times with this correction,
  // tests/physics_toolkit_test.cpp); NaN with fewer than 4 batches. So still low when the samples
  // span fewer than about 40 autocorrelation times: realizations give the honest error there.
  double standard_error() const {
    if (batches_ < 4) return std::nan("");
    double m = 0;
    for (std::size_t k = 0; k < batches_; ++k) m += batch_[k];
    m /= static_cast<double>(batches_);
    double v = 0;
    for (std::size_t k = 0; k < batches_; ++k) v += (batch_[k] - m) * (batch_[k] - m);
    v /= static_cast<double>(batches_ - 1);
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
