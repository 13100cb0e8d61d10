// The anti-drag force (1/2) zeta m V that gives back the energy the collisions dissipated
// (paper 002, Eq. 15, first term; zeta of Eq. 6 measured in the run).
#include <cmath>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class AntiDrag final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "anti_drag";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Anti-drag F = (1/2) zeta m V compensating the collisional cooling, zeta measured every step (002 Eq. 15)";
  static constexpr const char* documentation =
      "The deterministic part of paper 002's Eq. (15): the non-conservative force F = (1/2) zeta m V\n"
      "(V relative to the mean velocity), whose heating rate gamma = zeta exactly compensates the\n"
      "collisional cooling, so that the temperature obeys dT/dt = -(2/3n) a P_xy (Eq. 4 with\n"
      "gamma = zeta). zeta is measured self-consistently every step: the energy the collisions of this\n"
      "step dissipated, dE = zeta (3/2) N T dt (Eq. 6), is the increase of the collision rule's tally\n"
      "'dissipated_energy' (enskog_hard_spheres), or, for a rule without that tally, minus the\n"
      "kinetic-energy change the collisions declared (inelastic_hard_spheres, where they are the\n"
      "same). The force over the step, V <- u + exp(zeta dt/2) (V - u), is applied as the factor\n"
      "sqrt(1 + dE/E) with E = (m/2) sum (V - u)^2, which gives back dE exactly. Runs after the\n"
      "collisions (stage after_collisions), before hcs_replacement if both are used (002 Sec. 3).\n"
      "Conserves momentum (scaling about the mean), not energy; returns dE to the energy ledger.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit AntiDrag(const gdsmc::Params&) {}

  Stage stage() const override { return Stage::after_collisions; }
  gdsmc::Conservation conserves() const override { return {true, false}; }
  int order() const override { return 0; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    cooling_.update(ctx, p.count);
    const double dissipated = cooling_.dissipated_energy;
    if (dissipated == 0 || p.count < 2) return 0.0;
    double u[3];
    gdsmc::velocity_sums(p).mean(u);
    double energy = 0;  // (1/2) sum (V - u)^2, m = 1
    for (std::size_t i = 0; i < p.count; ++i) {
      const double dx = p.vx[i] - u[0], dy = p.vy[i] - u[1], dz = p.vz[i] - u[2];
      energy += 0.5 * (dx * dx + dy * dy + dz * dz);
    }
    if (!(energy > 0)) return 0.0;
    const double factor = std::sqrt(std::max(0.0, 1.0 + dissipated / energy));  // exp(zeta dt / 2)
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] = u[0] + factor * (p.vx[i] - u[0]);
      p.vy[i] = u[1] + factor * (p.vy[i] - u[1]);
      p.vz[i] = u[2] + factor * (p.vz[i] - u[2]);
    }
    return (factor * factor - 1.0) * energy;
  }
  // Checkpoints: the running totals this step's dissipation is the difference from.
  void save_state(gdsmc::StateWriter& out) const override { cooling_.save(out, "cooling"); }
  void load_state(gdsmc::StateReader& in) override { cooling_.load(in, "cooling"); }

 private:
  gdsmc::StepCooling cooling_;  // what this step's collisions dissipated
};

}  // namespace

GDSMC_PLUGIN(AntiDrag)
