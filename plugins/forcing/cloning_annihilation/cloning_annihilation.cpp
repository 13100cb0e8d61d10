// The stochastic term (1/2) zeta (f - f^(0)) of paper 001's Eq. 3.17: each particle is cloned at
// the rate zeta/2 and annihilated at the rate (zeta/2) f^(0)/f, the annihilation done by removing
// the particle nearest in velocity to a draw from an HCS reservoir (docs/heat-flux-kappa.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

// Particles binned on a uniform grid in velocity space, for nearest-neighbour queries.
class VelocityGrid {
 public:
  void build(const gdsmc::ParticleSpan& p, std::size_t cells_per_axis) {
    g_ = cells_per_axis;
    const gdsmc::Column<double> v[3] = {p.vx, p.vy, p.vz};
    for (int d = 0; d < 3; ++d) {
      double lo = v[d][0], hi = v[d][0];
      for (std::size_t i = 1; i < p.count; ++i) lo = std::min(lo, v[d][i]), hi = std::max(hi, v[d][i]);
      lo_[d] = lo;
      width_[d] = std::max((hi - lo) / static_cast<double>(g_), 1e-300) * (1.0 + 1e-12);
    }
    cell_of_.resize(p.count);
    start_.assign(g_ * g_ * g_ + 1, 0);
    for (std::size_t i = 0; i < p.count; ++i) {
      const std::size_t c = index(clamp_cell(p.vx[i], 0), clamp_cell(p.vy[i], 1), clamp_cell(p.vz[i], 2));
      cell_of_[i] = static_cast<std::uint32_t>(c);
      ++start_[c + 1];
    }
    for (std::size_t c = 0; c < g_ * g_ * g_; ++c) start_[c + 1] += start_[c];
    order_.resize(p.count);
    fill_ = start_;
    for (std::size_t i = 0; i < p.count; ++i) order_[fill_[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }

  // The particle nearest to r (Euclidean, in velocity) among those with usable[i] != 0; the
  // search widens shell by shell until no unexamined cell can hold a nearer one.
  std::uint32_t nearest(const gdsmc::ParticleSpan& p, const gdsmc::Vec3& r, const std::vector<std::uint8_t>& usable) const {
    const double q[3] = {r.x, r.y, r.z};
    long qc[3];
    for (int d = 0; d < 3; ++d) qc[d] = clamp_cell(q[d], d);
    const long g = static_cast<long>(g_);
    double best = INFINITY;
    std::uint32_t best_i = UINT32_MAX;
    for (long k = 0;; ++k) {
      const long x0 = std::max(qc[0] - k, 0L), x1 = std::min(qc[0] + k, g - 1);
      const long y0 = std::max(qc[1] - k, 0L), y1 = std::min(qc[1] + k, g - 1);
      const long z0 = std::max(qc[2] - k, 0L), z1 = std::min(qc[2] + k, g - 1);
      for (long x = x0; x <= x1; ++x)
        for (long y = y0; y <= y1; ++y)
          for (long z = z0; z <= z1; ++z) {
            if (std::max({std::labs(x - qc[0]), std::labs(y - qc[1]), std::labs(z - qc[2])}) != k) continue;
            const std::size_t c = index(static_cast<std::size_t>(x), static_cast<std::size_t>(y), static_cast<std::size_t>(z));
            for (std::uint32_t s = start_[c]; s < start_[c + 1]; ++s) {
              const std::uint32_t i = order_[s];
              if (!usable[i]) continue;
              const double dx = p.vx[i] - q[0], dy = p.vy[i] - q[1], dz = p.vz[i] - q[2];
              const double d2 = dx * dx + dy * dy + dz * dz;
              if (d2 < best) {
                best = d2;
                best_i = i;
              }
            }
          }
      // Every particle outside the cube of cells [qc - k, qc + k] is at least `bound` away.
      double bound = INFINITY;
      for (int d = 0; d < 3; ++d) {
        if (qc[d] - k > 0) bound = std::min(bound, q[d] - (lo_[d] + static_cast<double>(qc[d] - k) * width_[d]));
        if (qc[d] + k < g - 1) bound = std::min(bound, lo_[d] + static_cast<double>(qc[d] + k + 1) * width_[d] - q[d]);
      }
      if (bound == INFINITY) return best_i;  // the cube is the whole grid
      if (best_i != UINT32_MAX && best <= bound * bound) return best_i;
    }
  }

 private:
  long clamp_cell(double v, int d) const {
    const double f = (v - lo_[d]) / width_[d];
    if (!(f > 0)) return 0;
    return std::min(static_cast<long>(f), static_cast<long>(g_) - 1);
  }
  std::size_t index(std::size_t x, std::size_t y, std::size_t z) const { return (x * g_ + y) * g_ + z; }

  std::size_t g_ = 0;
  double lo_[3] = {0, 0, 0}, width_[3] = {1, 1, 1};
  std::vector<std::uint32_t> cell_of_, start_, fill_, order_;
};

class CloningAnnihilation final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "cloning_annihilation";
  static constexpr const char* version = "1.1.1";
  static constexpr const char* summary =
      "Clones at rate zeta/2 and annihilates at rate (zeta/2) f0/f, f0 from an HCS reservoir (001 Eq. 3.17)";
  static constexpr const char* documentation =
      "The anomalous term (1/2) zeta (f - f0) of paper 001's Eq. (3.17), which with heat_flux_force\n"
      "(route: kappa) and energy_momentum_thermostat makes the steady state the Navier-Stokes\n"
      "distribution of the thermal conductivity kappa (Eq. 2.28) instead of kappa' (Eq. 2.30): \"a\n"
      "particle of a given velocity V has a probability per unit time zeta/2 of being cloned and a\n"
      "probability per unit time (zeta/2) f0(V)/f(V) of being annihilated\" (Sec. III.B).\n"
      "Algorithm (derivation in docs/heat-flux-kappa.md): per step, M = (zeta dt / 2) N events\n"
      "(stochastically rounded; zeta dt = dE / ((3/2) N T), dE the energy the collisions of the step\n"
      "dissipated, from the tally 'dissipated_energy' or minus the declared collisional energy\n"
      "change). Each event picks a particle a uniformly (cloning: rate zeta/2 per particle, the\n"
      "+(zeta/2) f term), draws C from a reservoir in the homogeneous cooling state at unit\n"
      "temperature (gdsmc::HcsReservoir, as hcs_replacement) and the point r = u + sqrt(T/m) C, and\n"
      "overwrites the velocity of the particle b nearest to r in velocity space with that of a. The\n"
      "particle b is thereby annihilated with probability (zeta dt/2) N times the f0-mass of its\n"
      "Voronoi cell, ~ (zeta dt/2) f0(V_b)/f(V_b) (the cell's volume is 1/(N f) on average): the\n"
      "-(zeta/2) f0 term, with no estimate of f needed. N is unchanged; momentum and energy change\n"
      "only by fluctuations (f and f0 share n, u, T), which energy_momentum_thermostat removes.\n"
      "A particle overwritten in a step is not annihilated again in that step. Nearest neighbours come\n"
      "from a uniform grid of N^(1/3) cells per axis (at least 4, at most 128) over the particles'\n"
      "velocity range, rebuilt each step that has events, searched shell by shell until the nearest\n"
      "is proved.\n"
      "Order in the step: collisions, heat_flux_force, this, energy_momentum_thermostat. Streams:\n"
      "for_unit(0) the reservoir's collisions, for_unit(1) the events, for_unit(2) the reservoir's\n"
      "start. Returns the energy it added (m = 1).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("reservoir_particles", "particles of the HCS reservoir").range(1000.0, 1e6).default_value(50000),
            gdsmc::ParamSpec::real("reservoir_relaxation", "collisions per reservoir particle before the first draw")
                .range(1.0, 100.0)
                .default_value(50.0)};
  }
  explicit CloningAnnihilation(const gdsmc::Params& p)
      : size_(static_cast<std::size_t>(p.integer("reservoir_particles"))), relaxation_(p.real("reservoir_relaxation")) {}

  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {}; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (!reservoir_.started()) {
      const double* alpha = ctx.quantities ? ctx.quantities->find("restitution") : nullptr;
      if (!alpha)
        throw std::runtime_error("cloning_annihilation needs the restitution of the HCS reservoir: the collision rule "
                                 "must publish 'restitution' (inelastic_hard_spheres does)");
      gdsmc::Rng start = ctx.streams->for_unit(2);
      reservoir_.start(size_, *alpha, relaxation_, start);
    }
    if (usable_.size() != p.count) {  // the first apply, also after a resume (scratch, not saved)
      usable_.assign(p.count, 1);
      touched_.reserve(p.count / 2);  // at most N/2 events per step: no allocation in the step loop
    }
    cooling_.update(ctx, p.count);
    gdsmc::Rng reservoir_rng = ctx.streams->for_unit(0);
    reservoir_.advance(cooling_.collisions_per_particle, reservoir_rng);
    if (!(cooling_.dissipated_energy > 0) || p.count < 2) return 0.0;

    double u[3];
    gdsmc::velocity_sums(p).mean(u);
    const double n = static_cast<double>(p.count);
    const double sum2 = gdsmc::peculiar_square_sum(p, u);
    const double temperature = sum2 / (3.0 * n);  // m = 1
    if (!(temperature > 0)) return 0.0;
    gdsmc::Rng rng = ctx.streams->for_unit(1);
    auto events = cooling_.half_zeta_events(temperature, rng);  // (zeta dt / 2) N
    if (events == 0) return 0.0;
    events = std::min<std::uint64_t>(events, p.count / 2);  // a step this coarse is refused by the host long before

    grid_.build(p, std::clamp<std::size_t>(static_cast<std::size_t>(std::cbrt(n)), 4, 128));
    const double scale = std::sqrt(temperature);
    double energy = 0;
    touched_.clear();
    for (std::uint64_t e = 0; e < events; ++e) {
      const std::uint32_t a = rng.below(static_cast<std::uint32_t>(p.count));  // cloned: rate zeta/2
      const gdsmc::Vec3 c = reservoir_.draw(rng);
      const gdsmc::Vec3 r{u[0] + scale * c.x, u[1] + scale * c.y, u[2] + scale * c.z};
      const std::uint32_t b = grid_.nearest(p, r, usable_);  // annihilated: rate (zeta/2) f0/f
      usable_[b] = 0;
      touched_.push_back(b);
      energy += 0.5 * (p.vx[a] * p.vx[a] + p.vy[a] * p.vy[a] + p.vz[a] * p.vz[a] - p.vx[b] * p.vx[b] -
                       p.vy[b] * p.vy[b] - p.vz[b] * p.vz[b]);
      p.vx[b] = p.vx[a];
      p.vy[b] = p.vy[a];
      p.vz[b] = p.vz[a];
    }
    for (std::uint32_t b : touched_) usable_[b] = 1;
    return energy;
  }
  // Checkpoints: the reservoir (empty before the first apply, which starts it) and the running
  // totals of the collisions. The grid and usable_/touched_ are scratch of one step.
  void save_state(gdsmc::StateWriter& out) const override {
    reservoir_.save(out, "reservoir");
    cooling_.save(out, "cooling");
  }
  void load_state(gdsmc::StateReader& in) override {
    reservoir_.load(in, "reservoir", size_);
    cooling_.load(in, "cooling");
  }

 private:
  std::size_t size_;
  double relaxation_;
  gdsmc::HcsReservoir reservoir_;  // f0 at unit temperature
  VelocityGrid grid_;                   // rebuilt by each step that has events
  std::vector<std::uint8_t> usable_;    // 0: annihilated already in this step (all 1 between steps)
  std::vector<std::uint32_t> touched_;  // the particles annihilated in this step
  gdsmc::StepCooling cooling_;  // what this step's collisions dissipated
};

}  // namespace

GDSMC_PLUGIN(CloningAnnihilation)
