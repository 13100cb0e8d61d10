// Rotational temperature of rough spheres: T_rot = (I/3) <w^2>, beside the translational T.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class RotationalTemperature final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "rotational_temperature";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* summary = "Rotational temperature T_rot = (I/3)<w^2> of rough spheres, and T_rot/T_tr";
  static constexpr const char* documentation =
      "Reads the per-particle attribute 'angular_velocity' (declared by a rough-sphere rule such\n"
      "as rough_spheres) and the moment-of-inertia factor kappa it publishes\n"
      "('moment_of_inertia_factor'; I = kappa m sigma^2 / 4, sigma the run's diameter). Series:\n"
      "  rotational_temperature [T0]    T_rot = (I/3) <w^2>\n"
      "  translational_temperature [T0] T_tr = (m/3) <V^2> (the host's ctx.moments)\n"
      "  temperature_ratio [1]          r = T_rot / T_tr (Huthmann & Zippelius 1997)\n"
      "  energy_per_particle [T0]       (3/2)(T_tr + T_rot), conserved when alpha = beta = 1\n"
      "Scalar after the run: final_temperature_ratio.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit RotationalTemperature(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    const double* kappa = board.find("moment_of_inertia_factor");
    if (!kappa)
      throw gdsmc::ParameterError("plugin", "rotational_temperature needs a collision rule that publishes "
                                            "'moment_of_inertia_factor' (for example rough_spheres)");
    inertia_ = *kappa * sys.mass * sys.sigma * sys.sigma / 4.0;
    t0_ = sys.initial_temperature;
    window_.declare(out, {{"rotational_temperature", "T0", "T_rot = (I/3) <w^2>"},
                          {"translational_temperature", "T0", "T_tr = (m/3) <V^2>"},
                          {"temperature_ratio", "1", "T_rot / T_tr"},
                          {"energy_per_particle", "T0", "(3/2)(T_tr + T_rot)"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan& p) override {
    const double* w = p.attribute("angular_velocity");
    if (!w)
      throw std::runtime_error("rotational_temperature: no particle attribute 'angular_velocity' (use a collision rule "
                               "that declares it, such as rough_spheres)");
    const std::size_t n = p.count;
    double w2 = 0;
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < n; ++i) w2 += w[c * n + i] * w[c * n + i];
    const double t_rot = inertia_ * w2 / (3.0 * static_cast<double>(n)) / t0_;
    const double t_tr = ctx.moments->local.temperature / t0_;
    last_ratio_ = t_rot / t_tr;
    window_.add({t_rot, t_tr, last_ratio_, 1.5 * (t_tr + t_rot)});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    out.scalar("final_temperature_ratio", last_ratio_, "1", "T_rot / T_tr at the last sample");
    char buf[160];
    std::snprintf(buf, sizeof buf, "rotational_temperature: T_rot / T_tr = %.5f at the end of the run", last_ratio_);
    out.summary(buf);
  }
  // Checkpoints: what sample() changes (inertia_ and t0_ are set again by begin(); the angular
  // velocities are the host's, saved with the particles).
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("last_ratio", last_ratio_);
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("last_ratio", last_ratio_);
    window_.load(in);
  }

 private:
  double inertia_ = 0.1, t0_ = 1, last_ratio_ = 0;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(RotationalTemperature)
