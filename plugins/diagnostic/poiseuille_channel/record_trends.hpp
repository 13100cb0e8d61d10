// poiseuille_channel: the trends of its own records, written at the end of a run so that no report
// fits them: the drift and relative rms of E(t) over the averaging window (004 Appendix: E is
// constant once steady) and the growth rate dQ/dt of the flow rate over the last three quarters of
// the records (Eq. 40: Q grows as Kn t/tau0 where nothing balances the acceleration, as between
// specular walls; about 0 in a steady run).
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>

namespace poiseuille {

class RecordTrends {
 public:
  void clear() {
    t_.clear();
    e_.clear();
    q_.clear();
    first_steady_ = kNone;
  }
  // One record that holds samples: its time t/tau0, E [T_w], Q_record, and whether it lies in the
  // averaging window (every later record does).
  void add(double t, double e, double q, bool steady) {
    if (steady && first_steady_ == kNone) first_steady_ = t_.size();
    t_.push_back(t);
    e_.push_back(e);
    q_.push_back(q);
  }
  void write(gdsmc::OutputSink& out) const {
    double drift = std::nan(""), rms = std::nan("");
    const std::size_t n = t_.size();
    if (first_steady_ != kNone && n - first_steady_ >= 4) {
      const std::size_t from = first_steady_;
      const double mean = mean_of(e_, from), length = t_.back() - t_[from];
      drift = slope(e_, from) * length / mean;
      double ss = 0;
      for (std::size_t k = from; k < n; ++k) ss += (e_[k] - mean) * (e_[k] - mean);
      rms = std::sqrt(ss / static_cast<double>(n - from - 1)) / mean;
    }
    out.scalar("E_drift", drift, "1",
               "drift of E(t) over the averaging window: the least-squares slope of the E records from steady_from "
               "on, times the time between the first and last of them, over their mean (004 Appendix: 0 when "
               "steady); NaN without a window of 4 records");
    out.scalar("E_relative_rms", rms, "1",
               "rms of the E records over the averaging window about their mean (n - 1 in the denominator), over "
               "their mean; NaN without a window of 4 records");
    const std::size_t from = n / 4;
    out.scalar("Q_growth_rate", n - from >= 2 ? slope(q_, from) : std::nan(""), "1/tau0",
               "growth rate dQ/d(t/tau0) of the flow rate: the least-squares slope of Q_record against t/tau0 over "
               "the last three quarters of the records (Eq. 40: Kn exactly when nothing balances the acceleration, "
               "as between specular walls; about 0 in a steady run); NaN with fewer than 2 records there");
  }
  void save(gdsmc::StateWriter& out, const std::string& prefix) const {
    out.write(prefix + ".t", t_);
    out.write(prefix + ".E", e_);
    out.write(prefix + ".Q", q_);
    out.write(prefix + ".first_steady", static_cast<std::uint64_t>(first_steady_));
  }
  void load(gdsmc::StateReader& in, const std::string& prefix) {
    in.read(prefix + ".t", t_);
    in.read(prefix + ".E", e_);
    in.read(prefix + ".Q", q_);
    std::uint64_t first = 0;
    in.read(prefix + ".first_steady", first);
    first_steady_ = static_cast<std::size_t>(first);
    if (e_.size() != t_.size() || q_.size() != t_.size() || (first_steady_ != kNone && first_steady_ > t_.size()))
      throw gdsmc::StateError("checkpoint entries '" + prefix + ".*': not the records of poiseuille_channel");
  }

 private:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

  double mean_of(const std::vector<double>& v, std::size_t from) const {
    double m = 0;
    for (std::size_t k = from; k < v.size(); ++k) m += v[k];
    return m / static_cast<double>(v.size() - from);
  }
  // Least-squares slope of v against t_ over the records from `from` on (centred sums).
  double slope(const std::vector<double>& v, std::size_t from) const {
    const double mt = mean_of(t_, from), mv = mean_of(v, from);
    double stv = 0, stt = 0;
    for (std::size_t k = from; k < t_.size(); ++k) {
      stv += (t_[k] - mt) * (v[k] - mv);
      stt += (t_[k] - mt) * (t_[k] - mt);
    }
    return stv / stt;
  }

  std::vector<double> t_, e_, q_;
  std::size_t first_steady_ = kNone;  // the first record of the averaging window
};

}  // namespace poiseuille
