// Lees-Edwards boundary along y (000 Eqs. 3.1, 4.11): periodic images sliding at +-aL/2 along x.
#include <cmath>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class LeesEdwards final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "lees_edwards";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Lees-Edwards boundary (000 Eqs. 3.1, 4.11): sliding periodic images for uniform shear flow u_x = a y";
  static constexpr const char* documentation =
      "Lees-Edwards generalized periodic boundary (paper 000, Sec. III and Eq. 4.11): the slab of width\n"
      "L = Ly is repeated along y, the images above and below moving with velocities +U and -U along\n"
      "x, U = a L, so that the laboratory flow settles on u_x = a y. In terms of the distribution\n"
      "(Eq. 3.1): f(y = +-L/2, v; t) = f(y = -+L/2, v -+ U x_hat; t).\n"
      "At the exact crossing time t of y = +L/2 (y_max) the particle re-enters at y = -L/2 with\n"
      "  v_x -> v_x - a L,   x -> x - (a L t mod Lx)   (Eq. 4.11 and the accumulated offset of the image),\n"
      "and at y = -L/2 (y_min) at y = +L/2 with the opposite signs; v_y, v_z and z are unchanged. The host\n"
      "then streams the remaining flight time of the step from the new plane and wraps x, z. Both y_min\n"
      "and y_max must be this plugin with the same shear rate (transfers() = true).\n"
      "Parameter shear_rate: a, any real number (negative: the opposite sense); a bare number is a tau0\n"
      "(a in units of 1/tau0), or give {value: X, unit: 1/tau0 | reduced}. Publishes 'shear_rate'\n"
      "(reduced units) for initial states (local_equilibrium, frame: laboratory) and diagnostics; do not\n"
      "combine it with the uniform_shear forcing, which shears the Lagrangian-frame state a second time.\n"
      "Conserves mass, the y and z momentum and the x momentum on average only: each crossing gives the\n"
      "gas -+ m a L along x and the energy (m/2)[(v_x -+ a L)^2 - v_x^2]; the net energy injected is the\n"
      "viscous heating -a Omega P_xy (000, after Eq. 3.1), which the host's tally of y_min and y_max\n"
      "records. A run with a body acceleration (a forcing that declares one) is refused: the images move\n"
      "with constant velocities +-aL/2 and are not accelerated, so with a body force Eq. 3.1 is no longer\n"
      "a symmetry of the flow.\n"
      "Mixtures (system.species): runs in them (gdsmc.species). The images slide with the same\n"
      "velocity +-aL for every species (Eq. 3.1 holds for each f_s), so the shift v_x -> v_x -+ a L\n"
      "does not involve the mass; a crossing of species s gives the gas -+ m_s a L along x and the\n"
      "energy (m_s/2)[(v_x -+ a L)^2 - v_x^2], which the host tallies mass-weighted per species.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("shear_rate", "imposed shear rate a (bare numbers: a tau0)")
                .unit(gdsmc::Dimension::inverse_time)};
  }
  explicit LeesEdwards(const gdsmc::Params& p) : a_(p.real("shear_rate")) {}

  // The boundary does not involve the particle's mass (see the documentation): runs in mixtures.
  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void publish(gdsmc::QuantityBoard& board) const override { board.publish("shear_rate", a_); }

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, const gdsmc::Vec3& g) override {
    if (g.x != 0.0 || g.y != 0.0 || g.z != 0.0)
      throw gdsmc::ParameterError(
          "shear_rate",
          "the Lees-Edwards boundary cannot be combined with a body acceleration (g = (" + gdsmc::value_text(g.x) + ", " +
              gdsmc::value_text(g.y) + ", " + gdsmc::value_text(g.z) +
              ")): its images move with the constant velocities +-aL/2 and are not accelerated, so with a "
              "body force the condition of 000 Eq. (3.1) is no longer a symmetry of the flow (the image "
              "system would be accelerated relative to the gas); remove the body_acceleration forcing or "
              "use walls");
  }

  bool transfers() const override { return true; }

  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng&) const override {
    const double length = ctx.system->box[1];
    const double slip = a_ * length;                                      // U = a L
    const double offset = std::fmod(slip * hit.time, ctx.system->box[0]);  // the image's x offset
    const double s = hit.side;                                            // +1: left through y_max
    hit.velocity.x -= s * slip;                                           // Eq. 4.11
    hit.position.x -= s * offset;
    gdsmc::transfer_to_opposite_plane(hit, length);
    return gdsmc::HitResult::transferred;
  }

 private:
  double a_;
};

}  // namespace

GDSMC_PLUGIN(LeesEdwards)
