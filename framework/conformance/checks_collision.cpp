// Collision-rule checks: the pair kernel (collide_batch) on a grid of pairs, and the host's collision
// stage with the rule on a population.
#include "config/system_info.hpp"
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Collision rules

std::string case_text(const PairCase& c) {
  return fmt("%s pair v1 = %s, v2 = %s, sigma_hat = %s (g.sigma_hat = %.6g), sigma = %g", c.what, vec_text(c.v1).c_str(),
             vec_text(c.v2).c_str(), vec_text(c.s).c_str(), dot(c.v1 - c.v2, c.s), c.sigma);
}

Vec3 gaussian(Rng& rng, double scale) { return {scale * rng.normal(), scale * rng.normal(), scale * rng.normal()}; }

std::vector<PairCase> pair_cases(const CollisionRule& rule, Rng& rng, std::size_t random_pairs) {
  std::vector<PairCase> cases;
  auto forward = [&](const Vec3& g) {
    const double gn = norm(g);
    return gn > 0 ? hard_sphere_impact_direction(g, gn, rng) : rng.unit_vector();
  };
  auto add = [&](Vec3 v1, Vec3 v2, Vec3 s, const char* what) {
    // Directions the kernel never selects (rate 0 on the far side) are flipped.
    if (rule.pair_rate(v1 - v2, s) <= 0 && dot(v1 - v2, s) < 0) s = -1.0 * s;
    // Every third pair with a non-unit diameter (PairContext::sigma).
    cases.push_back({v1, v2, s, what, cases.size() % 3 == 2 ? 2.5 : 1.0});
  };
  for (std::size_t k = 0; k < random_pairs; ++k) {
    const Vec3 v1 = gaussian(rng, 1), v2 = gaussian(rng, 1);
    if (k % 4 == 3) add(v1, v2, rng.unit_vector(), "random (uniform direction)");
    else add(v1, v2, forward(v1 - v2), "random");
  }
  const std::size_t edge = std::max<std::size_t>(20, random_pairs / 50);
  for (std::size_t k = 0; k < edge; ++k) {
    const Vec3 v = gaussian(rng, 1);
    add(v, v, rng.unit_vector(), "zero-relative-velocity");
    // grazing: sigma_hat nearly perpendicular to g
    const Vec3 v1 = gaussian(rng, 1), v2 = gaussian(rng, 1), g = v1 - v2;
    const Vec3 gh = (1.0 / norm(g)) * g;
    Vec3 t = cross(gh, rng.unit_vector());
    t = (1.0 / norm(t)) * t;
    const double tilt = k % 2 ? 1e-9 : 1e-15;
    const Vec3 sg = t + tilt * gh;
    add(v1, v2, (1.0 / norm(sg)) * sg, "grazing");
    const Vec3 h1 = gaussian(rng, 1e6), h2 = gaussian(rng, 1e6);
    add(h1, h2, forward(h1 - h2), "huge-speed (1e6)");
    const Vec3 t1 = gaussian(rng, 1e-8), t2 = gaussian(rng, 1e-8);
    add(t1, t2, forward(t1 - t2), "tiny-speed (1e-8)");
    const Vec3 u = gaussian(rng, 1e6), gr = gaussian(rng, 1);
    add(u + 0.5 * gr, u - 0.5 * gr, forward(gr), "fast-centre-of-mass (1e6) small-relative-velocity");
    const Vec3 w1 = gaussian(rng, 1), w2 = gaussian(rng, 1);
    add(w1, w2, (1.0 / norm(w1 - w2)) * (w1 - w2), "head-on");
  }
  return cases;
}

// A random 4-particle state around the pair case: slots i and j hold the pair's velocities.
void fill_case(const ParticleSpan& p, const PairCase& pc, std::uint32_t i, std::uint32_t j, Rng& case_rng) {
  const double scale = std::max({norm(pc.v1), norm(pc.v2), 1e-300});
  for (std::size_t k = 0; k < 4; ++k) {
    p.x[k] = case_rng.uniform();
    p.y[k] = case_rng.uniform();
    p.z[k] = case_rng.uniform();
    p.set_velocity(k, gaussian(case_rng, scale));
  }
  p.set_velocity(i, pc.v1);
  p.set_velocity(j, pc.v2);
  for (std::size_t a = 0; a < p.attribute_count; ++a)
    for (std::size_t e = 0; e < 4 * static_cast<std::size_t>(p.attribute_specs[a].components); ++e)
      p.attribute_data[a][e] = scale * case_rng.normal();
}

