#include "engine/adaptive_layers.hpp"

#include <algorithm>
#include <cmath>

#include <gdsmc/physics/units.hpp>

#include "util/text.hpp"

namespace gdsmc::host {

void AdaptiveLayers::open(const Pipeline& p, SystemInfo& system) {
  p_ = &p;
  system_ = &system;
  enabled_ = p.layers_mean_free_paths > 0;
  if (!enabled_ || system.geometry != Geometry::slab) return;
  const std::size_t m = system.cells;
  const double ly = system.box[1], half = 0.5 * ly;
  edges_.resize(m + 1);
  for (std::size_t I = 0; I <= m; ++I) edges_[I] = -half + ly * static_cast<double>(I) / static_cast<double>(m);
  edges_[0] = -half;
  edges_[m] = half;
  system.layer_edges = edges_.data();
  // The profile's fine bins: 64 per layer (the densest layer is then still a few bins wide where
  // the density is up to ~16 times its mean), within [1024, 2^22].
  profile_.assign(std::clamp<std::size_t>(64 * m, 1024, std::size_t{1} << 22), 0.0);
  count_sums_.assign(m, 0.0);
}

void AdaptiveLayers::sample_profile(const ParticleSpan& p) {
  const double half = 0.5 * system_->box[1];
  const double scale = static_cast<double>(profile_.size()) / system_->box[1];
  const std::size_t last = profile_.size() - 1;
  double* const h = profile_.data();
  for (std::size_t i = 0; i < p.count; ++i) {
    const double f = (p.y[i] + half) * scale;
    const std::size_t b = f > 0 ? std::min(static_cast<std::size_t>(f), last) : 0;
    h[b] += 1.0;
  }
  ++profile_samples_;
}

// Edges at the quantiles I/M of the measured profile (linear within a fine bin), so that every
// layer holds the same mean number of particles N/M. With the dilute lambda(y) = 1/(sqrt(2) pi
// n(y) sigma^2) a layer's width in local mean free paths is sqrt(2) pi sigma^2 N_I / A, the same
// N/M for all: Ly/(M lambda0) <= the target. With max_width L each fine bin also weighs as if it
// held c = N w lambda0 / (bins L) particles more: a layer then spans one unit of n(y)/(n-bar w
// lambda0) + 1/L, so it is at most w local mean free paths and at most L wide (c = 0 without L:
// the same edges as without it to the bit).
std::vector<double> AdaptiveLayers::edges_from_profile() {
  const std::size_t m = system_->cells, bins = profile_.size();
  const double ly = system_->box[1], half = 0.5 * ly, width = ly / static_cast<double>(bins);
  particles_ = 0;
  for (const double c : profile_) particles_ += c;
  per_bin_ = p_->layers_max_width > 0 ? particles_ * p_->layers_mean_free_paths * system_->mean_free_path0 /
                                            (static_cast<double>(bins) * p_->layers_max_width)
                                      : 0.0;
  total_ = particles_ + per_bin_ * static_cast<double>(bins);
  std::vector<double> edges(m + 1);
  edges[0] = -half;
  edges[m] = half;
  double below = 0;  // weight of the bins before j
  std::size_t j = 0;
  for (std::size_t I = 1; I < m; ++I) {
    const double target = total_ * static_cast<double>(I) / static_cast<double>(m);
    while (j + 1 < bins && below + (profile_[j] + per_bin_) < target) below += profile_[j++] + per_bin_;
    const double in_bin = profile_[j] + per_bin_;
    const double f = in_bin > 0 ? std::clamp((target - below) / in_bin, 0.0, 1.0) : 0.5;
    edges[I] = -half + (static_cast<double>(j) + f) * width;
  }
  // Strictly increasing, and inside the slab, whatever the rounding.
  for (std::size_t I = 1; I < m; ++I) {
    if (!(edges[I] > edges[I - 1])) edges[I] = std::nextafter(edges[I - 1], half);
  }
  for (std::size_t I = m - 1; I >= 1; --I) {
    if (!(edges[I] < edges[I + 1])) edges[I] = std::nextafter(edges[I + 1], -half);
  }
  return edges;
}

void AdaptiveLayers::use(std::vector<double> edges) {
  edges_ = std::move(edges);
  system_->layer_edges = edges_.data();
}

std::string AdaptiveLayers::adopt(std::vector<double> edges, double t) {
  use(std::move(edges));
  set_ = true;
  set_time_tau0_ = t;
  profile_.assign(profile_.size(), 0.0);
  const std::size_t m = system_->cells;
  const double ly = system_->box[1], lambda0 = system_->mean_free_path0;
  double narrow = ly, wide = 0;
  for (std::size_t I = 0; I < m; ++I) {
    narrow = std::min(narrow, edges_[I + 1] - edges_[I]);
    wide = std::max(wide, edges_[I + 1] - edges_[I]);
  }
  // A layer holds total/m of the weight: at most that many particles (its width in local mean free
  // paths: the particles' share of Ly/lambda0) and that many bins' worth of per_bin.
  const double share = total_ / static_cast<double>(m), width = ly / static_cast<double>(profile_.size());
  const std::string bound =
      per_bin_ > 0 ? fmt("each at most %.4g local mean free paths and %.4g lambda0 wide (targets %.4g and max_width "
                         "%.4g lambda0)",
                         share / particles_ * ly / lambda0, share / per_bin_ * width / lambda0,
                         p_->layers_mean_free_paths, p_->layers_max_width / lambda0)
                   : fmt("each %.4g local mean free paths (target %.4g)", ly / (static_cast<double>(m) * lambda0),
                         p_->layers_mean_free_paths);
  return fmt("layers: set at t = %.4g tau0 from the density over t >= %.4g tau0 (%llu samples): %zu layers %.4g to "
             "%.4g lambda0 wide, %s",
             set_time_tau0_, 0.5 * p_->layers_after_tau0, static_cast<unsigned long long>(profile_samples_), m,
             narrow / lambda0, wide / lambda0, bound.c_str());
}

void AdaptiveLayers::tally(const CellMoments* cells) {
  for (std::size_t I = 0; I < count_sums_.size(); ++I) count_sums_[I] += static_cast<double>(cells[I].count);
  ++count_samples_;
}

// delta y_I / lambda_I = sqrt(2) pi sigma^2 n_I delta y_I = N_I / (n-bar A lambda0), N_I the mean
// count since the edges were set.
double AdaptiveLayers::width_local(std::size_t I) const {
  if (!set_ || count_samples_ == 0) return std::nan("");
  const double mean_count = count_sums_[I] / static_cast<double>(count_samples_);
  return mean_count / (system_->number_density * system_->cross_section() * system_->mean_free_path0);
}

std::string AdaptiveLayers::widths_text(double t_end) const {
  if (!set_)
    return fmt("layers: the run ended at t = %.4g tau0, before system.layers.after = %.4g tau0: the layers stayed "
               "equal",
               t_end, p_->layers_after_tau0);
  double lo = INFINITY, hi = 0;
  for (std::size_t I = 0; I < system_->cells; ++I) {
    const double w = width_local(I);
    lo = std::min(lo, w);
    hi = std::max(hi, w);
  }
  return fmt("layers: %zu, set at t = %.4g tau0; widths in local mean free paths (mean densities over %llu moment "
             "updates since): %.3g to %.3g (target %.4g)",
             system_->cells, set_time_tau0_, static_cast<unsigned long long>(count_samples_), lo, hi,
             p_->layers_mean_free_paths);
}

void AdaptiveLayers::write(CaseOutput& out) const {
  if (!enabled_) return;
  const double lambda0 = system_->mean_free_path0;
  out.system["layers_target_mean_free_paths"] = p_->layers_mean_free_paths;
  out.system["layers_set_at_tau0"] = set_ ? set_time_tau0_ : std::nan("");
  if (p_->layers_max_width > 0) out.system["layers_max_width_lambda0"] = p_->layers_max_width / lambda0;
  ParticleDataset edges{"layer_edges", units::length,
                        "the edges of the collision layers along y (layers + 1 values from -Ly/2 to +Ly/2), set "
                        "at layers_set_at_tau0 from the transient's density profile (system.layers: "
                        "{mean_free_paths, after}; equal widths before)",
                        1, {}, ""};
  for (const double e : edges_) edges.data.push_back(e / lambda0);
  out.system_arrays.push_back(std::move(edges));
  ParticleDataset widths{"layer_width_local_mean_free_paths", units::dimensionless,
                         "each layer's width over its local mean free path, delta y_I / lambda_I with lambda_I = "
                         "1/(sqrt(2) pi n_I sigma^2) and n_I its mean density over the moment updates after the "
                         "edges were set (NaN if they never were)",
                         1, {}, ""};
  for (std::size_t I = 0; I < system_->cells; ++I) widths.data.push_back(width_local(I));
  out.system_arrays.push_back(std::move(widths));
}

void AdaptiveLayers::save(StateWriter& out) const {
  if (!enabled_) return;  // other runs' state is unchanged
  out.write("layers.edges", edges_);
  out.write("layers.profile", profile_);
  const std::uint64_t counts[3] = {set_, profile_samples_, count_samples_};
  out.write("layers.counts", counts, 3);
  out.write("layers.set_time", set_time_tau0_);
  out.write("layers.count_sums", count_sums_);
}

void AdaptiveLayers::load_entries(StateReader& in, std::vector<double>& edges) {
  std::vector<double> profile, sums;
  std::uint64_t counts[3];
  in.read("layers.edges", edges);
  in.read("layers.profile", profile);
  in.read("layers.counts", counts, 3);
  in.read("layers.set_time", set_time_tau0_);
  in.read("layers.count_sums", sums);
  if (edges.size() != edges_.size() || profile.size() != profile_.size() || sums.size() != count_sums_.size())
    throw StateError("checkpoint entries 'layers.*': " + std::to_string(edges.size()) + " edges, " +
                     std::to_string(profile.size()) + " profile bins and " + std::to_string(sums.size()) +
                     " layer counts where this run has " + std::to_string(edges_.size()) + ", " +
                     std::to_string(profile_.size()) + " and " + std::to_string(count_sums_.size()));
  profile_ = std::move(profile);
  count_sums_ = std::move(sums);
  set_ = counts[0] != 0;
  profile_samples_ = counts[1];
  count_samples_ = counts[2];
}

}  // namespace gdsmc::host
