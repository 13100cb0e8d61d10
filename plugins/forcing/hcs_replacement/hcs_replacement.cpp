// The stochastic term (1/2) zeta (f - f^(0)) of paper 002, Eq. (15): velocities replaced by draws
// from a homogeneous cooling state kept alongside (002 Sec. 3).
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class HcsReplacement final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "hcs_replacement";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Replaces a fraction zeta dt/2 of the velocities by sqrt(T) C, C from an HCS reservoir at unit temperature (002 Eq. 15)";
  static constexpr const char* documentation =
      "The stochastic part of paper 002's Eq. (15), (1/2) zeta (f - f^(0)): each particle has the\n"
      "probability (1/2) zeta per unit time of getting a new velocity V_new = u + sqrt(T/m) C, with u and\n"
      "T the mean velocity and temperature of the gas at that moment and C the velocity of a particle\n"
      "of a reservoir kept in the homogeneous cooling state (HCS) at unit temperature (Sec. 3). zeta is\n"
      "measured in the run as anti_drag does (the increase of the tally 'dissipated_energy' over this\n"
      "step, or minus the declared collisional energy change: zeta dt = dE / ((3/2) N T)); per step\n"
      "round(N zeta dt / 2) particles (stochastically rounded) are picked uniformly, with replacement.\n"
      "The reservoir is a real HCS, not a Maxwellian stand-in: `reservoir_particles` particles, started\n"
      "Maxwellian and relaxed by `reservoir_relaxation` collisions per particle of inelastic hard spheres\n"
      "with the restitution alpha the collision rule publishes, then advanced every step by as many\n"
      "collisions per particle as the gas had in that step, and rescaled to zero mean and unit\n"
      "temperature after each advance (the HCS is self-similar: its scaled form is stationary). The\n"
      "packing fraction does not matter: in a homogeneous state the Enskog operator is chi times the\n"
      "Boltzmann one, which changes the collision rate but not the scaled HCS, so the Boltzmann IHS\n"
      "reservoir has the Enskog HCS shape (the cumulant a2 of 002 Eq. 18 does not depend on phi).\n"
      "The reservoir collisions pick pairs uniformly and accept with probability |g|/w (w a majorant\n"
      "raised when exceeded), sigma_hat from Theta(g.s)(g.s), so accepted collisions follow the\n"
      "hard-sphere rate. Streams: for_unit(0) the reservoir, for_unit(1) the replacements. Runs after\n"
      "the collisions and after anti_drag. Conserves momentum and energy only on average; returns the\n"
      "energy it added to the ledger.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::integer("reservoir_particles", "particles of the HCS reservoir").range(1000.0, 2e5).default_value(20000),
            gdsmc::ParamSpec::real("reservoir_relaxation", "collisions per reservoir particle before the first draw")
                .range(1.0, 100.0)
                .default_value(50.0)};
  }
  explicit HcsReplacement(const gdsmc::Params& p)
      : size_(static_cast<std::size_t>(p.integer("reservoir_particles"))), relaxation_(p.real("reservoir_relaxation")) {}

  Stage stage() const override { return Stage::after_collisions; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    if (!reservoir_.started()) start_reservoir(ctx);
    cooling_.update(ctx, p.count);
    gdsmc::Rng reservoir_rng = ctx.streams->for_unit(0);
    reservoir_.advance(cooling_.collisions_per_particle, reservoir_rng);
    if (!(cooling_.dissipated_energy > 0) || p.count < 2) return 0.0;

    const gdsmc::VelocitySums sums = gdsmc::velocity_sums(p);
    double u[3];
    sums.mean(u);
    const double n = static_cast<double>(p.count), sum2 = sums.square;
    const double temperature = (sum2 / n - (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])) / 3.0;  // m = 1
    if (!(temperature > 0)) return 0.0;
    // (1/2) zeta dt N = dE / (3 T), with zeta dt = dE / ((3/2) N T).
    gdsmc::Rng rng = ctx.streams->for_unit(1);
    auto count = cooling_.half_zeta_events(temperature, rng);  // (zeta dt / 2) N
    const double scale = std::sqrt(temperature);
    double energy = 0;
    for (std::uint64_t k = 0; k < count; ++k) {
      const std::uint32_t i = rng.below(static_cast<std::uint32_t>(p.count));
      const gdsmc::Vec3 c = reservoir_.draw(rng);
      const double nx = u[0] + scale * c.x, ny = u[1] + scale * c.y, nz = u[2] + scale * c.z;
      energy += 0.5 * (nx * nx + ny * ny + nz * nz - p.vx[i] * p.vx[i] - p.vy[i] * p.vy[i] - p.vz[i] * p.vz[i]);
      p.vx[i] = nx;
      p.vy[i] = ny;
      p.vz[i] = nz;
    }
    return energy;
  }
  // Checkpoints: the reservoir (empty before the first apply, which starts it) and the running
  // totals of the collisions.
  void save_state(gdsmc::StateWriter& out) const override {
    reservoir_.save(out, "reservoir");
    cooling_.save(out, "cooling");
  }
  void load_state(gdsmc::StateReader& in) override {
    reservoir_.load(in, "reservoir", size_);
    cooling_.load(in, "cooling");
  }

 private:
  void start_reservoir(const gdsmc::StepContext& ctx) {
    const double* alpha = ctx.quantities ? ctx.quantities->find("restitution") : nullptr;
    if (!alpha)
      throw std::runtime_error("hcs_replacement needs the restitution of the HCS reservoir: the collision rule must "
                               "publish 'restitution' (inelastic_hard_spheres and enskog_hard_spheres do)");
    gdsmc::Rng rng = ctx.streams->for_unit(2);
    reservoir_.start(size_, *alpha, relaxation_, rng);
  }

  std::size_t size_;
  double relaxation_;
  gdsmc::HcsReservoir reservoir_;  // f^(0) at unit temperature
  gdsmc::StepCooling cooling_;  // what this step's collisions dissipated
};

}  // namespace

GDSMC_PLUGIN(HcsReplacement)
