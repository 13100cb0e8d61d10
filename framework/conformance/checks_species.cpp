// The mixture check of a species-aware collision rule (SDK 6.5, extension "gdsmc.species"): the
// pair kernel on pairs of unequal masses and diameters, weighed by the species' masses.
#include "config/system_info.hpp"
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

namespace {

// The test mixture: masses and diameters far from each other and from 1 (a rule that drops a mass
// or takes sigma for sigma_ab shows), equal fractions; or the context's own mixture (its
// system.species), whose names the rule's parameters may refer to.
std::vector<SpeciesInfo> test_species(const Pipeline& p) {
  const SystemInfo sys = system_info(p, 16, 0);
  if (sys.species && sys.species_count >= 2) return {sys.species, sys.species + sys.species_count};
  return {{"light", 1.0, 1.0, 0.5}, {"heavy", 3.7, 2.0, 0.5}};
}

// "a mixture of light (m = 1, sigma = 1), heavy (m = 3.7, sigma = 2)"
std::string mixture_text(const std::vector<SpeciesInfo>& species) {
  std::vector<std::string> parts;
  for (const auto& s : species) parts.push_back(fmt("%s (m = %g, sigma = %g)", s.name, s.mass, s.diameter));
  return fmt("a %zu-species mixture of ", species.size()) + join(parts, ", ");
}

struct MixtureReport {
  PairReport pairs;  // cases, nonfinite, locality, worst_* and their cases
  std::size_t cross = 0;  // pairs of two different species
};

std::string species_text(const SystemInfo& sys, std::uint32_t a, std::uint32_t b) {
  return fmt("%s (m = %g) - %s (m = %g) pair (sigma above: their sigma_ab)", sys.species[a].name, sys.species_mass(a),
             sys.species[b].name, sys.species_mass(b));
}

// Total momentum m_a v1 + m_b v2 kept to round-off, and the declared energy change equal to the
// mass-weighted measured one, (m_a/2)(v1'^2 - v1^2) + (m_b/2)(v2'^2 - v2^2).
void weigh_pair(const PairCase& pc, double ma, double mb, const Vec3& w1, const Vec3& w2, double declared,
                const std::string& what, PairReport& r) {
  const Vec3 dp = (ma * w1 + mb * w2) - (ma * pc.v1 + mb * pc.v2);
  const double ptol = 64 * kEps * (ma * (norm(pc.v1) + norm(w1)) + mb * (norm(pc.v2) + norm(w2))) + 1e-300;
  const double pratio = std::isfinite(norm(dp)) ? norm(dp) / ptol : std::numeric_limits<double>::infinity();
  if (pratio > r.worst_momentum) {
    r.worst_momentum = pratio;
    r.momentum_case = what + ": |sum m v' - sum m v| = " + fmt("%.3g, round-off tolerance %.3g", norm(dp), ptol);
  }
  const double e0 = 0.5 * (ma * dot(pc.v1, pc.v1) + mb * dot(pc.v2, pc.v2));
  const double e1 = 0.5 * (ma * dot(w1, w1) + mb * dot(w2, w2));
  const double diff = (e1 - e0) - declared;
  const double etol = 64 * kEps * (e0 + e1 + std::fabs(declared)) + 1e-300;
  const double eratio = std::isfinite(diff) ? std::fabs(diff) / etol : std::numeric_limits<double>::infinity();
  r.energy_declared_total += declared;
  if (eratio > r.worst_energy) {
    r.worst_energy = eratio;
    r.energy_case = what + fmt(": mass-weighted change of kinetic energy %.10g, declared %.10g (tolerance %.3g)",
                               e1 - e0, declared, etol);
  }
}

// The pair cases of the one-species suite, each with an ordered pair of species (all four in
// turn) at its contact distance sigma_ab, in a 4-particle state whose bystanders have random species.
MixtureReport mixture_suite(const BegunRule& begun, std::uint64_t seed, std::size_t random_pairs) {
  CollisionRule& rule = begun.rule();
  const SystemInfo& sys = begun.system;
  Rng case_rng = StreamFactory::standalone(seed, 5, StreamPurpose::host);
  Rng rule_rng = StreamFactory::standalone(seed, 0, StreamPurpose::collisions);
  const auto cases = pair_cases(rule, case_rng, random_pairs);
  MixtureReport r;
  Particles store, before_store;
  store.allocate(4, begun.object->attributes());
  before_store.allocate(4, begun.object->attributes());
  std::vector<std::uint32_t> species(4, 0);
  ParticleSpan p = store.span();
  p.species = species.data();  // the column a mixture's span carries (fixed storage: bound once)
  ParticleSpan b = before_store.span();
  b.species = species.data();
  rule.bind(p);
  std::vector<double> tally(rule.tallies().size());
  for (std::size_t c = 0; c < cases.size(); ++c) {
    PairCase pc = cases[c];
    const std::uint32_t i = c % 2 ? 3 : 0, j = c % 2 ? 1 : 2;
    const std::size_t n = sys.species_count;
    const auto sa = static_cast<std::uint32_t>((c / 2) % n), sb = static_cast<std::uint32_t>((c / (2 * n)) % n);
    for (std::uint32_t k = 0; k < 4; ++k)
      species[k] = static_cast<std::uint32_t>(std::min<double>(n - 1, case_rng.uniform() * static_cast<double>(n)));
    species[i] = sa;
    species[j] = sb;
    pc.sigma = sys.pair_diameter(sa, sb);
    fill_case(p, pc, i, j, case_rng);
    copy_all(p, b);
    const double declared = collide_with_direction(rule, p, i, j, pc.s, pc.sigma, rule_rng, tally);
    ++r.pairs.cases;
    r.cross += sa != sb;
    const Vec3 w1 = p.velocity(i), w2 = p.velocity(j);
    const std::string what = case_text(pc) + ", " + species_text(sys, sa, sb);
    if (r.pairs.nonfinite.empty() && !(std::isfinite(declared) && std::isfinite(norm(w1)) && std::isfinite(norm(w2))))
      r.pairs.nonfinite = fmt("energy change %g, velocities %s, %s for the ", declared, vec_text(w1).c_str(),
                              vec_text(w2).c_str()) + what;
    if (r.pairs.locality.empty()) check_locality(p, b, i, j, r.pairs);
    weigh_pair(pc, sys.species_mass(sa), sys.species_mass(sb), w1, w2, declared, what, r.pairs);
  }
  return r;
}

constexpr std::size_t kMixturePairs = 8000;

}  // namespace

