// Inelastic hard spheres with a constant coefficient of normal restitution alpha; in a mixture
// (SDK 6.5) a coefficient alpha_ab per pair of species and the masses m_a, m_b of the pair.
#include <cstdlib>
#include <string>
#include <vector>

#include <gdsmc/gdsmc.hpp>

namespace {

// One `restitution_pairs` entry as written: "light-heavy: 0.8".
struct PairEntry {
  std::string names;  // "light-heavy", split against the species names in begin()
  double value = 1;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\n") - b + 1);
}

constexpr const char* kPairsParam = "restitution_pairs";

// "a-b: 0.8, c-d: 0.7" into entries; the syntax and the range [0, 1] are checked here, the
// species names in begin(), where they are known.
std::vector<PairEntry> parse_pairs(const std::string& text) {
  std::vector<PairEntry> out;
  const std::string form = " (write 'name-name: value, ...', e.g. 'light-heavy: 0.8, heavy-heavy: 0.7')";
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = trim(text.substr(start, comma - start));
    start = comma + 1;
    if (item.empty()) {
      if (comma < text.size()) throw gdsmc::ParameterError(kPairsParam, "an empty entry" + form);
      continue;
    }
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos)
      throw gdsmc::ParameterError(kPairsParam, "'" + item + "' has no ':'" + form);
    PairEntry e{trim(item.substr(0, colon)), 0};
    const std::string number = trim(item.substr(colon + 1));
    char* end = nullptr;
    e.value = std::strtod(number.c_str(), &end);
    if (number.empty() || *end != '\0')
      throw gdsmc::ParameterError(kPairsParam, "'" + number + "' in '" + item + "' is not a number" + form);
    if (!(e.value >= 0 && e.value <= 1))
      throw gdsmc::ParameterError(kPairsParam, number + " for '" + e.names +
                                                   "' is outside [0, 1] (a coefficient of normal restitution)");
    out.push_back(e);
  }
  return out;
}

struct InelasticHardSpheres {
  static constexpr const char* name = "inelastic_hard_spheres";
  static constexpr const char* version = "1.1.0";
  static constexpr bool species_aware = true;  // SDK 6.5: runs in mixtures (masses from begin())
  static constexpr const char* summary = "Inelastic hard spheres (IHS) with constant restitution alpha";
  static constexpr const char* documentation =
      "Smooth inelastic hard spheres of diameter sigma and mass m = 1. A collision with impact\n"
      "direction s (g.s > 0, g = v1 - v2) gives (paper 000, Eq. 2.8)\n"
      "  v1' = v1 - (1+alpha)/2 (g.s) s,   v2' = v2 + (1+alpha)/2 (g.s) s,\n"
      "conserving momentum and losing kinetic energy (1 - alpha^2)/4 (g.s)^2. The collision\n"
      "kernel is the hard-sphere one, sigma^2 Theta(g.s)(g.s) (Eq. 2.6). alpha = 1 is the elastic\n"
      "gas. Publishes 'restitution' = alpha for diagnostics and forcings that need it.\n"
      "Mixtures (system.species): a particle of species a (mass m_a) meeting one of species b at\n"
      "the contact distance sigma_ab = (sigma_a + sigma_b)/2 collides as (Garzo & Dufty, Phys.\n"
      "Rev. E 60, 5706 (1999), Eq. 2)\n"
      "  v1' = v1 - m_b/(m_a+m_b) (1+alpha_ab)(g.s) s,   v2' = v2 + m_a/(m_a+m_b) (1+alpha_ab)(g.s) s,\n"
      "conserving m_a v1 + m_b v2 and losing m_a m_b/(2(m_a+m_b)) (1 - alpha_ab^2)(g.s)^2 of kinetic\n"
      "energy. alpha_ab is `alpha` unless `restitution_pairs` names the pair ('light-heavy: 0.8,\n"
      "heavy-heavy: 0.7', species by name, either order). In a mixture it also publishes\n"
      "'restitution[a,b]' for every pair of species indices a <= b, and keeps the collision tallies\n"
      "'species_energy_change[<name>]': the kinetic energy sum (m_a/2)(v'^2 - v^2) that the\n"
      "particles of each species received in collisions (its partial cooling rate zeta_a is\n"
      "-(2/(3 n_a T_a)) d/dt of it per unit volume).";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution (every pair of species not in restitution_pairs)")
                .range(0.0, 1.0)
                .default_value(1.0),
            gdsmc::ParamSpec::string(kPairsParam,
                                     "mixtures: restitution per pair of species, 'name-name: value, ...' (e.g. "
                                     "'light-heavy: 0.8, heavy-heavy: 0.7'); pairs not named take alpha")
                .default_value("")};
  }
  explicit InelasticHardSpheres(const gdsmc::Params& p)
      : alpha(p.real("alpha")), half_one_plus_alpha(0.5 * (1.0 + alpha)), pair_entries(parse_pairs(p.string(kPairsParam))) {}

  void publish(gdsmc::QuantityBoard& board) const { board.publish("restitution", alpha); }

  void begin(const gdsmc::SystemInfo& system, gdsmc::QuantityBoard& board);

  std::vector<std::string> tallies() const {
    std::vector<std::string> names;
    for (const std::string& s : species_names) names.push_back("species_energy_change[" + s + "]");
    return names;
  }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    if (species_count > 0) return collide_species(v1, v2, s, pair);
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = (half_one_plus_alpha * gs) * s;  // Eq. (2.8)
    v1 -= dv;
    v2 += dv;
    return -0.25 * (1.0 - alpha * alpha) * gs * gs;
  }

  // The pair (a, b) of a mixture, from the table built in begin().
  double collide_species(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    const std::uint32_t a = pair.particles.species_of(pair.i), b = pair.particles.species_of(pair.j);
    const PairConstants& c = table[a * species_count + b];
    const double gs = dot(v1 - v2, s);
    if (pair.tally) {
      // Energy each particle receives, (m/2)(v'^2 - v^2) without the cancellation of the difference.
      pair.tally[a] += c.mass1 * c.kick1 * gs * (0.5 * c.kick1 * gs - dot(v1, s));
      pair.tally[b] += c.mass2 * c.kick2 * gs * (0.5 * c.kick2 * gs + dot(v2, s));
    }
    v1 -= (c.kick1 * gs) * s;  // Garzo & Dufty PRE 60, 5706, Eq. (2)
    v2 += (c.kick2 * gs) * s;
    return c.loss * gs * gs;
  }

  // Per ordered pair of species (a, b): kick1 = m_b/(m_a+m_b)(1+alpha_ab), kick2 = m_a/(m_a+m_b)
  // (1+alpha_ab), loss = -m_a m_b/(2(m_a+m_b))(1-alpha_ab^2). Equal unit masses give the
  // one-species constants to the bit: 1/(1+1) = 0.5 and 1/(2 (1+1)) = 0.25 exactly.
  struct PairConstants {
    double kick1, kick2, loss, mass1, mass2;
  };

  double alpha;
  double half_one_plus_alpha;
  std::vector<PairEntry> pair_entries;
  std::size_t species_count = 0;  // 0: one species of unit mass (no system.species)
  std::vector<PairConstants> table;
  std::vector<std::string> species_names;
};

