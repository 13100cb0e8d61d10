// The strongly non-equilibrium initial state (3.6) of paper 000 for the inhomogeneous USF problem:
// every particle has the same peculiar speed V0, density and flow have the "wrong" symmetries.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/species_values.hpp>

namespace {

class DeltaShell final : public gdsmc::InitialState {
 public:
  static constexpr const char* name = "delta_shell";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary =
      "Paper 000 Eq. (3.6): peculiar speed exactly V0, n0(y) = n(1 + sin(2 pi y/L)/2), u0 = U(cos(pi y/L) - 2/pi) x";
  static constexpr const char* documentation =
      "The initial distribution of the inhomogeneous USF problem of paper 000 (Sec. III):\n"
      "  f(y, v; 0) = n0(y) / (4 pi V0^2) delta(|v - u0(y)| - V0)                     (Eq. 3.6)\n"
      "  n0(y) = n_bar (1 + (1/2) sin(2 pi y / L))                                     (Eq. 3.7)\n"
      "  u0(y) = U (cos(pi y / L) - 2/pi) x_hat,  U = a L                             (Eq. 3.8)\n"
      "with L = Ly the distance between the planes y = -L/2 and y = +L/2, and the uniform initial\n"
      "temperature T0 = m V0^2 / 3, i.e. V0 = sqrt(3 T / m) for the `temperature` parameter T.\n"
      "Each particle: x and z uniform on [0, Lx) and [0, Lz); y drawn from n0(y)/(n_bar L) by\n"
      "rejection (y uniform on [-L/2, L/2), accepted with probability (1 + sin(2 pi y/L)/2) / (3/2);\n"
      "exact, 1.5 trials per particle on average); velocity v = u0(y) + V0 e with e uniform on the\n"
      "unit sphere. Every particle draws from its own stream (Streams::for_particle(id)), so the\n"
      "state does not depend on storage order. Both the density modulation (odd in y) and the flow\n"
      "(even in y) have zero mean over the slab, so the expected total momentum is zero; the sample\n"
      "is not corrected to exact moments (the peculiar speeds stay exactly V0).\n"
      "The shear rate a: the plugin's `shear_rate` parameter if it is >= 0 (a bare number is a tau0,\n"
      "or give {value: X, unit: 1/tau0 | reduced}); otherwise (the default, -1) the quantity\n"
      "'shear_rate' published by another plugin (a lees_edwards boundary). Needs a slab system.\n"
      "Mixtures (system.species): the flow u0(y) and the density profile are common to all species;\n"
      "a particle of species s (mass m_s) has the peculiar speed V0_s = sqrt(3 T_s / m_s), so that\n"
      "every species starts at the temperature T_s = m_s V0_s^2 / 3. T_s is `temperature` unless\n"
      "species_temperatures names the species (\"heavy: 2.0\", bare numbers in units of T0, entries\n"
      "separated by commas). The draws are those of the one-species state, so a one-species run is\n"
      "unchanged to the last bit.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("temperature", "initial temperature T0 = m V0^2 / 3").above(0.0).unit(gdsmc::Dimension::temperature).default_value(1.0),
            gdsmc::ParamSpec::real("shear_rate",
                                   "shear rate a of U = a L in u0(y) (bare numbers: a tau0); negative (default): "
                                   "the 'shear_rate' a lees_edwards boundary publishes")
                .unit(gdsmc::Dimension::inverse_time)
                .default_value(-1.0),
            gdsmc::ParamSpec::string("species_temperatures",
                                     "mixtures: initial temperatures of named species, \"name: T_s/T0, ...\" (others: temperature)")
                .default_value("")};
  }
  explicit DeltaShell(const gdsmc::Params& p)
      : temperature_(p.real("temperature")),
        shear_rate_(p.real("shear_rate")),
        species_temperatures_(gdsmc::parse_species_values(name, "species_temperatures", p.string("species_temperatures"),
                                                          {0.0, HUGE_VAL, true})) {}

  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  void generate(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard& quantities, const gdsmc::ParticleSpan& p,
                const gdsmc::Streams& streams) override {
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("delta_shell: needs a slab system (system.domain: slab)");
    double a = shear_rate_;
    if (a < 0) {
      const double* published = quantities.find("shear_rate");
      if (!published)
        throw gdsmc::ParameterError("shear_rate",
                                    "delta_shell: no shear rate: give shear_rate, or use a boundary that publishes "
                                    "'shear_rate' (lees_edwards)");
      a = *published;
    }
    const double L = sys.box[1];
    const double U = a * L;
    // V0 of each species: T_s = m_s V0_s^2 / 3 (Eq. 3.6 per species); one species: T0 = m V0^2 / 3
    std::vector<double> v0{std::sqrt(3.0 * temperature_ / sys.mass)};
    if (gdsmc::has_species_masses(sys) || !species_temperatures_.empty()) {
      const std::vector<double> T = gdsmc::species_values(sys, name, "species_temperatures", species_temperatures_,
                                                          temperature_, sys.initial_temperature);
      v0.resize(sys.species_count);
      for (std::size_t s = 0; s < sys.species_count; ++s) v0[s] = std::sqrt(3.0 * T[s] / sys.species_mass(s));
    }
    const double k = 2.0 * M_PI / L;
    for (std::size_t i = 0; i < p.count; ++i) {
      gdsmc::Rng rng = streams.for_particle(p.id[i]);
      p.x[i] = sys.box[0] * rng.uniform();
      double y;
      do {
        y = L * rng.uniform() - 0.5 * L;
      } while (1.5 * rng.uniform() >= 1.0 + 0.5 * std::sin(k * y));  // Eq. (3.7) by rejection
      p.y[i] = y;
      p.z[i] = sys.box[2] * rng.uniform();
      const gdsmc::Vec3 e = rng.unit_vector();
      const double speed = v0[p.species_of(i)];
      p.vx[i] = U * (std::cos(0.5 * k * y) - 2.0 / M_PI) + speed * e.x;  // Eq. (3.8)
      p.vy[i] = speed * e.y;
      p.vz[i] = speed * e.z;
    }
  }

 private:
  double temperature_, shear_rate_;
  std::vector<gdsmc::SpeciesValue> species_temperatures_;
};

}  // namespace

GDSMC_PLUGIN(DeltaShell)

// What `gdsmc conformance` runs it in when no --context is given.
// A slab sheared by Lees-Edwards planes (which publish the shear rate).
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
    "boundaries: {y: {plugin: lees_edwards, shear_rate: 0.1}}")
