// gdsmc SDK, physics toolkit: the delete-one jackknife error of any estimator computed from
// batches of consecutive samples (a profile fit, a ratio, a slip length: values that are not a
// plain mean, for which BatchMeans of series.hpp is the estimator). With B batches and theta_k the
// estimate from all batches but k, in batch order,
//   error^2 = (B - 1)/B sum_k (theta_k - mean_k theta_k)^2 * tau,
// tau the integrated autocorrelation time of the theta_k in batch order (series.hpp: consecutive
// batches of a short window are correlated); for a mean it is BatchMeans' error. Fixed memory: the
// caller holds the delete-one values.
#pragma once
#include <cmath>
#include <cstddef>

#include "gdsmc/physics/series.hpp"

namespace gdsmc {

// The jackknife error from the B delete-one values `delete_one` (batch order). NaN when a value is
// not finite (the estimate is undefined in some batch's complement). Needs B >= 2: one value gives
// 0, which is no error estimate.
inline double jackknife_error(const double* delete_one, std::size_t B) {
  const double b = static_cast<double>(B);
  double mean = 0;
  for (std::size_t k = 0; k < B; ++k) mean += delete_one[k];
  mean /= b;
  double ss = 0;
  for (std::size_t k = 0; k < B; ++k) ss += (delete_one[k] - mean) * (delete_one[k] - mean);
  const double tau = std::isfinite(ss) ? integrated_autocorrelation_time(delete_one, B) : 1.0;
  return std::sqrt((b - 1.0) / b * ss * tau);
}

}  // namespace gdsmc
