// Test support: compensated sums, the mean and error of independent values, and the HCS theory
// the physics tests compare with.
#pragma once
#include <cmath>
#include <vector>

namespace gdsmc::test {

// Sum of doubles with Neumaier's compensation: the error is about one rounding of the result
// plus N eps^2 sum|x|, negligible next to the round-off the tests bound.
class ExactishSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::fabs(sum_) >= std::fabs(x)) c_ += (sum_ - t) + x;
    else c_ += (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + c_; }

 private:
  double sum_ = 0, c_ = 0;
};

// Mean and standard error of independent values.
struct MeanError {
  double mean = 0, standard_error = 0;
};
inline MeanError mean_error(const std::vector<double>& x) {
  MeanError r;
  const double n = static_cast<double>(x.size());
  for (double v : x) r.mean += v;
  r.mean /= n;
  double var = 0;
  for (double v : x) var += (v - r.mean) * (v - r.mean);
  var /= (n - 1);
  r.standard_error = std::sqrt(var / n);
  return r;
}

// a2 of the HCS in the first Sonine approximation, d = 3 (paper 001, Eq. 2.16).
inline double sonine_a2(double alpha) {
  constexpr double d = 3.0;
  return 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha) /
         (25.0 + 24.0 * d - alpha * (57.0 - 8.0 * d) - 2.0 * (1.0 - alpha) * alpha * alpha);
}
// zeta(T0) tau0 of the HCS (paper 001, Eqs. 2.14-2.15 with d = 3; paper 000, Eq. 2.16).
inline double haff_zeta_tau0(double alpha) {
  return 2.0 * (1.0 - alpha * alpha) * (1.0 + 3.0 * sonine_a2(alpha) / 16.0) / (3.0 * std::sqrt(M_PI));
}

}  // namespace gdsmc::test