void copy_all(const ParticleSpan& from, const ParticleSpan& to) {
  for (std::size_t k = 0; k < from.count; ++k) {
    to.x[k] = from.x[k]; to.y[k] = from.y[k]; to.z[k] = from.z[k];
    to.vx[k] = from.vx[k]; to.vy[k] = from.vy[k]; to.vz[k] = from.vz[k];
  }
  for (std::size_t a = 0; a < from.attribute_count; ++a)
    std::copy(from.attribute_data[a], from.attribute_data[a] + from.count * from.attribute_specs[a].components,
              to.attribute_data[a]);
}

namespace {

// pair_rate finite, >= 0 and within rate_bound(|g|) along the case's direction, its opposite and
// a random one.
void check_rate(CollisionRule& rule, const PairCase& pc, Rng& case_rng, PairReport& r) {
  const Vec3 g = pc.v1 - pc.v2;
  const Vec3 other = case_rng.unit_vector();
  const double bound = rule.rate_bound(norm(g));
  for (const Vec3& d : {pc.s, -1.0 * pc.s, other}) {
    const double rate = rule.pair_rate(g, d);
    if (!std::isfinite(rate) || rate < 0) {
      r.rate = fmt("pair_rate(g = %s, sigma_hat = %s) = %g (must be finite and >= 0) for a %s pair", vec_text(g).c_str(),
                   vec_text(d).c_str(), rate, pc.what);
      break;
    }
    if (rate > bound * (1 + 64 * kEps) + 1e-300) {
      r.rate = fmt("pair_rate(g = %s, sigma_hat = %s) = %.10g exceeds rate_bound(|g| = %.6g) = %.10g (the majorant "
                   "the host draws candidates against) for a %s pair",
                   vec_text(g).c_str(), vec_text(d).c_str(), rate, norm(g), bound, pc.what);
      break;
    }
  }
}

void check_finite(const ParticleSpan& p, const PairCase& pc, double declared, const Vec3& w1, const Vec3& w2,
                  PairReport& r) {
  std::string bad;
  if (!std::isfinite(declared)) bad = fmt("returned the energy change %g", declared);
  else if (!all_finite(&w1.x, 1) || !all_finite(&w1.y, 1) || !all_finite(&w1.z, 1) || !all_finite(&w2.x, 1) ||
           !all_finite(&w2.y, 1) || !all_finite(&w2.z, 1))
    bad = "produced the velocities " + vec_text(w1) + ", " + vec_text(w2);
  else {
    const std::string n = nonfinite_in(p);
    if (!n.empty()) bad = "produced " + n;
  }
  if (!bad.empty()) r.nonfinite = bad + " for the " + case_text(pc);
}

}  // namespace

// Mass / locality: nothing but the velocities and attributes of i and j may change.
void check_locality(const ParticleSpan& p, const ParticleSpan& b, std::uint32_t i, std::uint32_t j, PairReport& r) {
  for (std::size_t k = 0; k < 4 && r.locality.empty(); ++k) {
    if (p.x[k] != b.x[k] || p.y[k] != b.y[k] || p.z[k] != b.z[k])
      r.locality = fmt("moved particle %zu (a collision changes velocities only)", k);
    else if (k != i && k != j && (p.vx[k] != b.vx[k] || p.vy[k] != b.vy[k] || p.vz[k] != b.vz[k]))
      r.locality = fmt("changed the velocity of particle %zu, which is not in the colliding pair (%u, %u)", k, i, j);
    for (std::size_t a = 0; a < p.attribute_count && r.locality.empty() && k != i && k != j; ++a)
      for (int comp = 0; comp < p.attribute_specs[a].components; ++comp) {
        const std::size_t e = static_cast<std::size_t>(comp) * p.count + k;
        if (std::memcmp(&p.attribute_data[a][e], &b.attribute_data[a][e], sizeof(double)) != 0) {
          r.locality = fmt("changed attribute '%s' of particle %zu, which is not in the colliding pair",
                           p.attribute_specs[a].name.c_str(), k);
          break;
        }
      }
  }
}

