// Layers sized to the local mean free path (system.layers: {mean_free_paths, after[, max_width]}):
// equal widths during the transient, the density profile of its second half on a fine grid, the
// edges set from it at its end and then frozen, and each layer's width in local mean free paths
// measured after that (the run's summary and /system datasets).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/state.hpp>

#include "config/pipeline.hpp"
#include "output/records.hpp"

namespace gdsmc::host {

class AdaptiveLayers {
 public:
  // A slab pipeline with system.layers: {mean_free_paths, ...}: the edges of equal layers, given as
  // edges from the start (system.layer_edges), so that a plugin sees in begin() that this run's
  // layers are not uniform and can refuse it there. Otherwise nothing.
  void open(const Pipeline& p, SystemInfo& system);
  bool enabled() const { return enabled_; }
  bool set() const { return set_; }
  const std::vector<double>& edges() const { return edges_; }
  // Whether the run at t (tau0) has reached the end of the transient, or its second half.
  bool due(double t) const { return !set_ && t >= p_->layers_after_tau0; }
  bool profiling(double t) const { return !set_ && t >= 0.5 * p_->layers_after_tau0; }

  // One sample of the density profile: every particle's y into the fine bins.
  void sample_profile(const ParticleSpan& p);
  // The edges from the profile sampled so far (the caller samples the state at the end of the
  // transient first): every layer holds the same weight.
  std::vector<double> edges_from_profile();
  // The edges in use from now on (checked by the caller's grid), set at t (tau0); returns the
  // summary line that says what they are.
  std::string adopt(std::vector<double> edges, double t);
  // At every moment update after the edges are set: each layer's count, for its mean width.
  void tally(const CellMoments* cells);
  // delta y_I / lambda_I for layer I since the edges were set (NaN before).
  double width_local(std::size_t I) const;
  // The end-of-run summary line: the widths reached, or that the run ended before the edges were set.
  std::string widths_text(double t_end) const;
  // /system attributes and datasets: the target, when the edges were set, the edges, the widths.
  void write(CaseOutput& out) const;
  void save(StateWriter& out) const;
  // The checkpoint's entries; `set_edges` hands the edges to the caller's grid (which may refuse them).
  template <typename SetEdges>
  void load(StateReader& in, SetEdges&& set_edges);

 private:
  void load_entries(StateReader& in, std::vector<double>& edges);
  void use(std::vector<double> edges);

  bool enabled_ = false;
  const Pipeline* p_ = nullptr;
  SystemInfo* system_ = nullptr;
  std::vector<double> edges_;    // SystemInfo::layer_edges points here
  std::vector<double> profile_;  // the fine bins of the transient's second half
  std::uint64_t profile_samples_ = 0;
  bool set_ = false;
  double set_time_tau0_ = 0;
  std::vector<double> count_sums_;  // each layer's count, summed over the moment updates since set
  std::uint64_t count_samples_ = 0;
  // Of the last edges_from_profile(), for adopt()'s line: the particles sampled, the weight each
  // fine bin adds for max_width, and the total weight.
  double particles_ = 0, per_bin_ = 0, total_ = 0;
};

template <typename SetEdges>
void AdaptiveLayers::load(StateReader& in, SetEdges&& set_edges) {
  if (!enabled_) return;  // other runs' state has no layers entries
  std::vector<double> edges;
  load_entries(in, edges);
  set_edges(edges);
  use(std::move(edges));
}

}  // namespace gdsmc::host
