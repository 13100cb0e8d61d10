// Granular temperature of the whole system.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class Temperature final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "temperature";
  static constexpr const char* version = "1.5.1";
  static constexpr const char* summary = "Granular temperature T(t)/T0 and mean velocity";
  static constexpr const char* documentation =
      "T = (m / 3N) sum_i V_i^2 with V_i the velocity relative to the local flow (paper 000, Eq. 4.15):\n"
      "the mean of all particles in a homogeneous system; in a slab the mean of the particle's layer,\n"
      "so that T is T-bar of Eq. (4.8). Read from the moments the host computes once per sample\n"
      "(ctx.moments). Series: temperature [T0], mean_velocity_x, mean_velocity_y, mean_velocity_z\n"
      "[sqrt(2T0/m)] (the mean velocity of all particles). Each record is the mean of the samples taken since the previous record.\n"
      "None of its series is declared stationary (group attribute `stationary` = \"\", so `gdsmc plot` draws\n"
      "no steady mean): whether T settles depends on the whole pipeline, not on anything this diagnostic\n"
      "reads: T decays in the homogeneous cooling state (Haff's law), grows by viscous heating in the\n"
      "modified shear flow of paper 002 (shear_rate published, anti_drag), and is steady in the uniform\n"
      "shear flow (the same shear_rate published) or under a thermostat. The diagnostics of steady states\n"
      "declare their own temperature series stationary (shear_rheology's temperature, poiseuille_channel's T);\n"
      "temperature.steady_mean is written over run.average_after in any case.\n"
      "Mixtures (gdsmc.species): the host's moments weigh each particle by its species' mass m_i, so T is\n"
      "the mixture temperature sum_i m_i V_i^2 / 3N = sum_s x_s T_s and the mean velocity the barycentric one\n"
      "(species_moments gives each species' T_s and T_s/T).";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Temperature(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    // Declared, not left out: no series is stationary as far as this diagnostic can know (see the
    // documentation: a published shear_rate is a steady USF or the ever-heating flow of paper 002).
    out.attribute("stationary", "");
    t0_ = sys.initial_temperature;
    v0_ = std::sqrt(2.0 * sys.initial_temperature / sys.mass);
    window_.declare(out, {{"temperature", "T0", "granular temperature T / T0 (000 Eq. 4.15)"},
                          {"mean_velocity_x", gdsmc::units::speed, "x component of the mean velocity"},
                          {"mean_velocity_y", gdsmc::units::speed, "y component of the mean velocity"},
                          {"mean_velocity_z", gdsmc::units::speed, "z component of the mean velocity"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    window_.add({m.temperature / t0_, m.mean[0] / v0_, m.mean[1] / v0_, m.mean[2] / v0_});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void save_state(gdsmc::StateWriter& out) const override { window_.save(out); }
  void load_state(gdsmc::StateReader& in) override { window_.load(in); }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Right in a mixture (gdsmc.species): it reads only the host's mass-weighted moments.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);  // no particle
  }
 private:
  gdsmc::WindowAverage window_;
  double t0_ = 1, v0_ = 1;
};

}  // namespace

GDSMC_PLUGIN(Temperature)
