// The stochastic (white-noise) thermostat of driven granular gases and mixtures: every particle
// receives an independent Gaussian velocity kick at every step, the same variance for every
// species (Barrat & Trizac, Granular Matter 4, 57 (2002); Henrique et al.; Williams & MacKintosh,
// PRE 54, R9 (1996)).
#include <cmath>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class WhiteNoiseThermostat final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "white_noise_thermostat";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Stochastic thermostat: Gaussian kicks of variance xi0^2 dt per component, the same for every species";
  static constexpr const char* documentation =
      "White-noise thermostat of the driven granular gas and mixture (Williams & MacKintosh, PRE 54,\n"
      "R9 (1996); Henrique et al.; Barrat & Trizac, Granular Matter 4, 57 (2002)): particle i of\n"
      "mass m_i feels the random force m_i xi_i(t) with\n"
      "<xi_ia(t) xi_jb(t')> = xi0^2 delta_ij delta_ab delta(t - t'), the same xi0^2 for every species.\n"
      "After the collisions of every step (Stage::after_collisions) each particle gets the kick\n"
      "  v_i <- v_i + d_i,   d_i = xi0 sqrt(dt) (G1, G2, G3),  G standard normals,\n"
      "drawn from the particle's own stream (Streams::for_particle(id)), so the result does not depend\n"
      "on the storage order or the threads. The step is exact in distribution for any dt (additive\n"
      "noise: two kicks of dt/2 make one of dt); order() = 1, the weak order of Euler-Maruyama.\n"
      "Heating: each species gains dT_s/dt = m_s xi0^2 (T_s = m_s <V^2>/3), i.e. the kinetic energy\n"
      "(3/2) m_s xi0^2 per particle and unit time: heavy particles are heated more, which is why a\n"
      "driven mixture does not reach equipartition (Barrat & Trizac 2002). With inelastic collisions\n"
      "the gas reaches the steady state where this heating balances the collisional cooling.\n"
      "remove_net_momentum (default true): the kicks of one step carry the net momentum\n"
      "P = sum_i m_i d_i, which would make the total momentum diffuse (<|P(t)|^2> = 3 xi0^2 t\n"
      "sum m_i^2) and give the gas a growing mean flow, while the theory of the driven steady state\n"
      "assumes zero mean flow. With it each kick is replaced by d_i - P / M (M = sum m_i), so the\n"
      "total momentum is conserved exactly (to round-off; conserves().momentum) and every species is\n"
      "still kicked with the same velocity noise; the mean energy input per unit time becomes\n"
      "(3/2) xi0^2 (M - sum m_i^2 / M), smaller by a relative O(1/N) (1/N in a one-species gas),\n"
      "and species s gains (3/2) m_s xi0^2 (1 - 2 m_s/M + sum m_i^2/M^2) per particle. With\n"
      "remove_net_momentum: false the kicks are independent and the input is (3/2) xi0^2 M.\n"
      "apply() returns the kinetic energy it added, sum_i (m_i/2)(v_i'^2 - v_i^2), mass-weighted in a\n"
      "mixture, and expected_energy_rate() declares the mean input above (checked by `gdsmc\n"
      "conformance`, forcing.expected_energy).\n"
      "Parameter xi0_squared: xi0^2 > 0, a velocity^2 per unit time; bare numbers are in units of\n"
      "T0/(m tau0), i.e. the heating rate dT/dt of a species of the reference mass in T0/tau0 (or\n"
      "give {value: X, unit: reduced | T0/(m*tau0) | lambda0^2/tau0^3}). Publishes\n"
      "'white_noise_strength' = xi0^2 (reduced units) for diagnostics. Runs in mixtures\n"
      "(gdsmc.species): species s of mass m_s = SystemInfo::species_mass(s).\n"
      "Measured: light and heavy (m = 4) species heated from rest gain 0.9989 and 1.0023 times\n"
      "(3/2) m_s xi0^2 (1 - 2 m_s/M + sum m_i^2/M^2) per particle (4e5 kicks each, 5 standard errors\n"
      "0.0065); with inelastic hard spheres (alpha = 0.8, x = 0.5, equal diameters) and xi0^2 = 0.5\n"
      "the steady state has T_heavy/T_light = 1.645 +- 0.02 (T_light = 4.44, T_heavy = 7.30 T0), the\n"
      "balance (3/2) m_s xi0^2 = -dE_s/dt|coll with Maxwellian species gives 1.647 (4.432, 7.300).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("xi0_squared",
                                   "noise strength xi0^2: each velocity component's kick has variance xi0^2 dt "
                                   "(bare numbers: T0/(m tau0))")
                .above(0.0)
                .unit(gdsmc::Dimensions{.time = -1, .temperature = 1, .mass = -1}),
            gdsmc::ParamSpec::boolean("remove_net_momentum",
                                      "subtract the kicks' net momentum sum m_i d_i / sum m_i from every kick, so that "
                                      "the total momentum stays exactly what it was")
                .default_value(true)};
  }
  explicit WhiteNoiseThermostat(const gdsmc::Params& p)
      : xi0_squared_(p.real("xi0_squared")), remove_net_momentum_(p.boolean("remove_net_momentum")) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }
  void publish(gdsmc::QuantityBoard& board) const override { board.publish("white_noise_strength", xi0_squared_); }
  Stage stage() const override { return Stage::after_collisions; }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const gdsmc::SystemInfo& sys = *ctx.system;
    const double kick = std::sqrt(xi0_squared_ * ctx.dt);  // standard deviation of each component
    if (!(kick > 0) || p.count == 0) return 0.0;
    double added = 0, mass = 0;
    double kick_momentum[3] = {0, 0, 0}, momentum[3] = {0, 0, 0};  // sum m_i d_i; sum m_i v_i after the kicks
    for (std::size_t i = 0; i < p.count; ++i) {
      gdsmc::Rng rng = ctx.streams->for_particle(p.id[i]);
      const double m = sys.species_mass(p.species_of(i));
      const double dx = kick * rng.normal(), dy = kick * rng.normal(), dz = kick * rng.normal();
      // (m/2)((v + d)^2 - v^2) = m (v.d + d^2/2), from the kick itself (no cancellation)
      added += m * (p.vx[i] * dx + p.vy[i] * dy + p.vz[i] * dz + 0.5 * (dx * dx + dy * dy + dz * dz));
      p.vx[i] += dx;
      p.vy[i] += dy;
      p.vz[i] += dz;
      mass += m;
      kick_momentum[0] += m * dx;
      kick_momentum[1] += m * dy;
      kick_momentum[2] += m * dz;
      momentum[0] += m * p.vx[i];
      momentum[1] += m * p.vy[i];
      momentum[2] += m * p.vz[i];
    }
    if (!remove_net_momentum_) return added;
    // Every kick becomes d_i - Delta, Delta = sum m_i d_i / M: the total momentum is unchanged.
    const double delta[3] = {kick_momentum[0] / mass, kick_momentum[1] / mass, kick_momentum[2] / mass};
    for (std::size_t i = 0; i < p.count; ++i) {
      p.vx[i] -= delta[0];
      p.vy[i] -= delta[1];
      p.vz[i] -= delta[2];
    }
    // sum (m_i/2)((w_i - Delta)^2 - w_i^2) = -Delta . sum m_i w_i + M Delta^2 / 2, w_i the kicked velocity
    const double delta_square = delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2];
    return added - (delta[0] * momentum[0] + delta[1] * momentum[1] + delta[2] * momentum[2]) + 0.5 * mass * delta_square;
  }

  // The mean of what apply() returns per unit time, given the masses of `particles`:
  // (3/2) xi0^2 M, or (3/2) xi0^2 (M - sum m_i^2 / M) with remove_net_momentum.
  bool expected_energy_rate(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p, double& rate) const override {
    double mass = 0, square = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      const double m = ctx.system->species_mass(p.species_of(i));
      mass += m;
      square += m * m;
    }
    rate = 1.5 * xi0_squared_ * (remove_net_momentum_ && mass > 0 ? mass - square / mass : mass);
    return true;
  }
  gdsmc::Conservation conserves() const override { return {remove_net_momentum_, false}; }
  int order() const override { return 1; }

 private:
  double xi0_squared_;
  bool remove_net_momentum_;
};

}  // namespace

GDSMC_PLUGIN(WhiteNoiseThermostat)
