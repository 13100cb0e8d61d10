// The collisions-per-particle clock s(t) and the health of the majorant scheme.
#include <gdsmc/gdsmc.hpp>

namespace {

class CollisionCount final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "collision_count";
  static constexpr const char* version = "1.2.1";
  static constexpr const char* summary = "Collisions per particle s(t), acceptance ratio, majorant exceedances";
  static constexpr const char* documentation =
      "s(t) = (accepted collisions up to t) / N is the internal clock of paper 000 (text after\n"
      "Fig. 4; each collision involves two particles, so a particle collides 2s times on average);\n"
      "the host writes it beside every diagnostic as 'collisions_per_particle' and records the\n"
      "instantaneous value here. Series [1]: collisions, acceptance_ratio (the fraction of candidate\n"
      "pairs accepted) and majorant_exceeded (the number of candidates whose rate exceeded the cell majorant w (each such pair is accepted with probability 1 and\n"
      "w is raised; a count that is not small is a warning about the run). All cumulative, at the\n"
      "record time. Mixtures (gdsmc.species): the counts are those of all species pairs together.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit CollisionCount(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo&, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    n_ = out.series("collisions", "1", "accepted collisions since the start");
    acc_ = out.series("acceptance_ratio", "1", "accepted / candidate pairs since the start");
    exc_ = out.series("majorant_exceeded", "1", "candidates whose rate exceeded the majorant, since the start");
  }
  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan&) override {}
  // Reads none of the host's sampled moments (MomentsRead): the step context's counts only.
  // Right in a mixture (gdsmc.species): counts know no mass.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    return gdsmc::offer_moments_read<0, gdsmc::reads_no_particles>(id);  // no particle
  }
  void record(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    const auto collisions = static_cast<double>(ctx.collisions), candidates = static_cast<double>(ctx.candidates);
    out.append(n_, collisions);
    out.append(acc_, ctx.candidates > 0 ? collisions / candidates : 0.0);
    out.append(exc_, static_cast<double>(ctx.majorant_exceeded));
  }
  void finish(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    if (ctx.majorant_exceeded > 0) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "collision_count: %.0f of %.3g candidates exceeded the majorant (raised each time)",
                    static_cast<double>(ctx.majorant_exceeded), static_cast<double>(ctx.candidates));
      out.summary(buf);
    }
  }

 private:
  std::size_t n_ = 0, acc_ = 0, exc_ = 0;
};

}  // namespace

GDSMC_PLUGIN(CollisionCount)