namespace {

void check_momentum(const PairCase& pc, const Vec3& w1, const Vec3& w2, PairReport& r) {
  const Vec3 dp = (w1 + w2) - (pc.v1 + pc.v2);
  const double tol = 64 * kEps * (norm(pc.v1) + norm(pc.v2) + norm(w1) + norm(w2)) + 1e-300;
  const double ratio = std::isfinite(norm(dp)) ? norm(dp) / tol : std::numeric_limits<double>::infinity();
  if (ratio > r.worst_momentum) {
    r.worst_momentum = ratio;
    r.momentum_excess = norm(dp);
    r.momentum_case = case_text(pc) + fmt(": |p' - p| = %.3g, round-off tolerance %.3g", norm(dp), tol);
  }
}

void check_energy(const PairCase& pc, double declared, const Vec3& w1, const Vec3& w2, PairReport& r) {
  const double e0 = 0.5 * (dot(pc.v1, pc.v1) + dot(pc.v2, pc.v2));
  const double e1 = 0.5 * (dot(w1, w1) + dot(w2, w2));
  const double diff = (e1 - e0) - declared;
  const double tol = 64 * kEps * (e0 + e1 + std::fabs(declared)) + 1e-300;
  const double ratio = std::isfinite(diff) ? std::fabs(diff) / tol : std::numeric_limits<double>::infinity();
  r.energy_declared_total += declared;
  if (ratio > r.worst_energy) {
    r.worst_energy = ratio;
    r.energy_excess = std::fabs(diff);
    r.energy_case = case_text(pc) + fmt(": actual change of kinetic energy %.10g, declared %.10g (tolerance %.3g)",
                                        e1 - e0, declared, tol);
  }
}

}  // namespace

// One collision of slots i and j with the impact direction s, through the rule's pair kernel: a
// batch of one pair whose direction is given (PairBatch::direction). Writes the velocities back
// and returns the declared energy change.
double collide_with_direction(const CollisionRule& rule, const ParticleSpan& p, std::uint32_t i, std::uint32_t j,
                              const Vec3& s, double sigma, Rng& rng, std::vector<double>& tally) {
  Vec3 v1 = p.velocity(i), v2 = p.velocity(j);
  const double u = 0;
  std::uint8_t accepted = 0;
  PairBatch b;
  b.count = 1;
  b.i = &i;
  b.j = &j;
  b.v1 = &v1;
  b.v2 = &v2;
  b.u = &u;
  b.direction = &s;
  b.accepted = &accepted;
  b.sigma = sigma;
  b.particles = &p;
  b.rng = &rng;
  b.tally = tally.empty() ? nullptr : tally.data();
  rule.collide_batch(b);
  if (accepted) {
    p.set_velocity(i, v1);
    p.set_velocity(j, v2);
  }
  return b.energy_change;
}

PairReport pair_suite(CollisionRule& rule, const std::vector<AttributeSpec>& attributes, std::uint64_t seed,
                      std::size_t random_pairs) {
  // The harness's own draws on a host stream, the rule's on the collision stream of "cell" 0.
  Rng case_rng = StreamFactory::standalone(seed, 1, StreamPurpose::host);
  Rng rule_rng = StreamFactory::standalone(seed, 0, StreamPurpose::collisions);
  const auto cases = pair_cases(rule, case_rng, random_pairs);
  PairReport r;
  Particles store, before_store;
  store.allocate(4, attributes);
  before_store.allocate(4, attributes);
  const ParticleSpan p = store.span();
  const ParticleSpan b = before_store.span();
  rule.bind(p);  // once: the 4 particles stay where they are
  std::vector<double> tally(rule.tallies().size());  // the sums are not checked here
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const PairCase& pc = cases[c];
    const std::uint32_t i = c % 2 ? 3 : 0, j = c % 2 ? 1 : 2;  // vary the slots
    fill_case(p, pc, i, j, case_rng);
    copy_all(p, b);
    if (r.rate.empty()) check_rate(rule, pc, case_rng, r);

    const double declared = collide_with_direction(rule, p, i, j, pc.s, pc.sigma, rule_rng, tally);
    ++r.cases;
    const Vec3 w1 = p.velocity(i), w2 = p.velocity(j);
    if (r.nonfinite.empty()) check_finite(p, pc, declared, w1, w2, r);
    if (r.locality.empty()) check_locality(p, b, i, j, r);
    check_momentum(pc, w1, w2, r);
    check_energy(pc, declared, w1, w2, r);
  }
  return r;
}

