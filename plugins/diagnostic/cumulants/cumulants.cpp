// Fourth and sixth cumulants of the velocity distribution.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class Cumulants final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "cumulants";
  static constexpr const char* version = "1.4.1";
  static constexpr const char* summary = "Cumulants a2 and a3 of the velocity distribution";
  static constexpr const char* documentation =
      "a2 = (m^2 / 15 T^2) <V^4> - 1 and a3 = -(m^3 / 105 T^3) <V^6> + 1 + 3 a2\n"
      "(paper 000, Eqs. 4.17-4.18; the Sonine coefficients of paper 001, Eq. 2.9). Both vanish\n"
      "for a Maxwellian. V is the velocity relative to the local flow (the mean of all particles in a\n"
      "homogeneous system, of the particle's layer in a slab) and T the matching temperature (T-bar of\n"
      "Eq. 4.8 in a slab), as the host computes them once per sample (ctx.moments). Series a2, a3\n"
      "(dimensionless). Mixtures (gdsmc.species): the host's moments weigh by the species' masses, so a2 and\n"
      "a3 are the cumulants of the mass-weighted energy m_i V_i^2 about the mixture T: they vanish for Maxwellian\n"
      "species at one temperature but not when the species' temperatures differ (non-equipartition) even if each\n"
      "species is Maxwellian; each species' own a2 is species_moments' a2[<name>].";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Cumulants(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    window_.declare(out, {{"a2", "1", "fourth cumulant (000 Eq. 4.17)"}, {"a3", "1", "sixth cumulant (000 Eq. 4.18)"}});
  }
  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const gdsmc::VelocityMoments& m = ctx.moments->local;
    window_.add({m.a2(), m.a3()});
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }
  void save_state(gdsmc::StateWriter& out) const override { window_.save(out); }
  void load_state(gdsmc::StateReader& in) override { window_.load(in); }

  // Sampled on both sides of the collision stage (BracketedSampling): its means carry no O(dt) bias.
  // Runs in a mixture (gdsmc.species): it reads only the host's mass-weighted moments.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_all, gdsmc::reads_no_particles>(id);  // no particle
  }
 private:
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(Cumulants)
