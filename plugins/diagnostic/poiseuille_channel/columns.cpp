// poiseuille_channel: the columns written at the end of a run (columns.hpp), with the error
// descriptions that say why an error is NaN.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "columns.hpp"

namespace poiseuille {

void write_columns(gdsmc::OutputSink& out, const gdsmc::SystemInfo& sys, const Result& whole, const Result& err,
                   std::size_t used, std::size_t reach_bins) {
  const std::size_t bins = sys.bins;
  // A NaN error says why (issue 29: no NaN error without its reason and the remedy).
  const auto error_doc = [&](const std::string& what, double value, double error) {
    std::string doc = "jackknife error over the batches of " + what + " (times the square root of the delete-one values' integrated autocorrelation time)";
    if (std::isfinite(error)) return doc;
    if (used < 2)
      return doc + "; NaN: the steady window holds " + std::to_string(used) +
             " batch(es) (E(t) never settled, or the run stopped right after it did): run longer (run.stop) or "
             "lower min_time; with run.realizations >= 2 the host's _stderr is the realizations' scatter";
    if (!std::isfinite(value)) return doc + "; NaN: the value itself is undefined in this run (see its description)";
    return doc + "; NaN: the value is undefined in some batch's complement (a gradient or fit without enough "
                 "finite bins there): run longer so that every batch fills every bin";
  };
  if (reach_bins >= 3) {
    out.scalar("wall_fit_reach", static_cast<double>(reach_bins) / static_cast<double>(bins), "W",
               "distance from the wall spanned by the bins of the quadratic wall fit (their outer edge)");
    out.scalar("wall_fit_bins_used", static_cast<double>(reach_bins), "1", "bins next to each wall in the quadratic wall fit");
  }
  for (std::size_t s = 0; s < kScalar; ++s) {
    if (s >= kFirstWallFit && reach_bins < 3) continue;  // wall_fit_reach off
    out.scalar(kScalars[s].name, whole.scalars[s], kScalars[s].unit, kScalars[s].doc);
    out.scalar(std::string(kScalars[s].name) + "_error", err.scalars[s], kScalars[s].unit,
               s == centre_peak_width && std::isfinite(err.scalars[s])
                   ? "the resolution of the peak's two edges, a bin width / sqrt(6) (the width is fixed by the whole window)"
                   : error_doc(kScalars[s].name, whole.scalars[s], err.scalars[s]));
  }
  double chi2 = 0;
  std::size_t terms = 0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double res = whole.profiles[pPxyResidual * bins + b], e = err.profiles[pPxyResidual * bins + b];
    if (std::isfinite(res) && e > 0) {
      chi2 += res * res / (e * e);
      ++terms;
    }
  }
  out.scalar("momentum_balance_chi2", terms ? chi2 / static_cast<double>(terms) : std::nan(""), "1",
             "mean over bins of (P_xy_residual / its jackknife error)^2: about 1 when Eq. 33 holds");
  std::vector<double> y(bins);
  for (std::size_t b = 0; b < bins; ++b) y[b] = sys.bin_centre(b) / sys.box[1];
  out.array("y", y, {bins}, "W", "bin centres y / W of the steady profiles");
  for (std::size_t k = 0; k < kProfile; ++k) {
    std::vector<double> v(whole.profiles.begin() + static_cast<std::ptrdiff_t>(k * bins),
                          whole.profiles.begin() + static_cast<std::ptrdiff_t>((k + 1) * bins));
    std::vector<double> e(err.profiles.begin() + static_cast<std::ptrdiff_t>(k * bins),
                          err.profiles.begin() + static_cast<std::ptrdiff_t>((k + 1) * bins));
    out.array(std::string("steady_") + kProfiles[k].name, v, {bins}, kProfiles[k].unit,
              std::string("steady ") + kProfiles[k].doc);
    const bool any_nan = std::any_of(e.begin(), e.end(), [](double x) { return !std::isfinite(x); });
    const bool value_nan = std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); });
    out.array(std::string("steady_") + kProfiles[k].name + "_error", e, {bins}, kProfiles[k].unit,
              any_nan ? error_doc("steady_" + std::string(kProfiles[k].name) + " (some bins)",
                                  value_nan ? std::nan("") : 0.0, std::nan(""))
                      : std::string("jackknife error of steady_") + kProfiles[k].name);
    out.axis(std::string("steady_") + kProfiles[k].name, "y");
    out.axis(std::string("steady_") + kProfiles[k].name + "_error", "y");
  }
}

}  // namespace poiseuille