std::string pair_failure(const PairReport& r) {
  if (!r.nonfinite.empty()) return "not finite: " + r.nonfinite;
  if (!r.locality.empty()) return "mass: " + r.locality;
  if (r.worst_momentum > 1) return "momentum not conserved: " + r.momentum_case;
  if (r.worst_energy > 1) return "energy change differs from the declared one: " + r.energy_case;
  if (!r.rate.empty()) return "rate: " + r.rate;
  return "";
}

constexpr std::size_t kRandomPairs = 20000;

BegunRule begun_rule(const Pipeline& p, const std::vector<SpeciesInfo>* species) {
  BegunRule r{create_object(*p.collision.plugin, p.collision.params), system_info(p, 16, 0)};
  if (species) {  // a mixture (collision.species): the rule reads the species in begin()
    r.system.species = species->data();
    r.system.species_count = species->size();
  }
  QuantityBoard board;
  r.object->publish(board);
  for (const auto& f : p.forcings) create_object(*f.plugin, f.params)->publish(board);
  for (std::size_t b = 0; b < p.boundaries.size(); ++b)  // a slab context's (Lees-Edwards publishes 'shear_rate')
    if (b == 0 || p.boundaries[b].plugin != p.boundaries[0].plugin)
      create_object(*p.boundaries[b].plugin, p.boundaries[b].params)->publish(board);
  r.rule().begin(r.system, board);
  return r;
}

BegunRule begun_rule(const Subject& s) { return begun_rule(*load_test_pipeline(s, base_assignment(s), 16)); }

// The pair suite on a fresh rule (each collision.* check reads one property); pair_suite binds it
// to its own particles.
PairReport pair_report(const Subject& s) {
  const BegunRule r = begun_rule(s);
  return pair_suite(r.rule(), r.object->attributes(), s.cfg.seed, kRandomPairs);
}

Result check_collision_finite(const Subject& s) {
  const PairReport r = pair_report(s);
  if (!r.nonfinite.empty()) return fail("NaN or infinity: collide " + r.nonfinite);
  return pass(fmt("%zu pairs (random, zero relative velocity, grazing, speeds 1e6 and 1e-8): velocities, attributes "
                  "and declared energy changes finite", r.cases));
}

Result check_collision_mass(const Subject& s) {
  const PairReport r = pair_report(s);
  if (!r.locality.empty()) return fail("mass: collide_batch " + r.locality);
  return pass(fmt("%zu pairs: the particle count is fixed and only the colliding pair changes (mass conserved)", r.cases));
}

Result check_collision_momentum(const Subject& s) {
  const PairReport r = pair_report(s);
  if (r.worst_momentum > 1) return fail("momentum not conserved: " + r.momentum_case);
  return pass(fmt("%zu pairs: momentum conserved to round-off (worst %.2g of the tolerance 64 eps |v|)", r.cases,
                  r.worst_momentum));
}

Result check_collision_energy(const Subject& s) {
  const PairReport r = pair_report(s);
  if (r.worst_energy > 1) return fail("energy change differs from the declared one: " + r.energy_case);
  return pass(fmt("%zu pairs: the kinetic-energy change equals the declared one to round-off (worst %.2g of the "
                  "tolerance); mean declared change %.4g per random pair", r.cases, r.worst_energy,
                  r.energy_declared_total / static_cast<double>(r.cases)));
}

Result check_collision_rate(const Subject& s) {
  const PairReport r = pair_report(s);
  if (!r.rate.empty()) return fail("collision rate invalid: " + r.rate);
  return pass(fmt("pair_rate finite, >= 0 and <= rate_bound(|g|) for %zu pairs in 3 directions each", r.cases));
}

