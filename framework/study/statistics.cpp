#include "study/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include <gdsmc/series.hpp>

namespace gdsmc::host {

namespace {

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}
// Standard error of the mean of v (sample standard deviation / sqrt(n)).
double stderr_of(const std::vector<double>& v) {
  const double m = mean_of(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
}

// Mean and standard error over realizations of one value of diagnostic d, read by `get`.
class Combiner {
 public:
  Combiner(const std::vector<std::vector<DiagnosticOutput>>& runs, std::size_t d)
      : runs_(runs), d_(d), values_(runs.size()) {}
  template <class Get>
  std::pair<double, double> operator()(Get get) {
    for (std::size_t r = 0; r < runs_.size(); ++r) values_[r] = get(runs_[r][d_]);
    return {mean_of(values_), stderr_of(values_)};
  }

 private:
  const std::vector<std::vector<DiagnosticOutput>>& runs_;
  std::size_t d_;
  std::vector<double> values_;
};

using VectorOf = std::function<const std::vector<double>&(const DiagnosticOutput&)>;

// Element by element: mean (into `mean`) and standard error (into `se`) of the vector `of` reads.
void combine_into(Combiner& combine, const VectorOf& of, std::vector<double>& mean, std::vector<double>& se) {
  for (std::size_t i = 0; i < mean.size(); ++i) {
    auto [m, e] = combine([&](const DiagnosticOutput& o) { return of(o)[i]; });
    mean[i] = m;
    se[i] = e;
  }
}

// The mean item and its "_stderr" companion (an Array, a Histogram or a Profile), appended to
// `into`: the first `size` values (all of them unless given: a profile keeps its common records).
template <class Item>
void combine_item(Combiner& combine, const Item& first, const VectorOf& of, std::vector<double> Item::*values,
                  std::vector<Item>& into, std::size_t size = SIZE_MAX) {
  Item mean = first, se = first;
  if (size != SIZE_MAX) {
    (mean.*values).resize(size);
    (se.*values).resize(size);
  }
  se.name += "_stderr";
  se.doc = "standard error over realizations of " + first.name;
  combine_into(combine, of, mean.*values, se.*values);
  into.push_back(std::move(mean));
  into.push_back(std::move(se));
}

void average_columns(Combiner& combine, const DiagnosticOutput& first, std::size_t records, DiagnosticOutput& out) {
  for (std::size_t k = 0; k < records; ++k) {
    out.time.push_back(combine([&](const DiagnosticOutput& o) { return o.time[k]; }).first);
    out.collisions_per_particle.push_back(combine([&](const DiagnosticOutput& o) { return o.collisions_per_particle[k]; }).first);
  }
  for (std::size_t c = 0; c < first.columns.size(); ++c) {
    DiagnosticOutput::Column mean{first.columns[c].name, first.columns[c].unit, first.columns[c].doc, {}};
    DiagnosticOutput::Column se{first.columns[c].name + "_stderr", first.columns[c].unit,
                                "standard error over realizations of " + first.columns[c].name, {}};
    for (std::size_t k = 0; k < records; ++k) {
      auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.columns[c].values[k]; });
      mean.values.push_back(m);
      se.values.push_back(e);
    }
    out.columns.push_back(std::move(mean));
    out.columns.push_back(std::move(se));
  }
}

void average_scalars(Combiner& combine, const DiagnosticOutput& first, DiagnosticOutput& out) {
  for (std::size_t s = 0; s < first.scalars.size(); ++s) {
    auto [m, e] = combine([&](const DiagnosticOutput& o) { return o.scalars[s].value; });
    out.scalars.push_back({first.scalars[s].name, first.scalars[s].unit, first.scalars[s].doc, m});
    out.scalars.push_back({first.scalars[s].name + "_stderr", first.scalars[s].unit,
                           "standard error over realizations of " + first.scalars[s].name, e});
  }
}

}  // namespace

