// Kinetic pressure tensor of the whole system (the mean P-bar of 000 Eq. 4.9 in a slab).
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class PressureTensor final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "pressure_tensor";
  static constexpr const char* version = "1.4.1";
  static constexpr const char* summary = "Kinetic pressure tensor P_ij / (n0 T0) of the whole system";
  static constexpr const char* documentation =
      "P = (m / Omega) sum_i V_i V_i with Omega = N / n the system volume and V_i the velocity\n"
      "relative to the local flow (paper 000, Eq. 4.16): the mean of all particles in a homogeneous\n"
      "system; in a slab the mean of the particle's layer, so that P is the mean pressure tensor P-bar\n"
      "of Eq. (4.9) and T is T-bar (Eq. 4.8). From the moments the host computes once per sample\n"
      "(ctx.moments). Series P_xx, P_yy, P_zz, P_xy, P_xz, P_yz in\n"
      "units of n0 T0 [n0 T0] (n0 = N / Omega), plus the reduced forms P_xy_over_nT = P_xy/(nT), N1_over_nT = (P_xx -\n"
      "P_yy)/(nT) and N2_over_nT = (P_zz - P_yy)/(nT) [1] with the current temperature T, as the papers\n"
      "plot them. Mixtures (gdsmc.species): the host's moments weigh each particle by its species' mass,\n"
      "so P = sum_i m_i V_i V_i / Omega (V about the barycentric flow) is the mixture's pressure tensor, the\n"
      "sum of species_moments' partial P[<name>], and T the mixture temperature.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit PressureTensor(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    t0_ = sys.initial_temperature;
    window_.declare(out, {{"P_xx", gdsmc::units::pressure, "xx element of the kinetic pressure tensor (000 Eq. 4.16)"},
                          {"P_yy", gdsmc::units::pressure, "yy element"},
                          {"P_zz", gdsmc::units::pressure, "zz element"},
                          {"P_xy", gdsmc::units::pressure, "xy element"},
                          {"P_xz", gdsmc::units::pressure, "xz element"},
                          {"P_yz", gdsmc::units::pressure, "yz element"},
                          {"P_xy_over_nT", "1", "reduced shear stress P_xy / (n T)"},
                          {"N1_over_nT", "1", "reduced normal stress difference (P_xx - P_yy) / (n T)"},
                          {"N2_over_nT", "1", "reduced normal stress difference (P_zz - P_yy) / (n T)"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    // P / n = m <V V> with m = 1; divided by T0 or by T.
    const double (&s)[3][3] = m.second;
    const double T = m.temperature;
    window_.add({s[0][0] / t0_, s[1][1] / t0_, s[2][2] / t0_, s[0][1] / t0_, s[0][2] / t0_, s[1][2] / t0_,
                 s[0][1] / T, (s[0][0] - s[1][1]) / T, (s[2][2] - s[1][1]) / T});
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
  double t0_ = 1;
};

}  // namespace

GDSMC_PLUGIN(PressureTensor)
