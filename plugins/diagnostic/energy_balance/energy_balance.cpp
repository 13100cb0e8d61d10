// The energy balance of a run: E(t) - E(0) against the energy each stage added (the host's ledger).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class EnergyBalance final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "energy_balance";
  static constexpr const char* version = "1.3.1";
  static constexpr const char* summary =
      "Kinetic energy E(t) per particle and its balance E - E0 = sum of the energy ledger [T0]";
  static constexpr const char* documentation =
      "E = (m/2) sum_i v_i^2 with laboratory velocities (paper 004 Eq. A1; the shared moments'\n"
      "kinetic_energy). Every stage that changes velocities (collisions, each forcing, each\n"
      "boundary) reports the energy it added; the host's energy ledger keeps the cumulative sums.\n"
      "Energy conservation of the algorithm is then the identity\n"
      "  E(t) - E(0) = sum over stages of the energy added up to t,\n"
      "so residual = (E - E0) - ledger_total must stay at round-off (a few 1e-16 E per step,\n"
      "growing with the number of steps; typically below 1e-10 of E for a whole run). A larger\n"
      "residual means a stage changed velocities without declaring it (or declared it wrong).\n"
      "E0 = E - ledger_total at the first sample: the initial energy E(0) when the first sample is\n"
      "the initial state (the ledger is then zero), as the host records it.\n"
      "Series (per particle, divided by N, in units of T0; each record the mean of the samples since\n"
      "the previous record): E, E_change = E - E0, ledger_total, residual.\n"
      "At the end: array added_by_stage [T0 per particle] with attribute 'stages' naming its\n"
      "entries, scalars added_by_<stage>, final_E_change, final_residual and\n"
      "final_relative_residual = residual / E (the host prints the same balance for every run).\n"
      "Mixtures (gdsmc.species): E is the host's sum_i (m_i/2) v_i^2 and each stage declares the energy it adds\n"
      "with the species' masses, so the identity holds as it stands and checks those stages.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit EnergyBalance(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    per_ = 1.0 / (static_cast<double>(sys.particles) * sys.initial_temperature);  // per particle, in T0
    have_e0_ = false;
    values_.assign(4, 0.0);
    window_.declare(out, {{"E", "T0", "kinetic energy per particle (m/2N) sum v_i^2 (004 Eq. A1)"},
                          {"E_change", "T0", "E - E0 per particle"},
                          {"ledger_total", "T0", "energy added by all stages so far, per particle (the energy ledger)"},
                          {"residual", "T0", "(E - E0) - ledger_total per particle: round-off in a correct run"}});
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    const double E = ctx.moments->kinetic_energy;
    const double added = ledger_total(ctx);
    if (!have_e0_) {
      e0_ = E - added;
      have_e0_ = true;
    }
    last_e_ = E;
    values_[0] = E * per_;
    values_[1] = (E - e0_) * per_;
    values_[2] = added * per_;
    values_[3] = ((E - e0_) - added) * per_;
    window_.add(values_);
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }

  void finish(const gdsmc::StepContext& ctx, gdsmc::OutputSink& out) override {
    if (!have_e0_) return;
    const double change = last_e_ - e0_;
    const double added = ledger_total(ctx);
    const double residual = change - added;
    std::vector<double> stages;
    std::string names;
    for (std::size_t k = 0; k < ctx.energy_ledger_size; ++k) {
      const gdsmc::EnergyLedgerEntry& e = ctx.energy_ledger[k];
      stages.push_back(e.energy * per_);
      names += (k ? "," : "") + std::string(e.stage);
      out.scalar(std::string("added_by_") + e.stage, e.energy * per_, "T0",
                 std::string("energy added by stage '") + e.stage + "' over the run, per particle");
    }
    out.array("added_by_stage", stages, {stages.size()}, "T0",
              "energy added by each stage over the run, per particle, in the order of attribute 'stages'");
    out.attribute("stages", names);
    out.scalar("final_E_change", change * per_, "T0", "E - E0 at the end, per particle");
    out.scalar("final_residual", residual * per_, "T0", "(E - E0) - ledger_total at the end, per particle");
    out.scalar("final_relative_residual", residual / last_e_, "1", "residual / E at the end");
  }
  // values_ is scratch, rewritten by every sample before use: not saved.
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("have_e0", have_e0_);
    out.write("e0", e0_);
    out.write("last_e", last_e_);
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("have_e0", have_e0_);
    in.read("e0", e0_);
    in.read("last_e", last_e_);
    window_.load(in);
  }
  // Reads only the kinetic energy of the host's sampled moments (MomentsRead).
  // Right in a mixture (gdsmc.species): the mass-weighted energy and the ledger.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    return gdsmc::offer_moments_read<gdsmc::moments_energy, gdsmc::reads_no_particles>(id);  // no particle
  }

 private:
  static double ledger_total(const gdsmc::StepContext& ctx) {
    double s = 0;
    for (std::size_t k = 0; k < ctx.energy_ledger_size; ++k) s += ctx.energy_ledger[k].energy;
    return s;
  }

  double per_ = 1, e0_ = 0, last_e_ = 0;
  bool have_e0_ = false;
  std::vector<double> values_;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(EnergyBalance)
