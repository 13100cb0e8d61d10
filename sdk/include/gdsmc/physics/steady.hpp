// gdsmc SDK, physics toolkit: the steady-state test. One scalar signal x(t) (for example the
// kinetic energy per particle, 004 Appendix Eq. A1) is averaged over consecutive windows of a fixed
// length in time; a window that ends agrees with the one before when
//   |m_k - m_{k-1}| <= max(tolerance |m_k|, sigmas sqrt(s_k^2 + s_{k-1}^2)),
// m_k the window's mean and s_k its standard error by batch means: the window is cut into
// `pieces` (8) equal pieces in time and s_k^2 = var(piece means) / pieces. The first clause is the
// constancy of E(t) that paper 004 monitors (Appendix) as a relative tolerance; the second accepts a change that noise alone explains, so a
// noisy but stationary signal is found steady even where the relative tolerance is below its
// noise (sigmas = 0: the relative test alone). Fixed memory; nothing is allocated while sampling.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "gdsmc/state.hpp"

namespace gdsmc {

class SteadyTest {
 public:
  static constexpr std::size_t pieces = 8;

  // window: the length of a window (same unit as the times passed to add()); tolerance: relative;
  // sigmas: standard errors of the difference that still count as agreement.
  void configure(double window, double tolerance, double sigmas) {
    window_ = window;
    tolerance_ = tolerance;
    sigmas_ = sigmas;
  }
  // Forget every window; the first one starts at `time`.
  void start(double time) {
    piece_sum_.fill(0.0);
    piece_samples_.fill(0);
    window_start_ = time;
    previous_mean_ = std::nan("");
    previous_error_ = 0;
  }
  // One sample x at `time` (non-decreasing). Returns true when this sample closes a window that
  // agrees with the previous one (the next window then starts at `time`); false otherwise.
  bool add(double time, double x) {
    const double into = (time - window_start_) / window_;
    const std::size_t piece = std::min(pieces - 1, static_cast<std::size_t>(std::max(0.0, into) * pieces));
    piece_sum_[piece] += x;
    ++piece_samples_[piece];
    if (into < 1.0 - 1e-12) return false;
    double sum = 0, count = 0, sum_means = 0, sum_means2 = 0;
    std::size_t used = 0;
    for (std::size_t k = 0; k < pieces; ++k) {
      sum += piece_sum_[k];
      count += static_cast<double>(piece_samples_[k]);
      if (piece_samples_[k] == 0) continue;
      const double m = piece_sum_[k] / static_cast<double>(piece_samples_[k]);
      sum_means += m;
      sum_means2 += m * m;
      ++used;
    }
    const double mean = sum / count;
    const double np = static_cast<double>(used);
    const double error = used > 1 ? std::sqrt(std::max(0.0, (sum_means2 - sum_means * sum_means / np) / (np - 1) / np)) : 0.0;
    const double change = std::fabs(mean - previous_mean_);
    const bool settled = std::isfinite(previous_mean_) &&
                         (change <= tolerance_ * std::fabs(mean) ||
                          change <= sigmas_ * std::sqrt(error * error + previous_error_ * previous_error_));
    previous_mean_ = mean;
    previous_error_ = error;
    piece_sum_.fill(0.0);
    piece_samples_.fill(0);
    window_start_ = time;
    return settled;
  }
  // The mean and standard error of the last window that ended (NaN and 0 before the first).
  double last_mean() const { return previous_mean_; }
  double last_error() const { return previous_error_; }

  // Checkpoints: the open window and the last closed one, under `prefix`.
  void save(StateWriter& out, const std::string& prefix) const {
    const double values[3] = {window_start_, previous_mean_, previous_error_};
    out.write(prefix + ".window", values, 3);
    out.write(prefix + ".piece_sum", piece_sum_.data(), pieces);
    std::uint64_t samples[pieces];
    std::copy(piece_samples_.begin(), piece_samples_.end(), samples);
    out.write(prefix + ".piece_samples", samples, pieces);
  }
  void load(StateReader& in, const std::string& prefix) {
    double values[3];
    in.read(prefix + ".window", values, 3);
    window_start_ = values[0];
    previous_mean_ = values[1];
    previous_error_ = values[2];
    in.read(prefix + ".piece_sum", piece_sum_.data(), pieces);
    std::uint64_t samples[pieces];
    in.read(prefix + ".piece_samples", samples, pieces);
    for (std::size_t k = 0; k < pieces; ++k) piece_samples_[k] = static_cast<std::size_t>(samples[k]);
  }

 private:
  double window_ = 1, tolerance_ = 0, sigmas_ = 0;
  std::array<double, pieces> piece_sum_{};
  std::array<std::size_t, pieces> piece_samples_{};
  double window_start_ = 0, previous_mean_ = std::nan(""), previous_error_ = 0;
};

}  // namespace gdsmc