std::vector<DiagnosticOutput> average_realizations(const std::vector<std::vector<DiagnosticOutput>>& runs,
                                                   std::vector<std::string>* summary) {
  if (runs.size() == 1) return runs[0];
  const std::size_t K = runs.size();
  std::vector<DiagnosticOutput> avg;
  for (std::size_t d = 0; d < runs[0].size(); ++d) {
    const DiagnosticOutput& first = runs[0][d];
    DiagnosticOutput out(first.group(), summary);
    out.attributes = first.attributes;
    out.attributes["realizations"] = std::to_string(K);
    std::size_t records = first.time.size();
    for (const auto& r : runs) records = std::min(records, r[d].time.size());
    Combiner combine(runs, d);
    average_columns(combine, first, records, out);
    average_scalars(combine, first, out);
    out.bin_centres = first.bin_centres;
    for (std::size_t p = 0; p < first.profiles.size(); ++p)
      combine_item(combine, first.profiles[p],
                   [p](const DiagnosticOutput& o) -> const std::vector<double>& { return o.profiles[p].values; },
                   &DiagnosticOutput::Profile::values, out.profiles, records * first.bins());
    for (std::size_t a = 0; a < first.arrays.size(); ++a)
      combine_item(combine, first.arrays[a], [a](const DiagnosticOutput& o) -> const std::vector<double>& { return o.arrays[a].data; },
                   &DiagnosticOutput::Array::data, out.arrays);
    for (std::size_t h = 0; h < first.histograms.size(); ++h)
      combine_item(combine, first.histograms[h],
                   [h](const DiagnosticOutput& o) -> const std::vector<double>& { return o.histograms[h].values; },
                   &DiagnosticOutput::Histogram::values, out.histograms);
    avg.push_back(std::move(out));
  }
  return avg;
}

namespace {

// The records of a steady average: those with s >= after_s (or else t/tau0 >= after_t).
struct SteadyWindow {
  std::optional<double> after_s, after_t;
  bool contains(const DiagnosticOutput& d, std::size_t k) const {
    return after_s ? d.collisions_per_particle[k] >= *after_s : d.time[k] >= *after_t;
  }
  std::string text() const { return after_s ? "s >= " + std::to_string(*after_s) : "t/tau0 >= " + std::to_string(*after_t); }
};

bool is_stderr(const std::string& name) { return name.size() > 7 && name.compare(name.size() - 7, 7, "_stderr") == 0; }

void add_finite(BatchMeans& bm, double x) {
  if (std::isfinite(x)) bm.add(x);
}

void add_steady_series(DiagnosticOutput& d, const SteadyWindow& w) {
  const std::size_t columns = d.columns.size();
  for (std::size_t c = 0; c < columns; ++c) {
    const auto& col = d.columns[c];
    if (is_stderr(col.name)) continue;
    BatchMeans bm;
    for (std::size_t k = 0; k < d.time.size(); ++k)
      if (w.contains(d, k)) add_finite(bm, col.values[k]);
    d.scalars.push_back({col.name + ".steady_mean", col.unit,
                         "time average of " + col.name + " over the records with " + w.text() + " (" +
                             std::to_string(bm.count()) + " records)",
                         bm.mean()});
    d.scalars.push_back({col.name + ".steady_stderr", col.unit,
                         "batch-means standard error of " + col.name + ".steady_mean (NaN: too few records)",
                         bm.standard_error()});
  }
}

// The same per bin for every profile, as arrays of shape (bins).
void add_steady_profiles(DiagnosticOutput& d, const SteadyWindow& w) {
  const std::size_t bins = d.bins();
  for (const auto& prof : d.profiles) {
    if (is_stderr(prof.name)) continue;
    std::vector<BatchMeans> bm(bins);
    std::size_t records = 0;
    for (std::size_t k = 0; k < d.time.size() && (k + 1) * bins <= prof.values.size(); ++k) {
      if (!w.contains(d, k)) continue;
      ++records;
      for (std::size_t b = 0; b < bins; ++b) add_finite(bm[b], prof.values[k * bins + b]);
    }
    std::vector<double> mean(bins), se(bins);
    for (std::size_t b = 0; b < bins; ++b) {
      mean[b] = bm[b].mean();
      se[b] = bm[b].standard_error();
    }
    d.arrays.push_back({prof.name + ".steady_mean", prof.unit,
                        "time average per bin of " + prof.name + " over the records with " + w.text() + " (" +
                            std::to_string(records) + " records; non-finite values skipped)",
                        std::move(mean), {bins}});
    d.arrays.push_back({prof.name + ".steady_stderr", prof.unit,
                        "batch-means standard error per bin of " + prof.name + ".steady_mean (NaN: too few records)",
                        std::move(se), {bins}});
  }
}

}  // namespace

void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t) {
  if (!after_s && !after_t) return;
  const SteadyWindow window{after_s, after_t};
  for (auto& d : diagnostics) {
    add_steady_series(d, window);
    add_steady_profiles(d, window);
  }
}

}  // namespace gdsmc::host