// The pair kernel's acceptance, on a grid of relative speeds |g| = f w (f from 0.05 to 1.5: the tail
// above the majorant included), 4000 pairs of one g each (the batch's pairs share nothing, so each
// is an independent trial): the fraction accepted must be the probability the kernel form promises,
// min(1, |g|/w) (hard sphere) or the mean over uniform directions of min(1, B(g, s)/W) (general,
// estimated from pair_rate on 20000 directions), within 5 standard errors; every candidate above
// its bound must be reported (exceeded, max_rate).
Result check_collision_acceptance(const Subject& s) {
  const BegunRule begun = begun_rule(s);
  CollisionRule& rule = begun.rule();
  constexpr std::uint32_t pairs = 4000;
  Particles store;
  store.allocate(2 * pairs, begun.object->attributes());
  const ParticleSpan span = store.span();
  rule.bind(span);
  Rng host_rng = StreamFactory::standalone(s.cfg.seed, 7, StreamPurpose::host);
  Rng rule_rng = StreamFactory::standalone(s.cfg.seed, 0, StreamPurpose::collisions);
  std::vector<std::uint32_t> is(pairs), js(pairs);
  std::vector<Vec3> v1(pairs), v2(pairs);
  std::vector<double> u(pairs), tally(rule.tallies().size());
  std::vector<std::uint8_t> accepted(pairs);
  for (std::uint32_t q = 0; q < pairs; ++q) is[q] = 2 * q, js[q] = 2 * q + 1;
  const bool general = rule.kernel_form() == KernelForm::general;
  const double w = 1.0, bound = rule.rate_bound(w);
  std::vector<std::string> rows;
  for (const double f : {0.05, 0.3, 0.7, 0.95, 1.2, 1.5}) {
    const Vec3 g = f * host_rng.unit_vector();
    double promised = 0;  // the acceptance probability the kernel form promises
    if (general) {
      constexpr int directions = 20000;
      for (int k = 0; k < directions; ++k) promised += std::min(1.0, rule.pair_rate(g, host_rng.unit_vector()) / bound);
      promised /= directions;
    } else {
      promised = std::min(1.0, norm(g) / w);
    }
    for (std::uint32_t q = 0; q < pairs; ++q) {
      const Vec3 c = host_rng.normal() * host_rng.unit_vector();  // any centre of mass
      v1[q] = c + 0.5 * g;
      v2[q] = c - 0.5 * g;
      u[q] = host_rng.uniform32();
    }
    PairBatch b;
    b.count = pairs;
    b.i = is.data();
    b.j = js.data();
    b.v1 = v1.data();
    b.v2 = v2.data();
    b.u = u.data();
    b.accepted = accepted.data();
    b.speed_bound = w;
    b.rate_bound = bound;
    b.sigma = begun.system.sigma;
    b.particles = &span;
    b.rng = &rule_rng;
    b.tally = tally.empty() ? nullptr : tally.data();
    rule.collide_batch(b);
    std::uint64_t flagged = 0;
    for (std::uint32_t q = 0; q < pairs; ++q) flagged += accepted[q] != 0;
    if (flagged != b.collided)
      return fail(fmt("collide_batch flagged %llu pairs accepted but counted %llu (|g| = %.2f w)",
                      static_cast<unsigned long long>(flagged), static_cast<unsigned long long>(b.collided), f));
    const double fraction = static_cast<double>(b.collided) / pairs;
    const double error = std::sqrt(std::max(promised * (1 - promised), 1.0 / pairs) / pairs);
    if (std::fabs(fraction - promised) > 5 * error)
      return fail(fmt("collide_batch accepted %.4f of %u candidates with |g| = %.2f w, where its kernel form (%s) "
                      "promises %.4f (5 standard errors: %.4f)",
                      fraction, pairs, f, general ? "general" : "hard sphere", promised, 5 * error));
    if (!general && f > 1 && (b.exceeded != pairs || b.max_rate < norm(g) * (1 - 1e-12)))
      return fail(fmt("collide_batch reported %llu of %u candidates above the majorant (|g| = %.2f w) and the largest "
                      "rate %.4g w: every one must be reported, with max_rate >= |g|",
                      static_cast<unsigned long long>(b.exceeded), pairs, f, b.max_rate));
    rows.push_back(fmt("%.2f: %.3f (promised %.3f)", f, fraction, promised));
  }
  return pass(fmt("%u candidates at each |g|/w, accepted fraction: ", pairs) + join(rows, ", "));
}

