// gdsmc SDK: a homogeneous cooling state (HCS) of inelastic hard spheres kept beside the gas, in
// its scaled form (zero mean, unit temperature), as a source of draws from f^(0) (001 Eq. 2.8).
// Header-only: plugins that need f^(0) (002's hcs_replacement, 001's cloning_annihilation) share it,
// with StepCooling, what the step's collisions dissipated, which they and anti_drag follow.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gdsmc/collision.hpp"
#include "gdsmc/context.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/state.hpp"
#include "gdsmc/vec3.hpp"

namespace gdsmc {

class HcsReservoir {
 public:
  // `size` particles, started Maxwellian from `rng` and relaxed by `relaxation` collisions per
  // particle of inelastic hard spheres with restitution `alpha`, rescaled after each one.
  void start(std::size_t size, double alpha, double relaxation, Rng& rng) {
    cx_.assign(size, 0.0);
    cy_.assign(size, 0.0);
    cz_.assign(size, 0.0);
    half_one_plus_alpha_ = 0.5 * (1.0 + alpha);
    for (std::size_t k = 0; k < size; ++k) {
      cx_[k] = rng.normal();
      cy_[k] = rng.normal();
      cz_[k] = rng.normal();
    }
    rescale();
    // In chunks of one collision per particle, rescaling in between (the HCS cools).
    for (double done = 0; done < relaxation; done += 1.0) advance(std::min(1.0, relaxation - done), rng);
  }
  bool started() const { return !cx_.empty(); }
  std::size_t size() const { return cx_.size(); }
  Vec3 velocity(std::size_t k) const { return {cx_[k], cy_[k], cz_[k]}; }
  // Checkpoints: the whole reservoir (its velocities, majorant and owed collisions), under `prefix`.
  void save(StateWriter& out, const std::string& prefix) const {
    out.write(prefix + ".cx", cx_);
    out.write(prefix + ".cy", cy_);
    out.write(prefix + ".cz", cz_);
    const double scalars[3] = {half_one_plus_alpha_, majorant_, owed_};
    out.write(prefix + ".scalars", scalars, 3);
  }
  // `size`: the reservoir's size as the plugin's parameters set it (a started reservoir of
  // another size is refused).
  void load(StateReader& in, const std::string& prefix, std::size_t size) {
    in.read(prefix + ".cx", cx_);
    in.read(prefix + ".cy", cy_);
    in.read(prefix + ".cz", cz_);
    if (cy_.size() != cx_.size() || cz_.size() != cx_.size())
      throw StateError("checkpoint entry '" + prefix + "': velocity components of different lengths");
    if (!cx_.empty() && cx_.size() != size)
      throw StateError("checkpoint entry '" + prefix + ".cx': " + std::to_string(cx_.size()) +
                       " reservoir particles where the plugin's parameters give " + std::to_string(size));
    double scalars[3];
    in.read(prefix + ".scalars", scalars, 3);
    half_one_plus_alpha_ = scalars[0];
    majorant_ = scalars[1];
    owed_ = scalars[2];
  }
  // A velocity drawn uniformly from the reservoir.
  Vec3 draw(Rng& rng) const { return velocity(rng.below(static_cast<std::uint32_t>(cx_.size()))); }

  // `ds` more collisions per particle (s counted as the host does: accepted pairs over N), then
  // rescale to zero mean and unit temperature (the HCS is self-similar: its scaled form is
  // stationary). Pairs are picked uniformly and accepted with probability |g|/w, w a majorant of
  // |g| raised when exceeded; sigma_hat from Theta(g.s)(g.s): the hard-sphere rate.
  void advance(double ds, Rng& rng) {
    owed_ += ds * static_cast<double>(cx_.size());
    const auto n = static_cast<std::uint32_t>(cx_.size());
    while (owed_ >= 1.0) {
      const std::uint32_t i = rng.below(n);
      std::uint32_t j = rng.below(n - 1);
      j += (j >= i);
      const Vec3 g{cx_[i] - cx_[j], cy_[i] - cy_[j], cz_[i] - cz_[j]};
      const double gn = norm(g);
      if (gn > majorant_) majorant_ = 1.05 * gn;
      if (rng.uniform() * majorant_ >= gn) continue;
      const Vec3 s = hard_sphere_impact_direction(g, gn, rng);
      const Vec3 dv = (half_one_plus_alpha_ * dot(g, s)) * s;
      cx_[i] -= dv.x; cy_[i] -= dv.y; cz_[i] -= dv.z;
      cx_[j] += dv.x; cy_[j] += dv.y; cz_[j] += dv.z;
      owed_ -= 1.0;
    }
    rescale();
  }