// The species named by "x-y" (split at the '-' that leaves two known names), or an error text.
std::string split_pair(const std::string& names, const std::vector<std::string>& species, std::size_t& a, std::size_t& b) {
  int found = 0;
  for (std::size_t dash = names.find('-'); dash != std::string::npos; dash = names.find('-', dash + 1)) {
    const std::string left = trim(names.substr(0, dash)), right = trim(names.substr(dash + 1));
    std::size_t x = species.size(), y = species.size();
    for (std::size_t k = 0; k < species.size(); ++k) {
      if (species[k] == left) x = k;
      if (species[k] == right) y = k;
    }
    if (x < species.size() && y < species.size()) a = x, b = y, ++found;
  }
  if (found == 1) return "";
  return found == 0 ? "'" + names + "' is not two species names joined by '-'"
                    : "'" + names + "' can be split into two species names in more than one way";
}

void InelasticHardSpheres::begin(const gdsmc::SystemInfo& system, gdsmc::QuantityBoard& board) {
  if (!system.species) {
    if (!pair_entries.empty())
      throw gdsmc::ParameterError(kPairsParam, "the system has a single species (no system.species); "
                                               "use alpha, or list the species under system.species");
    return;  // one species: collide() keeps the arithmetic of Eq. (2.8)
  }
  const std::size_t n = system.species_count;
  species_names.clear();
  for (std::size_t k = 0; k < n; ++k) species_names.emplace_back(system.species[k].name);
  std::string listed;
  for (const auto& s : species_names) listed += (listed.empty() ? "" : ", ") + s;
  std::vector<double> restitution(n * n, alpha);
  std::vector<bool> given(n * n, false);
  for (const PairEntry& e : pair_entries) {
    std::size_t a = 0, b = 0;
    const std::string error = split_pair(e.names, species_names, a, b);
    if (!error.empty())
      throw gdsmc::ParameterError(kPairsParam, error + "; the species are: " + listed);
    if (given[a * n + b])
      throw gdsmc::ParameterError(kPairsParam, "the pair " + species_names[a] + "-" + species_names[b] +
                                                   " is given twice (the order of the two names does not matter)");
    given[a * n + b] = given[b * n + a] = true;
    restitution[a * n + b] = restitution[b * n + a] = e.value;
  }
  table.assign(n * n, {});
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      const double ma = system.species_mass(a), mb = system.species_mass(b), e = restitution[a * n + b];
      const double one_plus = 1.0 + e;
      // Garzo & Dufty PRE 60, 5706, Eq. (2): the impulse shares and the energy lost
      table[a * n + b] = {mb / (ma + mb) * one_plus, ma / (ma + mb) * one_plus,
                          -(ma * mb / (2.0 * (ma + mb))) * (1.0 - e * e), ma, mb};
      if (a <= b) board.publish("restitution[" + std::to_string(a) + "," + std::to_string(b) + "]", e);
    }
  species_count = n;
}

}  // namespace

GDSMC_PLUGIN(InelasticHardSpheres)
