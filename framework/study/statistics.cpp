#include "study/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include <boost/math/distributions/chi_squared.hpp>

#include <gdsmc/physics/series.hpp>

#include "util/text.hpp"

namespace gdsmc::host {

namespace {

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The value a scalar named `name` is the error of, if it is a plugin's own error: "X" for
// "X_error" or "X_standard_error" (the value is X or X_mean); "" for a scalar that is no error.
std::string error_base(const std::string& name) {
  for (const std::string suffix : {"_standard_error", "_error"})
    if (name.size() > suffix.size() && ends_with(name, suffix)) return name.substr(0, name.size() - suffix.size());
  return "";
}

// Whether diagnostic d declares the series of a host steady error (name "<series>.steady_stderr")
// stationary: its attribute `stationary` is "all" or names the series among names separated by
// commas. A steady average of a cooling T or of a running count has no error to promise.
bool declared_stationary(const DiagnosticOutput& d, const std::string& error_name) {
  const auto declared = d.attributes.find("stationary");
  if (declared == d.attributes.end()) return false;
  if (declared->second == "all") return true;
  const std::string series = error_name.substr(0, error_name.find('.'));
  return ("," + declared->second + ",").find("," + series + ",") != std::string::npos;
}

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

// The seed check of every error a run reports (issue 29 item 2): for each scalar pair value X and
// error E (E named X_error or X_standard_error, X also X_mean), chi2/dof of the realizations'
// values about their mean against their own errors, "<E>_seed_chi2_dof" (and "_weighted"), and a
// text attribute "seed_check" (printed in the case's summary) naming those outside the 95 % band
// of chi2 with K - 1 degrees of freedom. A realization whose E is not finite and positive (its
// reason is in E's description) is left out of that check, and said so; with fewer than two left,
// the check is NaN.
void add_seed_checks(const std::vector<std::vector<DiagnosticOutput>>& runs, std::size_t d, DiagnosticOutput& out,
                     SeedErrors kind) {
  const DiagnosticOutput& first = runs[0][d];
  const std::size_t K = runs.size();
  const auto band_text = [](const SeedBand& b, std::size_t k) {
    return "[" + number(b.low) + ", " + number(b.high) + "] for " + std::to_string(k - 1) + " dof";
  };
  std::vector<double> x, e;
  std::string outside, unchecked;
  std::size_t pairs = 0, checked = 0, inside = 0, most_left_out = 0;
  for (std::size_t s = 0; s < first.scalars.size(); ++s) {
    const std::string& name = first.scalars[s].name;
    std::size_t v = first.scalars.size();
    if (kind == SeedErrors::plugin) {
      const std::string base = error_base(name);
      if (base.empty()) continue;
      for (std::size_t t = 0; t < first.scalars.size(); ++t)
        if (first.scalars[t].name == base || first.scalars[t].name == base + "_mean") v = t;
    } else {
      if (!ends_with(name, ".steady_stderr") || !declared_stationary(first, name)) continue;
      const std::string mean = name.substr(0, name.size() - 6) + "mean";  // X.steady_stderr -> X.steady_mean
      for (std::size_t t = 0; t < first.scalars.size(); ++t)
        if (first.scalars[t].name == mean) v = t;
    }
    if (v == first.scalars.size()) continue;
    x.clear(), e.clear();
    for (std::size_t r = 0; r < K; ++r) {
      const double value = runs[r][d].scalars[v].value, error = runs[r][d].scalars[s].value;
      if (!std::isfinite(value) || !std::isfinite(error) || !(error > 0)) continue;
      x.push_back(value), e.push_back(error);
    }
    const std::size_t used = x.size();
    const SeedBand band = seed_chi2_band(used);
    const std::string over = std::to_string(used) + (used < K ? " of the " + std::to_string(K) : "") + " realizations";
    const std::string left_out =
        used < K ? "; " + std::to_string(K - used) + " left out, their " + name + " NaN or not positive (the reason in its description)" : "";
    const double chi2 = seed_chi2_per_dof(x, e, false);
    out.scalars.push_back({name + "_seed_chi2_dof", "1",
                           "chi2/dof of " + over + "' " + first.scalars[v].name +
                               " about their mean against the mean of their own " + name + " squared (1 when the errors hold" +
                               (used >= 2 ? "; 95 % band " + band_text(band, used) : "") + left_out +
                               "; NaN with fewer than 2 finite errors)",
                           chi2});
    out.scalars.push_back({name + "_seed_chi2_dof_weighted", "1",
                           "the same with each realization weighted by its own " + name +
                               " (nu/(nu-2) on average when each error has nu degrees of freedom: it also "
                               "tests how precise each error is)",
                           seed_chi2_per_dof(x, e, true)});
    ++pairs;
    if (!std::isfinite(chi2)) {
      unchecked += (unchecked.empty() ? "" : ", ") + first.scalars[v].name;
      continue;
    }
    ++checked;
    most_left_out = std::max(most_left_out, K - used);
    if (chi2 >= band.low && chi2 <= band.high) ++inside;
    else outside += (outside.empty() ? "" : ", ") + first.scalars[v].name + " " + number(chi2);
  }
  if (pairs == 0) return;
  const std::string full_band = band_text(seed_chi2_band(K), K);
  out.attributes["seed_chi2_band_95"] = full_band;
  out.attributes[kind == SeedErrors::plugin ? "seed_check" : "seed_check_steady"] =
      first.group() + (kind == SeedErrors::plugin ? ": errors" : ": the host's steady errors of one realization") +
      " checked over " + std::to_string(K) + " realizations (chi2/dof, 95 % band " + full_band +
      "): " + std::to_string(inside) + " of " + std::to_string(checked) + " inside" +
      (outside.empty() ? "" : "; outside: " + outside) +
      (most_left_out ? "; up to " + std::to_string(most_left_out) +
                           " realization(s) left out of a check, their error NaN (the reason in its description)"
                     : "") +
      (unchecked.empty() ? "" : "; not checked, fewer than 2 finite errors: " + unchecked);
}

std::vector<DiagnosticOutput> average_realizations(const std::vector<std::vector<DiagnosticOutput>>& runs,
                                                   std::vector<std::string>* summary) {
  if (runs.size() == 1) return runs[0];
  const std::size_t K = runs.size();
  std::vector<DiagnosticOutput> avg;
  for (std::size_t d = 0; d < runs[0].size(); ++d) {
    const DiagnosticOutput& first = runs[0][d];
    DiagnosticOutput out(first.group(), summary);
    out.attributes = first.attributes;
    out.theory_tags = first.theory_tags;
    out.axes = first.axes;
    out.attributes["realizations"] = std::to_string(K);
    std::size_t records = first.time.size();
    for (const auto& r : runs) records = std::min(records, r[d].time.size());
    Combiner combine(runs, d);
    average_columns(combine, first, records, out);
    average_scalars(combine, first, out);
    add_seed_checks(runs, d, out, SeedErrors::plugin);
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

// Said in the description of a steady average whose window holds no record.
const char* const kNoRecord = "; NaN: no record reached the window";

bool is_stderr(const std::string& name) { return name.size() > 7 && ends_with(name, "_stderr"); }

// One value per record: a series (stride 1) or one bin of a profile (stride bins, offset bin).
struct Values {
  const std::vector<double>* values = nullptr;
  std::size_t stride = 1, offset = 0;
  double at(std::size_t k) const {
    const std::size_t i = k * stride + offset;
    return values && i < values->size() && offset < stride ? (*values)[i] : std::nan("");
  }
};
using ValuesOf = std::function<Values(const DiagnosticOutput&)>;

// The window's records of one value, non-finite values skipped.
std::vector<double> window_values(const Values& src, const std::vector<std::size_t>& records) {
  std::vector<double> v;
  v.reserve(records.size());
  for (std::size_t k : records) {
    const double x = src.at(k);
    if (std::isfinite(x)) v.push_back(x);
  }
  return v;
}

// The steady mean of one value and its error, with how the error was found.
struct SteadyEstimate {
  double mean = std::nan(""), stderr_ = std::nan("");
  double tau = std::nan("");  // single realization: integrated autocorrelation time, records
  std::size_t batch_length = 0, batches = 0;
};

SteadyEstimate single_realization(const std::vector<double>& v) {
  SteadyEstimate e;
  if (v.empty()) return e;
  e.mean = mean_of(v);
  const BatchSpec spec = choose_batches(v);
  e.tau = spec.tau;
  e.batch_length = spec.length;
  e.batches = spec.batches;
  if (spec.batches < kMinBatches) return e;
  std::vector<double> means(spec.batches, 0.0);
  const std::size_t skip = v.size() - spec.batches * spec.length;  // the earliest records of the window
  for (std::size_t i = 0; i < spec.batches; ++i) {
    for (std::size_t j = 0; j < spec.length; ++j) means[i] += v[skip + i * spec.length + j];
    means[i] /= static_cast<double>(spec.length);
  }
  e.stderr_ = stderr_of(means);
  return e;
}

// Several realizations: the mean over the pooled window (as before: the time average of the
// realization average) and the error from the scatter of each realization's own time average.
SteadyEstimate between_realizations(const std::vector<double>& pooled, const std::vector<std::vector<double>>& own) {
  SteadyEstimate e;
  if (!pooled.empty()) e.mean = mean_of(pooled);
  std::vector<double> means;
  for (const auto& v : own)
    if (!v.empty()) means.push_back(mean_of(v));
  if (means.size() >= 2) e.stderr_ = stderr_of(means);
  e.batches = means.size();
  return e;
}

// The records of d inside the window.
std::vector<std::size_t> window_records(const DiagnosticOutput& d, const SteadyWindow& w, std::size_t limit) {
  std::vector<std::size_t> r;
  for (std::size_t k = 0; k < d.time.size() && k < limit; ++k)
    if (w.contains(d, k)) r.push_back(k);
  return r;
}

SteadyEstimate estimate(const DiagnosticOutput& d, const std::vector<const DiagnosticOutput*>& own,
                        const std::vector<std::size_t>& records, const ValuesOf& of, std::size_t& finite) {
  const std::vector<double> pooled = window_values(of(d), records);
  finite = pooled.size();
  if (own.size() < 2) return single_realization(pooled);
  std::vector<std::vector<double>> per_run;
  for (const DiagnosticOutput* r : own) per_run.push_back(window_values(of(*r), records));
  return between_realizations(pooled, per_run);
}

std::string error_text(const std::string& of, std::size_t realizations, const SteadyEstimate& e, std::size_t n) {
  if (realizations >= 2)
    return "standard error of " + of + ": sd / sqrt(K) of the K = " + std::to_string(realizations) +
           " realizations' own time averages over the window (each realization's series is independent)";
  std::string s = "batch-means standard error of " + of + ": " + std::to_string(n) +
                  " records, integrated autocorrelation time tau_int = " + number(e.tau) +
                  " records (1 + 2 sum of the autocorrelations), batches of " + std::to_string(e.batch_length) +
                  " records (>= " + number(kBatchTaus) + " tau_int)";
  if (e.batches >= kMinBatches) return s + ", " + std::to_string(e.batches) + " batches";
  return s + "; NaN: the window holds only " + std::to_string(e.batches) + " such batches, fewer than " +
         std::to_string(kMinBatches) + " (run longer, average from earlier, or use several realizations)";
}

void add_steady_series(DiagnosticOutput& d, const std::vector<const DiagnosticOutput*>& own, const SteadyWindow& w,
                       std::size_t limit) {
  const std::vector<std::size_t> records = window_records(d, w, limit);
  const std::size_t columns = d.columns.size();
  for (std::size_t c = 0; c < columns; ++c) {
    if (is_stderr(d.columns[c].name)) continue;
    const std::string name = d.columns[c].name, unit = d.columns[c].unit;
    const ValuesOf of = [&name](const DiagnosticOutput& o) {
      for (const auto& col : o.columns)
        if (col.name == name) return Values{&col.values, 1, 0};
      return Values{};
    };
    std::size_t n = 0;
    const SteadyEstimate e = estimate(d, own, records, of, n);
    d.scalars.push_back({name + ".steady_mean", unit,
                         "time average of " + name + " over the records with " + w.text() + " (" + std::to_string(n) +
                             " records)" + (records.empty() ? kNoRecord : ""),
                         e.mean});
    d.scalars.push_back({name + ".steady_stderr", unit, error_text(name + ".steady_mean", own.size(), e, n), e.stderr_});
  }
}

// The same per bin for every profile, as arrays of shape (bins).
void add_steady_profiles(DiagnosticOutput& d, const std::vector<const DiagnosticOutput*>& own, const SteadyWindow& w,
                         std::size_t limit) {
  const std::size_t bins = d.bins();
  std::vector<std::size_t> records;
  for (std::size_t p = 0; p < d.profiles.size(); ++p) {
    if (is_stderr(d.profiles[p].name)) continue;
    const std::string name = d.profiles[p].name, unit = d.profiles[p].unit;
    records.clear();
    for (std::size_t k : window_records(d, w, limit))
      if ((k + 1) * bins <= d.profiles[p].values.size()) records.push_back(k);
    std::vector<double> mean(bins), se(bins);
    double tau_max = 0;
    std::size_t nan_bins = 0, fewest_batches = SIZE_MAX;
    for (std::size_t b = 0; b < bins; ++b) {
      const ValuesOf of = [&name, b, bins](const DiagnosticOutput& o) {
        for (const auto& prof : o.profiles)
          if (prof.name == name) return Values{&prof.values, bins, b};
        return Values{};
      };
      std::size_t n = 0;
      const SteadyEstimate e = estimate(d, own, records, of, n);
      mean[b] = e.mean;
      se[b] = e.stderr_;
      if (std::isfinite(e.tau)) tau_max = std::max(tau_max, e.tau);
      if (!std::isfinite(e.stderr_)) ++nan_bins;
      fewest_batches = std::min(fewest_batches, e.batches);
    }
    std::string how;
    if (own.size() >= 2) {
      how = "per bin: sd / sqrt(K) of the K = " + std::to_string(own.size()) +
            " realizations' own time averages over the window";
    } else {
      how = "per bin, batch means with batches of >= " + number(kBatchTaus) +
            " integrated autocorrelation times of that bin's series (largest tau_int " + number(tau_max) +
            " records; fewest batches " + std::to_string(fewest_batches == SIZE_MAX ? 0 : fewest_batches) + ")";
      if (nan_bins)
        how += "; NaN in " + std::to_string(nan_bins) + " bins: fewer than " + std::to_string(kMinBatches) +
               " such batches in the window (or no finite values)";
    }
    d.arrays.push_back({name + ".steady_mean", unit,
                        "time average per bin of " + name + " over the records with " + w.text() + " (" +
                            std::to_string(records.size()) + " records; non-finite values skipped)" +
                            (records.empty() ? kNoRecord : ""),
                        std::move(mean), {bins}});
    d.arrays.push_back({name + ".steady_stderr", unit, "standard error of " + name + ".steady_mean " + how,
                        std::move(se), {bins}});
  }
}

}  // namespace

void add_steady_averages(std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                         std::optional<double> after_t, const std::vector<std::vector<DiagnosticOutput>>& runs) {
  if (!after_s && !after_t) return;
  const SteadyWindow window{after_s, after_t};
  for (std::size_t i = 0; i < diagnostics.size(); ++i) {
    auto& d = diagnostics[i];
    std::vector<const DiagnosticOutput*> own;
    if (runs.size() >= 2)
      for (const auto& r : runs) own.push_back(&r.at(i));
    const std::size_t limit = d.time.size();
    add_steady_series(d, own, window, limit);
    add_steady_profiles(d, own, window, limit);
    d.tag_steady_means();
  }
}

std::string steady_window_missed(const std::vector<DiagnosticOutput>& diagnostics, std::optional<double> after_s,
                                 std::optional<double> after_t) {
  if (!after_s && !after_t) return "";
  for (const auto& d : diagnostics) {
    if (d.time.empty()) continue;
    // Every diagnostic records the final state, so the last record of any one (of the realization
    // average: the shortest run's) tells whether the window was reached.
    const double end = after_s ? d.collisions_per_particle.back() : d.time.back();
    const double start = after_s ? *after_s : *after_t;
    if (end >= start) return "";
    const char* clock = after_s ? "s" : "t/tau0";
    return fmt("run.average_after: the steady window %s >= %.6g holds no record (the last is at %s = %.6g), so every "
               "steady_mean and steady_stderr is NaN; start the average earlier or run longer",
               clock, start, clock, end);
  }
  return "";
}

std::vector<std::string> nan_error_warnings(const std::vector<DiagnosticOutput>& diagnostics) {
  // Per kind (the host's steady errors, the plugins' own): the count and "group (n)" per diagnostic.
  std::size_t counts[2] = {0, 0};
  std::string where[2], first[2];
  for (const auto& d : diagnostics) {
    // The host's steady errors count for the series the diagnostic declares stationary (its
    // attribute `stationary`: "all" or names separated by commas); a steady average of a cooling T
    // or of a running count has no error to promise.
    const auto stationary = [&](const std::string& error_name) { return declared_stationary(d, error_name); };
    std::size_t here[2] = {0, 0};
    const auto note = [&](int kind, const std::string& name) {
      if (counts[kind] + here[kind] == 0) first[kind] = d.group() + "/" + name;
      ++here[kind];
    };
    for (const auto& sc : d.scalars) {
      if (std::isfinite(sc.value)) continue;
      if (ends_with(sc.name, ".steady_stderr")) {
        if (stationary(sc.name)) note(0, sc.name);
      }
      else if (!error_base(sc.name).empty()) note(1, sc.name);
    }
    for (const auto& a : d.arrays)
      if (ends_with(a.name, ".steady_stderr") && stationary(a.name) && std::any_of(a.data.begin(), a.data.end(), [](double x) { return !std::isfinite(x); }))
        note(0, a.name + " (some bins)");
    for (int kind = 0; kind < 2; ++kind)
      if (here[kind]) {
        where[kind] += (where[kind].empty() ? "" : ", ") + d.group() + fmt(" (%zu)", here[kind]);
        counts[kind] += here[kind];
      }
  }
  const char* remedy = ": run longer, start run.average_after earlier, or use run.realizations >= 2 (errors from the "
                       "scatter of the realizations)";
  std::vector<std::string> lines;
  if (counts[0])
    lines.push_back(fmt("warning: %zu steady error%s NaN, in ", counts[0], counts[0] == 1 ? " is" : "s are") + where[0] + " (e.g. " + first[0] +
                    fmt("): the averaging window holds fewer than %zu batches of %.0f integrated autocorrelation times "
                        "(each description gives tau_int and the batch length)",
                        kMinBatches, kBatchTaus) + remedy);
  if (counts[1])
    lines.push_back(fmt("warning: %zu error%s estimated by plugins %s NaN, in ", counts[1], counts[1] == 1 ? "" : "s", counts[1] == 1 ? "is" : "are") + where[1] + " (e.g. " +
                    first[1] + "; each description says why)" + remedy);
  return lines;
}

SeedBand seed_chi2_band(std::size_t realizations) {
  SeedBand b;
  if (realizations < 2) return b;
  const double dof = static_cast<double>(realizations - 1);
  const boost::math::chi_squared dist(dof);
  b.low = boost::math::quantile(dist, 0.025) / dof;
  b.high = boost::math::quantile(dist, 0.975) / dof;
  return b;
}

double seed_chi2_per_dof(const std::vector<double>& values, const std::vector<double>& errors, bool weighted) {
  const std::size_t K = values.size();
  if (K < 2 || errors.size() != K) return std::nan("");
  double sw = 0, swx = 0, sx = 0, se2 = 0;
  for (std::size_t r = 0; r < K; ++r) {
    if (!std::isfinite(values[r]) || !std::isfinite(errors[r]) || !(errors[r] > 0)) return std::nan("");
    const double w = 1.0 / (errors[r] * errors[r]);
    sw += w;
    swx += w * values[r];
    sx += values[r];
    se2 += errors[r] * errors[r];
  }
  const double dof = static_cast<double>(K - 1);
  double chi2 = 0;
  if (weighted) {
    const double mean = swx / sw;
    for (std::size_t r = 0; r < K; ++r) chi2 += (values[r] - mean) * (values[r] - mean) / (errors[r] * errors[r]);
  } else {
    const double mean = sx / static_cast<double>(K), e2 = se2 / static_cast<double>(K);
    for (std::size_t r = 0; r < K; ++r) chi2 += (values[r] - mean) * (values[r] - mean) / e2;
  }
  return chi2 / dof;
}

double integrated_autocorrelation_time(const std::vector<double>& v) {
  return gdsmc::integrated_autocorrelation_time(v.data(), v.size());
}

BatchSpec choose_batches(const std::vector<double>& v) {
  BatchSpec s;
  s.tau = integrated_autocorrelation_time(v);
  s.length = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(kBatchTaus * s.tau)));
  s.batches = v.size() / s.length;
  if (s.batches > kMaxBatches) {
    s.length = (v.size() + kMaxBatches - 1) / kMaxBatches;
    s.batches = v.size() / s.length;
  }
  return s;
}

}  // namespace gdsmc::host
