// A constant body acceleration g (gravity, a pressure gradient): the driving of Poiseuille flow (004).
#include <cmath>
#include <string>

#include <gdsmc/gdsmc.hpp>

namespace {

class BodyAcceleration final : public gdsmc::Forcing {
 public:
  static constexpr const char* name = "body_acceleration";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Constant body acceleration g along x, y or z (gravity-driven Poiseuille flow, 004 Sec. III)";
  static constexpr const char* documentation =
      "A constant acceleration g = a e_axis acting on every particle (a body force m g per particle):\n"
      "the driving of the granular Poiseuille flow of paper 004 (Sec. III; its dimensionless\n"
      "acceleration is a_hat = a W / (2 T_w/m), Eq. 17, with W = Ly the channel width). The forcing\n"
      "declares g (Forcing::acceleration), and the host integrates it exactly during free flight,\n"
      "x += v t + g t^2/2, v += g t, across wall hits too (004 Eqs. 10-12); it then never calls\n"
      "apply(). apply() alone (e.g. in a homogeneous system) performs v += g dt for every particle and\n"
      "returns the energy it added, sum over particles of m (g.v dt + g^2 dt^2 / 2) with v before the\n"
      "step: exact for the force alone, so order() = 0.\n"
      "Parameters: acceleration a, any real (the sign gives the sense along the axis); a bare number\n"
      "is in units of 2 T0 / (m lambda0), or give {value: X, unit: 2T0/(m*lambda0) | reduced}; so\n"
      "a_hat = a (Ly / lambda0) (T0 / T_w) for a bare a. axis: x (default, along the walls), y or z.\n"
      "Publishes 'body_acceleration' = |g| (reduced units). Conserves neither momentum (it adds\n"
      "N m g per unit time) nor energy (power m g . sum v). The lees_edwards boundary refuses to run\n"
      "with it.\n"
      "Mixtures (system.species): runs in them (gdsmc.species). The acceleration g is the same for\n"
      "every species (gravity, or the pressure-gradient body force of 004 applied as a force m_s g\n"
      "on a particle of mass m_s), and the host's exact free flight does not involve the mass. In a\n"
      "mixture apply() returns the mass-weighted energy sum_i m_i (g.v_i dt + g^2 dt^2 / 2); in a\n"
      "one-species run its arithmetic is unchanged (m = 1).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("acceleration", "acceleration a along the axis (bare numbers: units of 2 T0/(m lambda0))")
                .unit(gdsmc::Dimension::acceleration),
            gdsmc::ParamSpec::choice("axis", {"x", "y", "z"}, "direction of the acceleration").default_value("x")};
  }
  explicit BodyAcceleration(const gdsmc::Params& p) : axis_(axis_index(p.string("axis"))), a_(p.real("acceleration")) {
    (axis_ == 0 ? g_.x : axis_ == 1 ? g_.y : g_.z) = a_;
  }

  // The same acceleration for every species, energy weighed by m_i in apply(): runs in mixtures.
  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void publish(gdsmc::QuantityBoard& board) const override { board.publish("body_acceleration", gdsmc::norm(g_)); }

  bool acceleration(gdsmc::Vec3& g) const override {
    g = g_;
    return true;
  }

  double apply(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double dv = a_ * ctx.dt;  // g dt along the axis
    const gdsmc::Column<double> v = axis_ == 0 ? p.vx : axis_ == 1 ? p.vy : p.vz;
    const gdsmc::SystemInfo& sys = *ctx.system;
    if (sys.species_count > 1 || sys.species_mass(0) != sys.mass) {
      // sum of (m_i/2)[(v_i + g dt)^2 - v_i^2] = g dt sum m_i v_i + (g dt)^2 sum m_i / 2
      double momentum = 0, mass = 0;
      for (std::size_t i = 0; i < p.count; ++i) {
        const double m = sys.species_mass(p.species_of(i));
        momentum += m * v[i];
        mass += m;
        v[i] += dv;
      }
      return dv * momentum + 0.5 * mass * dv * dv;
    }
    double sum_v = 0;
    for (std::size_t i = 0; i < p.count; ++i) {
      sum_v += v[i];
      v[i] += dv;
    }
    // sum of (1/2)[(v + g dt)^2 - v^2] = g dt sum v + N (g dt)^2 / 2   (m = 1)
    return dv * sum_v + 0.5 * static_cast<double>(p.count) * dv * dv;
  }
  gdsmc::Conservation conserves() const override { return {}; }
  int order() const override { return 0; }

 private:
  static int axis_index(const std::string& a) { return a == "x" ? 0 : a == "y" ? 1 : 2; }
  int axis_;      // 0, 1, 2: x, y, z
  double a_;      // the component of g along the axis
  gdsmc::Vec3 g_{0, 0, 0};
};

}  // namespace

GDSMC_PLUGIN(BodyAcceleration)
