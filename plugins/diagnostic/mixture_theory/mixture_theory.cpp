// Binary granular mixture: the kinetic theory of its homogeneous state (temperature ratio, partial
// cooling rates, cumulants; gdsmc/physics/mixture_theory.hpp), beside the measured T_0/T_1.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class MixtureTheoryDiagnostic final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "mixture_theory";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Temperature ratio T0/T1, partial cooling rates and cumulants of a binary granular mixture (HCS or white noise), "
      "Maxwellian and first Sonine, beside the measured T0/T1";
  static constexpr const char* documentation =
      "A dilute binary mixture of smooth inelastic hard spheres (system.species with two species, masses\n"
      "m_i, diameters sigma_i, number fractions x_i; restitution alpha_ij read from the collision rule's\n"
      "published 'restitution[i,j]', i <= j, else its common 'restitution'). T_i = m_i <V^2>_i / 3,\n"
      "T = x_0 T_0 + x_1 T_1, gamma = T_0 / T_1 (species 0, 1 are the papers' 1, 2).\n"
      "state: cooling -- the homogeneous cooling state, zeta_0 = zeta_1 (Garzo & Dufty, Phys. Rev. E 60,\n"
      "5706 (1999)); white_noise -- the steady state under a thermostat giving every species the same\n"
      "acceleration variance xi0^2 dt per component, dT_i/dt = m_i xi0^2 - zeta_i T_i = 0, so\n"
      "zeta_0 T_0/m_0 = zeta_1 T_1/m_1 (Barrat & Trizac, Granular Matter 4, 57 (2002); Dahl et al., Phys.\n"
      "Rev. E 66, 041301 (2002)).\n"
      "Maxwellian approximation: zeta_i = sum_j (8 sqrt(pi)/3) n_j sigma_ij^2 mu_ji (1 + alpha_ij) v_ij\n"
      "[1 - mu_ji (1 + alpha_ij)(1 + m_i T_j/(m_j T_i))/2], mu_ji = m_j/(m_i + m_j), v_ij^2 = 2T_i/m_i +\n"
      "2T_j/m_j. First Sonine: f_i = f_i,M [1 + (c_i/2) S_2(m_i V^2/2T_i)], zeta_i linear in c_0, c_1,\n"
      "and c_0, c_1 from the fourth-moment balances linearised in c (GD99's scheme; one species gives\n"
      "van Noije & Ernst's a2 = c/2 in both states). The pair moments are exact to first order in c\n"
      "(scripts/mixture_sonine_moments.py; checked by Monte Carlo in\n"
      "tests/sdk/mixture_kinetic_theory_test.cpp).\n"
      "Scalars (all dimensionless), Maxwellian: gamma_maxwellian (T0/T1), T0_over_T_maxwellian,\n"
      "T1_over_T_maxwellian, zeta0_star_maxwellian, zeta1_star_maxwellian; first Sonine: gamma_sonine,\n"
      "T0_over_T_sonine, T1_over_T_sonine, zeta0_star_sonine, zeta1_star_sonine, c0_sonine, c1_sonine;\n"
      "and gamma_tracer_maxwellian, gamma_tracer_sonine: T0/T1 with species 0 a tracer (x_0 -> 0).\n"
      "zeta_i* = zeta_i / nu with GD99's nu = n sigma_01^2 v0, v0 = sqrt(2T (m_0 + m_1)/(m_0 m_1)).\n"
      "Measured, per sample from the particles: series temperature_ratio (T0/T1, peculiar velocities\n"
      "about the mass-weighted mean), T0_over_T, T1_over_T; the gamma_* scalars are theory for\n"
      "temperature_ratio (its .steady_mean over the averaging window).\n"
      "Refuses a run that is not a two-species mixture.\n"
      "Measured (DSMC, 1e5 particles, equal diameters, x_0 = 0.5, alpha = 0.8 for every pair, m_0 = 1,\n"
      "steady mean of temperature_ratio +- batch-means error; theory Maxwellian / first Sonine):\n"
      "  HCS, m_1 = 4, dt = 0.02 tau0:          0.7533 +- 0.0011   theory 0.7456 / 0.7510\n"
      "  HCS, m_1 = 10, dt = 0.02 (0.005) tau0: 0.49086 (0.49001) +- 0.00023   theory 0.48575 / 0.48891\n"
      "  white noise xi0^2 = 0.1, m_1 = 4:       0.60902 +- 0.00029  theory 0.60881 / 0.60916\n"
      "  white noise xi0^2 = 0.1, m_1 = 10:      0.36277 +- 0.00025  theory 0.36538 / 0.36319\n"
      "The first Sonine approximation is within 0.3 % of the simulation (within 2 standard errors but\n"
      "HCS m_1 = 10: 0.2 %, 5 standard errors at the smaller dt), the Maxwellian off by up to 1 %.";
  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::choice("state", {"cooling", "white_noise"},
                                     "cooling: the homogeneous cooling state; white_noise: the steady state under a "
                                     "white-noise thermostat of equal acceleration variance for every species")
                .default_value("cooling")};
  }
  explicit MixtureTheoryDiagnostic(const gdsmc::Params& p)
      : state_(p.string("state") == "white_noise" ? gdsmc::MixtureState::white_noise : gdsmc::MixtureState::cooling) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& board, gdsmc::OutputSink& out) override {
    if (sys.species_count != 2 || !sys.species)
      throw gdsmc::ParameterError("plugin", "mixture_theory needs a two-species mixture (system.species with two "
                                            "entries); this run has " + std::to_string(sys.species_count) + " species");
    const double* common = board.find("restitution");
    for (int i = 0; i < 2; ++i) {
      mix_.mass[i] = sys.species_mass(i);
      mix_.diameter[i] = sys.species_diameter(i);
      mix_.fraction[i] = sys.species[i].fraction;
      for (int j = i; j < 2; ++j) {
        const std::string key = "restitution[" + std::to_string(i) + "," + std::to_string(j) + "]";
        const double* a = board.find(key);
        if (!a) a = common;
        if (!a)
          throw gdsmc::ParameterError("plugin", "mixture_theory needs a collision rule that publishes '" + key +
                                                    "' or 'restitution' (for example inelastic_hard_spheres)");
        mix_.alpha[i][j] = mix_.alpha[j][i] = *a;
      }
    }
    mass_[0] = mix_.mass[0];
    mass_[1] = mix_.mass[1];
    const char* names[2] = {"maxwellian", "sonine"};
    const gdsmc::MixtureApproximation approx[2] = {gdsmc::MixtureApproximation::maxwellian,
                                                   gdsmc::MixtureApproximation::first_sonine};
    const std::string eq = state_ == gdsmc::MixtureState::cooling ? "Garzo & Dufty, PRE 60, 5706 (1999): zeta_0 = zeta_1"
                                                                  : "Barrat & Trizac 2002, Dahl et al. 2002: zeta_0 T_0/m_0 = zeta_1 T_1/m_1";
    window_.declare(out, {{"temperature_ratio", "1", "measured T0/T1 (T_i = m_i <V^2>_i / 3)"},
                          {"T0_over_T", "1", "measured T0/T, T = x0 T0 + x1 T1"},
                          {"T1_over_T", "1", "measured T1/T"}});
    values_.assign(3, 0.0);
    for (int k = 0; k < 2; ++k) {
      theory_[k] = gdsmc::mixture_theory(mix_, state_, approx[k]);
      if (!theory_[k].converged)
        throw gdsmc::ParameterError("plugin", std::string("mixture_theory: no temperature ratio found in the ") + names[k] +
                                                  " approximation for these species (the first-Sonine system is singular)");
      const std::string s = std::string("_") + names[k];
      const std::string how = k ? " (first Sonine)" : " (Maxwellian approximation)";
      out.scalar("gamma" + s, theory_[k].gamma, "1", "T0/T1" + how);
      out.scalar("T0_over_T" + s, theory_[k].t_over_t[0], "1", "T0/T" + how);
      out.scalar("T1_over_T" + s, theory_[k].t_over_t[1], "1", "T1/T" + how);
      out.scalar("zeta0_star" + s, theory_[k].zeta_star[0], "1", "zeta_0 / (n sigma_01^2 v0)" + how);
      out.scalar("zeta1_star" + s, theory_[k].zeta_star[1], "1", "zeta_1 / (n sigma_01^2 v0)" + how);
      if (k) {
        out.scalar("c0" + s, theory_[k].c[0], "1", "fourth cumulant c_0 = 2 a2 of species 0" + how);
        out.scalar("c1" + s, theory_[k].c[1], "1", "fourth cumulant c_1 = 2 a2 of species 1" + how);
      }
      out.theory("gamma" + s, "temperature_ratio", eq + how);
      out.theory("T0_over_T" + s, "T0_over_T", eq + how);
      out.theory("T1_over_T" + s, "T1_over_T", eq + how);
      out.theory("zeta0_star" + s, "", eq + how);
      out.theory("zeta1_star" + s, "", eq + how);
      if (k) {
        out.theory("c0" + s, "", eq + how);
        out.theory("c1" + s, "", eq + how);
      }
      // The tracer limit of species 0 (x_0 -> 0: zeta_0 from its collisions with species 1 alone,
      // zeta_1 that of the pure gas 1), beside the run's own fraction.
      gdsmc::BinaryMixture tracer = mix_;
      tracer.fraction[0] = 0;
      tracer.fraction[1] = 1;
      const gdsmc::MixtureTheory limit = gdsmc::mixture_theory(tracer, state_, approx[k]);
      out.scalar("gamma_tracer" + s, limit.gamma, "1", "T0/T1 in the tracer limit x_0 -> 0" + how);
      out.theory("gamma_tracer" + s, "", eq + ", x_0 -> 0" + how);
    }
  }

  void sample(const gdsmc::StepContext&, const gdsmc::ParticleSpan& p) override {
    // peculiar velocities about the mass-weighted mean velocity of the mixture
    double mom[3] = {0, 0, 0}, mtot = 0, n[2] = {0, 0}, v2[2] = {0, 0}, v1[2][3] = {{0, 0, 0}, {0, 0, 0}};
    for (std::size_t k = 0; k < p.count; ++k) {
      const std::uint32_t s = p.species_of(k);
      const double vx = p.vx[k], vy = p.vy[k], vz = p.vz[k];
      n[s] += 1;
      v1[s][0] += vx;
      v1[s][1] += vy;
      v1[s][2] += vz;
      v2[s] += vx * vx + vy * vy + vz * vz;
    }
    for (int s = 0; s < 2; ++s) {
      mtot += mass_[s] * n[s];
      for (int c = 0; c < 3; ++c) mom[c] += mass_[s] * v1[s][c];
    }
    if (!(n[0] > 0 && n[1] > 0)) return;
    double T[2];
    for (int s = 0; s < 2; ++s) {
      // sum (v - u)^2 = sum v^2 - 2 u.sum v + n u^2
      double q = v2[s];
      for (int c = 0; c < 3; ++c) {
        const double u = mom[c] / mtot;
        q += -2.0 * u * v1[s][c] + n[s] * u * u;
      }
      T[s] = mass_[s] * q / (3.0 * n[s]);
    }
    const double Tm = (n[0] * T[0] + n[1] * T[1]) / (n[0] + n[1]);
    values_[0] = T[0] / T[1];
    values_[1] = T[0] / Tm;
    values_[2] = T[1] / Tm;
    last_ratio_ = values_[0];
    window_.add(values_);
  }
  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override { window_.commit(out); }

  void finish(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "mixture_theory (%s): T0/T1 theory %.5f (Maxwellian), %.5f (first Sonine, c0 = %.4f, c1 = %.4f); "
                  "measured at the last sample %.5f",
                  state_ == gdsmc::MixtureState::cooling ? "HCS" : "white noise", theory_[0].gamma, theory_[1].gamma,
                  theory_[1].c[0], theory_[1].c[1], last_ratio_);
    out.summary(buf);
  }
  void save_state(gdsmc::StateWriter& out) const override {
    out.write("last_ratio", last_ratio_);
    window_.save(out);
  }
  void load_state(gdsmc::StateReader& in) override {
    in.read("last_ratio", last_ratio_);
    window_.load(in);
  }

 private:
  gdsmc::MixtureState state_;
  gdsmc::BinaryMixture mix_;
  gdsmc::MixtureTheory theory_[2];
  double mass_[2] = {1, 1};
  double last_ratio_ = std::nan("");
  std::vector<double> values_;
  gdsmc::WindowAverage window_;
};

}  // namespace

GDSMC_PLUGIN(MixtureTheoryDiagnostic)

// What `gdsmc conformance` runs it in when no --context is given: a cooling binary mixture.
GDSMC_CONFORMANCE_CONTEXT(
    "system:\n  density: 1.0e-3\n  temperature: 1.0\n  species:\n"
    "    - {name: light, mass: 1, diameter: 1, fraction: 0.5}\n"
    "    - {name: heavy, mass: 4, diameter: 1.5, fraction: 0.5}")