// collision.species: a rule that offers "gdsmc.species" runs in mixtures, where the host hands it
// pairs of any two species; begun on a two-species system (masses 1 and 3.7, diameters 1 and 2;
// or the context's mixture), each pair must conserve sum m v to round-off, declare the
// mass-weighted energy change, and change nothing but the pair.
Result check_collision_species(const Subject& s) {
  const std::unique_ptr<Pipeline> p = load_test_pipeline(s, base_assignment(s), 16);
  if (!create_object(*p->collision.plugin, p->collision.params)->extension(species_id))
    return skip("the rule does not offer the extension gdsmc.species (static constexpr bool species_aware = true in "
                "a rule struct): the host refuses it in a mixture, so only one species of unit mass is asked of it");
  const std::vector<SpeciesInfo> species = test_species(*p);
  const std::string mixture = mixture_text(species);
  std::optional<BegunRule> begun;
  try {
    begun = begun_rule(*p, &species);
  } catch (const ParameterError& e) {
    return skip(fmt("begin() refused %s (parameter '%s'): %s; give a --context whose system.species the parameters "
                    "name", mixture.c_str(), e.parameter().c_str(), e.what()));
  }
  const MixtureReport m = mixture_suite(*begun, s.cfg.seed, kMixturePairs);
  const PairReport& r = m.pairs;
  const std::string where = " in " + mixture + ": ";
  if (!r.nonfinite.empty()) return fail("not finite" + where + r.nonfinite);
  if (!r.locality.empty()) return fail("mass" + where + "collide_batch " + r.locality);
  if (r.worst_momentum > 1)
    return fail("momentum not conserved" + where + r.momentum_case + " (collide() must weigh the pair by "
                "SystemInfo::species_mass of pair.particles.species_of(pair.i) and (pair.j))");
  if (r.worst_energy > 1)
    return fail("energy change differs from the declared mass-weighted one" + where + r.energy_case);
  return pass(fmt("%zu pairs (%zu of two species) of %s, at sigma_ab: sum m v conserved to round-off (worst %.2g of "
                  "the tolerance), the declared energy change equals sum (m/2) dv^2 (worst %.2g), only the colliding "
                  "pair changes", r.cases, m.cross, mixture.c_str(), r.worst_momentum, r.worst_energy));
}

}  // namespace gdsmc::host::conformance
