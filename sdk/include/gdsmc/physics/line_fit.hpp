// gdsmc SDK, physics toolkit: the least-squares straight line y = a + b x through n points, with the
// variances of a and b estimated from the scatter of the points about the line (the residual
// variance s^2 = sum r^2 / (n - 2) times the diagonal of (X^T X)^-1, as numpy.polyfit(cov=True)):
//   b = Sxy / Sxx,  a = ybar - b xbar,  var b = s^2 / Sxx,  var a = s^2 (1/n + xbar^2 / Sxx).
// Treats the points as independent: correlated points (neighbouring bins of one run) scatter less
// than their errors, and the variances are then lower bounds.
#pragma once
#include <cmath>
#include <cstddef>

namespace gdsmc {

struct LineFit {
  double intercept = std::nan(""), slope = std::nan("");
  // NaN with fewer than 3 points (no scatter to estimate them from).
  double intercept_variance = std::nan(""), slope_variance = std::nan("");
};

// The line through (x[i], y[i]), i < n; NaN throughout with fewer than 2 points, equal x, or a
// non-finite value.
inline LineFit fit_line(const double* x, const double* y, std::size_t n) {
  LineFit f;
  if (n < 2) return f;
  double xbar = 0, ybar = 0;
  for (std::size_t i = 0; i < n; ++i) xbar += x[i], ybar += y[i];
  xbar /= static_cast<double>(n);
  ybar /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) sxx += (x[i] - xbar) * (x[i] - xbar), sxy += (x[i] - xbar) * (y[i] - ybar);
  if (!(sxx > 0) || !std::isfinite(sxy)) return f;
  f.slope = sxy / sxx;
  f.intercept = ybar - f.slope * xbar;
  if (n < 3) return f;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - f.intercept - f.slope * x[i];
    rss += r * r;
  }
  const double s2 = rss / static_cast<double>(n - 2);
  f.slope_variance = s2 / sxx;
  f.intercept_variance = s2 * (1.0 / static_cast<double>(n) + xbar * xbar / sxx);
  return f;
}

}  // namespace gdsmc