 private:
  void rescale() {
    const double n = static_cast<double>(cx_.size());
    double u[3] = {0, 0, 0}, sum2 = 0;
    for (std::size_t k = 0; k < cx_.size(); ++k) {
      u[0] += cx_[k];
      u[1] += cy_[k];
      u[2] += cz_[k];
    }
    for (double& c : u) c /= n;
    for (std::size_t k = 0; k < cx_.size(); ++k) {
      cx_[k] -= u[0];
      cy_[k] -= u[1];
      cz_[k] -= u[2];
      sum2 += cx_[k] * cx_[k] + cy_[k] * cy_[k] + cz_[k] * cz_[k];
    }
    const double f = 1.0 / std::sqrt(sum2 / (3.0 * n));
    for (std::size_t k = 0; k < cx_.size(); ++k) {
      cx_[k] *= f;
      cy_[k] *= f;
      cz_[k] *= f;
    }
  }

  std::vector<double> cx_, cy_, cz_;  // unit temperature, zero mean
  double half_one_plus_alpha_ = 1.0;
  double majorant_ = 6.0 * M_SQRT2;  // of |g| at unit temperature (raised when exceeded)
  double owed_ = 0;                  // accepted collisions still owed
};

// What the collisions of the step just taken did, for forcings that compensate or follow the
// cooling (002 Eq. 15, 001 Eq. 3.17): the energy they dissipated -- the increase of the rule's tally
// "dissipated_energy", or minus the kinetic-energy change the collisions declared (the same for
// inelastic_hard_spheres) -- and the collisions per particle s. Call update() once per step.
class StepCooling {
 public:
  double dissipated_energy = 0;        // dE of this step (m = 1)
  double collisions_per_particle = 0;  // ds of this step

  void update(const StepContext& ctx, std::size_t particles) {
    const double* tally = ctx.collision_tally("dissipated_energy");
    const double total = tally ? *tally : -ctx.collision_energy_change;
    dissipated_energy = total - last_dissipated_;
    last_dissipated_ = total;
    collisions_per_particle =
        particles ? static_cast<double>(ctx.collisions - last_collisions_) / static_cast<double>(particles) : 0.0;
    last_collisions_ = ctx.collisions;
  }
  // Checkpoints: the running totals the next step's differences are taken from.
  void save(StateWriter& out, const std::string& prefix) const {
    out.write(prefix + ".last_dissipated", last_dissipated_);
    out.write(prefix + ".last_collisions", last_collisions_);
    const double current[2] = {dissipated_energy, collisions_per_particle};
    out.write(prefix + ".current", current, 2);
  }
  void load(StateReader& in, const std::string& prefix) {
    in.read(prefix + ".last_dissipated", last_dissipated_);
    in.read(prefix + ".last_collisions", last_collisions_);
    double current[2];
    in.read(prefix + ".current", current, 2);
    dissipated_energy = current[0];
    collisions_per_particle = current[1];
  }
  // (zeta dt / 2) N = dE / (3 T) (zeta dt = dE / ((3/2) N T), m = 1): the expected number of the
  // step's events of rate zeta/2 per particle, stochastically rounded with one draw of `rng`.
  std::uint64_t half_zeta_events(double temperature, Rng& rng) const {
    const double expected = dissipated_energy / (3.0 * temperature);
    auto count = static_cast<std::uint64_t>(expected);
    if (rng.uniform() < expected - static_cast<double>(count)) ++count;
    return count;
  }

 private:
  double last_dissipated_ = 0;
  std::uint64_t last_collisions_ = 0;
};

}  // namespace gdsmc