// the collision stage on a population: three stages at the system's diameter and three at 2.5 times it
// (PairBatch::sigma reaches the rule's PairContext), each on its own collision stream.
Result check_collision_cell(const Subject& s) {
  constexpr std::size_t n = 2000;
  auto h = make_harness(s, base_assignment(s), n);
  Rng attr_rng = h->host_rng(3);
  h->randomize_zero_attributes(attr_rng);
  h->update_moments();
  const ParticleSpan p = h->span();
  auto totals = [&](Vec3& mom, double& energy, double& abs_sum) { velocity_totals(p, mom, energy, abs_sum); };
  Vec3 p0, p1;
  double e0, e1, a0, a1;
  totals(p0, e0, a0);
  const double w = kInitialMajorantRatio * std::sqrt(h->global.temperature);
  std::uint64_t candidates = 0, accepted = 0;
  double declared = 0;
  std::vector<std::string> per_sigma;
  for (const double sigma : {h->sys.sigma, 2.5 * h->sys.sigma}) {
    // dt for about two candidate pairs per particle per call (hard-sphere kernel estimate)
    const double dt = 2.0 * static_cast<double>(n) * 2.0 * h->sys.volume /
                      (static_cast<double>(n) * static_cast<double>(n) * sigma * sigma * M_PI * w);
    std::uint64_t acc = 0, cand = 0;
    for (int k = 0; k < 3; ++k) {
      const CollisionStage::Totals c = h->collide(dt, sigma);
      ++h->ctx.step;
      if (c.accepted > c.candidates)
        return fail(fmt("the collision stage reports %llu accepted of %llu candidates (sigma = %g)",
                        static_cast<unsigned long long>(c.accepted), static_cast<unsigned long long>(c.candidates), sigma));
      if (!std::isfinite(c.energy_change) || !c.finite_remainders || !std::isfinite(c.max_rate) || c.max_rate < 0)
        return fail(fmt("the collision stage reports a non-finite or negative result (energy_change %g, remainders finite %d, max_rate %g; "
                        "sigma = %g)", c.energy_change, int(c.finite_remainders), c.max_rate, sigma));
      cand += c.candidates;
      acc += c.accepted;
      declared += c.energy_change;
      const std::string bad = nonfinite_in(p);
      if (!bad.empty()) return fail(fmt("not finite after the collision stage (sigma = %g): ", sigma) + bad);
    }
    candidates += cand;
    accepted += acc;
    per_sigma.push_back(fmt("sigma = %g: %llu of %llu candidates", sigma, static_cast<unsigned long long>(acc),
                            static_cast<unsigned long long>(cand)));
  }
  totals(p1, e1, a1);
  const double ptol = 64 * kEps * (a0 + a1) * std::max(1.0, std::sqrt(static_cast<double>(accepted) / n));
  if (norm(p1 - p0) > ptol)
    return fail(fmt("momentum not conserved by the collision stage on %zu particles: total momentum changed by %s (|dp| = %.3g, "
                    "round-off tolerance %.3g) in %llu collisions", n, vec_text(p1 - p0).c_str(), norm(p1 - p0), ptol,
                    static_cast<unsigned long long>(accepted)));
  const double etol = 64 * kEps * (e0 + e1) * std::max(1.0, static_cast<double>(accepted) / n);
  if (std::fabs((e1 - e0) - declared) > etol)
    return fail(fmt("energy change differs from the declared one in the collision stage: kinetic energy changed by %.10g, "
                    "the rule declared %.10g (tolerance %.3g) over %llu collisions", e1 - e0, declared, etol,
                    static_cast<unsigned long long>(accepted)));
  return pass(fmt("the collision stage on %zu particles: %llu collisions of %llu candidates (%s); momentum conserved "
                  "(|dp| = %.2g), energy change %.6g as declared", n, static_cast<unsigned long long>(accepted),
                  static_cast<unsigned long long>(candidates), join(per_sigma, "; ").c_str(), norm(p1 - p0), e1 - e0));
}

}  // namespace gdsmc::host::conformance
