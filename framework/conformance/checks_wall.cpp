// Boundary checks (SDK 2.0; issue 7 item 8): a 1 x 1 x 1 slab of 2000 particles (Maxwellian at
// T = 1) streamed by the host's Mover with the boundary on both planes for 300 steps of dt = 0.05
// (tens of thousands of hits), every hit recorded; and, for walls, hits fed directly from many
// incoming states to test the re-emitted distribution.
#include <boost/math/special_functions/gamma.hpp>

#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

namespace {

constexpr std::size_t kParticles = 2000;
constexpr int kSteps = 300;
constexpr double kDt = 0.05;

std::string hit_text(const HitRecord& r) {
  return fmt("particle %llu at the %s plane, t = %.6g: in x = %s, v = %s; out (%s) x = %s, v = %s",
             static_cast<unsigned long long>(r.in.id), r.in.side < 0 ? "y_min" : "y_max", r.in.time,
             vec_text(r.in.position).c_str(), vec_text(r.in.velocity).c_str(),
             r.result == HitResult::transferred ? "transferred" : "reflected", vec_text(r.out.position).c_str(),
             vec_text(r.out.velocity).c_str());
}

struct Streamed {
  std::unique_ptr<SlabHarness> h;
  Snapshot start;
  std::string error;  // what the Mover threw
};

Streamed streamed_slab(const Subject& s, const Assignment& a, int steps = kSteps) {
  Streamed r;
  r.h = make_slab(s, a, kParticles);
  if (!r.h->refusal.empty()) return r;
  r.start = r.h->particles.save();
  try {
    r.h->stream(steps, kDt);
  } catch (const std::runtime_error& e) {
    r.error = e.what();
    if (!r.h->recorder->log.empty()) r.error += "; the last hit: " + hit_text(r.h->recorder->log.back());
  }
  return r;
}

std::string tally_text(const StreamingTally& t) {
  auto side = [](const char* name, const BoundaryTally& b) {
    return fmt("%s %llu hits, energy %.6g, momentum %s", name, static_cast<unsigned long long>(b.hits), b.energy,
               vec_text({b.momentum[0], b.momentum[1], b.momentum[2]}).c_str());
  };
  return side("y_min", t.sides[0]) + "; " + side("y_max", t.sides[1]);
}

const char* kSetup = "2000 particles (Maxwellian, T = 1) in a 1 x 1 x 1 slab, 300 steps of dt = 0.05";

}  // namespace

Result check_boundary_containment(const Subject& s) {
  Streamed r = streamed_slab(s, base_assignment(s));
  SlabHarness& h = *r.h;
  if (!h.refusal.empty()) return skip(h.refusal + " (a refusal in begin() is allowed)");
  if (!r.error.empty()) return fail("particle lost or sent outside the box: the host's mover stopped: " + r.error);
  const ParticleSpan p = h.span();
  const double half = 0.5 * h.sys.box[1], tol = 1e-12 * h.sys.box[1];
  for (const HitRecord& hr : h.recorder->log) {
    const double y = hr.out.position.y;
    if (!(std::fabs(y) <= half + tol))
      return fail(fmt("particle left outside the box: the plugin returned the position y = %.17g, outside [-%g, %g]: ",
                      y, half, half) + hit_text(hr));
    if (hr.result == HitResult::reflected && std::fabs(y - hr.in.side * half) > tol)
      return fail(fmt("particle moved off its plane by a reflection (returned y = %.17g, the plane is y = %g): ", y,
                      hr.in.side * half) + hit_text(hr));
  }
  if (p.count != kParticles || h.particles.ids() != r.start.id)
    return fail(fmt("particle count or identities changed: %zu particles after streaming, %zu before", p.count, kParticles));
  const std::string bad = nonfinite_in(p);
  if (!bad.empty()) return fail("particle lost: " + bad);
  for (std::size_t i = 0; i < p.count; ++i)
    if (!(p.x[i] >= 0 && p.x[i] < h.sys.box[0] && p.z[i] >= 0 && p.z[i] < h.sys.box[2] && std::fabs(p.y[i]) <= half))
      return fail(fmt("particle left outside the box [0, %g) x [-%g, %g] x [0, %g): particle %zu at %s", h.sys.box[0],
                      half, half, h.sys.box[2], i, vec_text(p.position(i)).c_str()));
  return pass(fmt("%s with the plugin on both planes: %zu hits, every returned position on the box, count constant "
                  "(%zu), none lost, none outside; measured tallies: ", kSetup, h.recorder->log.size(), p.count) +
              tally_text(h.tally));
}

// A boundary whose tallies show no energy exchanged (to round-off) must keep every speed: per hit
// and per particle over the run. Boundaries that exchange energy report what they exchanged.
Result check_boundary_elastic(const Subject& s) {
  Streamed r = streamed_slab(s, base_assignment(s));
  SlabHarness& h = *r.h;
  if (!h.refusal.empty()) return skip(h.refusal + " (a refusal in begin() is allowed)");
  if (!r.error.empty()) return skip("needs a boundary that passes boundary.containment (the mover stopped: " + r.error + ")");
  const auto& log = h.recorder->log;
  double incoming = 0;
  std::map<std::uint64_t, int> hits_of;
  for (const HitRecord& hr : log) {
    incoming += 0.5 * dot(hr.in.velocity, hr.in.velocity);
    ++hits_of[hr.in.id];
  }
  const double exchanged = std::fabs(h.tally.sides[0].energy) + std::fabs(h.tally.sides[1].energy);
  const double tol = 16 * kEps * incoming + 1e-300;
  if (exchanged > tol)
    return skip(fmt("exchanges energy with the gas (%s; |E| = %.4g, %.3g of the kinetic energy brought by the %zu hits, "
                    "round-off %.2g): not elastic, so no speed has to be kept", tally_text(h.tally).c_str(), exchanged,
                    exchanged / incoming, log.size(), tol));
  double worst_hit = 0;
  const HitRecord* bad = nullptr;
  for (const HitRecord& hr : log) {
    const double e0 = dot(hr.in.velocity, hr.in.velocity), e1 = dot(hr.out.velocity, hr.out.velocity);
    const double rel = std::fabs(e1 - e0) / std::max(e0, 1e-300);
    if (rel > worst_hit) worst_hit = rel, bad = &hr;
  }
  if (worst_hit > 4 * kEps)
    return fail(fmt("speed not kept although no energy is exchanged in total (%s): |v|^2 changed by a relative %.3g "
                    "at ", tally_text(h.tally).c_str(), worst_hit) + hit_text(*bad));
  const ParticleSpan p = h.span();
  double worst_particle = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const double e0 = r.start.vx[i] * r.start.vx[i] + r.start.vy[i] * r.start.vy[i] + r.start.vz[i] * r.start.vz[i];
    const double e1 = p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    const double rel = std::fabs(e1 - e0) / std::max(e0, 1e-300);
    const auto it = hits_of.find(p.id[i]);
    const int n = it == hits_of.end() ? 0 : it->second;
    if (rel > 4 * kEps * (1 + n))
      return fail(fmt("speed not kept although no energy is exchanged in total: particle %zu (%d hits) has |v|^2 = %.17g "
                      "after %d steps, %.17g before", i, n, e1, kSteps, e0));
    worst_particle = std::max(worst_particle, rel);
  }
  return pass(fmt("%s: no energy exchanged (%s), and every speed kept: per hit (worst relative change of |v|^2 %.2g "
                  "over %zu hits) and per particle after the run (worst %.2g)", kSetup, tally_text(h.tally).c_str(),
                  worst_hit, log.size(), worst_particle));
}

// --------------------------------------------------------------------------------------------
// Re-emitted distribution of a wall

namespace {

constexpr std::size_t kHitsPerClass = 20000;
constexpr int kBins = 40, kClassBins = 20;
constexpr double kSignificance = 1e-4;  // each chi-square test must give p > this (fixed seed)
const char* const kClasses[] = {"thermal (T = 1)",          "hot (T = 100)",    "cold (T = 1e-4)",
                                "very fast (|v| = 1e3, any direction)", "grazing (|v_y| = 1e-9 |v_t|)",
                                "normal incidence (v_x = v_z = 0)"};
constexpr std::size_t kClassCount = std::size(kClasses);

struct Emission {
  std::size_t cls = 0;
  int side = 0;
  Vec3 in, out;
  bool deterministic = false;  // the same outgoing velocity from a second, different stream
  bool specular = false;       // |v_y|, v_x and v_z kept
};

Vec3 incoming_velocity(std::size_t cls, int side, Rng& rng) {
  Vec3 v{rng.normal(), 0, rng.normal()};
  double vn = std::sqrt(-2.0 * std::log(rng.uniform_open0()));  // Rayleigh at T = 1
  switch (cls) {
    case 1: v = 10.0 * v, vn *= 10.0; break;
    case 2: v = 1e-2 * v, vn *= 1e-2; break;
    case 3: {
      const Vec3 u = 1e3 * rng.unit_vector();
      v = {u.x, 0, u.z};
      vn = std::max(std::fabs(u.y), 1e-300);
      break;
    }
    case 4: vn = 1e-9 * std::hypot(v.x, v.z); break;
    case 5: v = {0, 0, 0}; break;
    default: break;
  }
  v.y = side * vn;  // moving out through the plane of `side`
  return v;
}

// Hits from every class of incoming state, on both planes, each served twice on different streams.
Result feed_hits(const Subject& s, SlabHarness& h, std::vector<Emission>& out) {
  const double half = 0.5 * h.sys.box[1];
  StreamFactory second = h.factory;
  h.factory.set_step(0);
  second.set_step(1);
  for (std::size_t k = 0; k < kClassCount * kHitsPerClass; ++k) {
    Emission e;
    e.cls = k % kClassCount;
    e.side = (k / kClassCount) % 2 ? 1 : -1;
    Rng in_rng = StreamFactory::standalone(s.cfg.seed, k, StreamPurpose::host, 1);
    WallHit hit;
    hit.id = k;
    hit.side = e.side;
    hit.position = {h.sys.box[0] * in_rng.uniform(), e.side * half, h.sys.box[2] * in_rng.uniform()};
    hit.velocity = e.in = incoming_velocity(e.cls, e.side, in_rng);
    hit.time = 1.0 + 1e-4 * static_cast<double>(k % 1000);
    hit.remaining = 0.5 * kDt;
    h.ctx.time = hit.time;
    h.ctx.dt = kDt;
    WallHit again = hit;
    Rng rng = h.factory.rng(StreamPurpose::boundary, 0, k), rng2 = second.rng(StreamPurpose::boundary, 0, k);
    const HitResult result = h.boundary->interact(h.ctx, hit, rng);
    (void)h.boundary->interact(h.ctx, again, rng2);
    e.out = hit.velocity;
    if (result != HitResult::reflected)
      return fail("a wall (transfers() is false) returned 'transferred' for the hit " + vec_text(e.in) + " at the " +
                  (e.side < 0 ? "y_min" : "y_max") + " plane");
    if (!std::isfinite(e.out.x) || !std::isfinite(e.out.y) || !std::isfinite(e.out.z) || !(e.out.y * e.side < 0))
      return fail(fmt("re-emitted a %s particle (v = %s at the %s plane) with v = %s: not finite or not into the gas",
                      kClasses[e.cls], vec_text(e.in).c_str(), e.side < 0 ? "y_min" : "y_max", vec_text(e.out).c_str()));
    e.deterministic = e.out.x == again.velocity.x && e.out.y == again.velocity.y && e.out.z == again.velocity.z;
    e.specular = std::fabs(e.out.y) == std::fabs(e.in.y) && e.out.x == e.in.x && e.out.z == e.in.z;
    out.push_back(e);
  }
  return pass("");
}

struct ChiSquare {
  double chi2 = 0, p = 1;
  int dof = 0;
  std::size_t n = 0;
  std::string text(const char* what) const {
    return fmt("%s%schi2 = %.1f (%d dof, %zu values), p = %.3g", what, *what ? " " : "", chi2, dof, n, p);
  }
};

// Pearson's test of the probability-integral transforms u = F(v) against the uniform law on
// K equal bins (equiprobable bins of the exact distribution), `fitted` parameters estimated.
ChiSquare chi_square(const std::vector<double>& u, int bins, int fitted) {
  ChiSquare c;
  c.n = u.size();
  if (u.empty()) return c;
  std::vector<double> count(static_cast<std::size_t>(bins), 0.0);
  for (double x : u) count[std::min<std::size_t>(static_cast<std::size_t>(std::max(0.0, x) * bins), bins - 1)] += 1;
  const double expected = static_cast<double>(u.size()) / bins;
  for (double o : count) c.chi2 += (o - expected) * (o - expected) / expected;
  c.dof = bins - 1 - fitted;
  c.p = boost::math::gamma_q(0.5 * c.dof, 0.5 * c.chi2);
  return c;
}

// Pearson's test of independence between the incoming class and the bin of u (equiprobable bins
// of the model): does the emission depend on the incoming state? (C - 1)(K - 1) dof.
ChiSquare homogeneity(const std::vector<std::vector<double>>& per_class, int bins) {
  ChiSquare c;
  std::vector<std::vector<double>> count;
  std::vector<double> col(static_cast<std::size_t>(bins), 0.0), row;
  for (const auto& u : per_class) {
    if (u.empty()) continue;
    count.emplace_back(static_cast<std::size_t>(bins), 0.0);
    for (double x : u) {
      const std::size_t b = std::min<std::size_t>(static_cast<std::size_t>(std::max(0.0, x) * bins), bins - 1);
      count.back()[b] += 1;
      col[b] += 1;
    }
    row.push_back(static_cast<double>(u.size()));
    c.n += u.size();
  }
  if (count.size() < 2) return c;
  for (std::size_t r = 0; r < count.size(); ++r)
    for (int b = 0; b < bins; ++b) {
      const double e = row[r] * col[b] / static_cast<double>(c.n);
      if (e > 0) c.chi2 += (count[r][b] - e) * (count[r][b] - e) / e;
    }
  c.dof = static_cast<int>(count.size() - 1) * (bins - 1);
  c.p = boost::math::gamma_q(0.5 * c.dof, 0.5 * c.chi2);
  return c;
}

double find_param(const PluginUse& use, const char* name, bool& found) {
  found = false;
  for (const auto& spec : use.plugin->descriptor->parameters)
    if (spec.name == name && spec.type == ParamType::real && use.params.has(name)) {
      found = true;
      return use.params.real(name);
    }
  return 0;
}

// The chi-square tests of the diffuse emissions against the wall's exact distributions (T_w and
// the wall velocity from the parameters, else fitted), and of their independence of the
// incoming class.
struct FluxTests {
  bool has_t = false;
  ChiSquare normal, x, z, classes;
  std::string source;  // where T_w and the wall velocity came from
};

FluxTests flux_tests(const SlabHarness& h, const std::vector<const Emission*>& diffuse) {
  FluxTests t;
  const double mass = h.sys.mass;
  bool has_ux, has_uz;
  double tw = find_param(*h.use, "temperature", t.has_t);
  const double ux_param = find_param(*h.use, "velocity_x", has_ux), uz_param = find_param(*h.use, "velocity_z", has_uz);
  double sy2 = 0, sx = 0, sz = 0;
  for (const Emission* e : diffuse) sy2 += e->out.y * e->out.y, sx += e->out.x, sz += e->out.z;
  const double m = static_cast<double>(diffuse.size());
  const double tw_fit = 0.5 * mass * sy2 / m;  // <v_y^2> = 2 T_w / m for the Rayleigh law
  if (!t.has_t) tw = tw_fit;
  const double ux = has_ux ? ux_param : sx / m, uz = has_uz ? uz_param : sz / m;
  const double th = std::sqrt(tw / mass);
  auto rayleigh = [&](double v) { return -std::expm1(-0.5 * mass * v * v / tw); };
  auto gauss = [&](double v, double u) { return 0.5 * std::erfc(-(v - u) / (M_SQRT2 * th)); };
  std::vector<double> un, ux_t, uz_t;
  std::vector<std::vector<double>> per_class(kClassCount);
  for (const Emission* e : diffuse) {
    un.push_back(rayleigh(std::fabs(e->out.y)));
    per_class[e->cls].push_back(un.back());
    ux_t.push_back(gauss(e->out.x, ux));
    uz_t.push_back(gauss(e->out.z, uz));
  }
  const int fit_t = t.has_t ? 0 : 1;
  t.normal = chi_square(un, kBins, fit_t);
  t.x = chi_square(ux_t, kBins, fit_t + (has_ux ? 0 : 1));
  t.z = chi_square(uz_t, kBins, fit_t + (has_uz ? 0 : 1));
  t.classes = homogeneity(per_class, kClassBins);
  t.source = t.has_t ? fmt("T_w = %.6g from the parameter 'temperature'", tw) : fmt("T_w = %.6g fitted as m<v_y^2>/2", tw);
  t.source += fmt(" (sample m<v_y^2>/2 = %.6g); wall velocity (%.4g, %.4g) %s", tw_fit, ux, uz,
                  has_ux && has_uz ? "from velocity_x, velocity_z" : "(fitted where no parameter)");
  return t;
}

// The flux test on the stochastic (diffuse) part of the emissions; `label` names the run.
Result diffuse_flux(const SlabHarness& h, const std::vector<Emission>& all, const std::string& label) {
  // A diffuse emission reproduces the specular reflection of the incoming velocity with
  // probability 0: the specular outcomes are the specular part of a mixed (Maxwell) wall, the
  // others its diffuse part.
  std::vector<const Emission*> diffuse;
  std::size_t deterministic = 0, specular = 0;
  for (const auto& e : all) {
    deterministic += e.deterministic;
    if (e.specular) ++specular;
    else diffuse.push_back(&e);
  }
  const std::size_t n = all.size();
  if (deterministic == n || diffuse.empty())
    return skip(fmt("%s: not a diffuse wall: each of %zu hits from %zu classes of incoming state (thermal, hot, cold, "
                    "very fast, grazing, normal) was re-emitted %s, %zu of them specularly (|v_y|, v_x, v_z kept); the "
                    "flux test applies to diffuse emission", label.c_str(), n, kClassCount,
                    deterministic == n ? "deterministically (the same outgoing velocity from two different random streams)"
                                       : "specularly", specular));
  const FluxTests t = flux_tests(h, diffuse);
  const bool has_t = t.has_t;
  const ChiSquare &cn = t.normal, &cx = t.x, &cz = t.z;
  const std::string& t_source = t.source;
  const double m = static_cast<double>(diffuse.size());
  std::string mixed;
  if (specular > 0) {
    mixed = fmt("; %zu of %zu hits reflected specularly, the test is on the %zu others", specular, n, diffuse.size());
    bool has_a;
    const double alpha = find_param(*h.use, "accommodation", has_a);
    if (has_a && alpha > 0 && alpha < 1) {
      const double z = (m - alpha * n) / std::sqrt(n * alpha * (1 - alpha));
      mixed += fmt(" (fraction %.4f, accommodation %.4g: z = %.2f)", m / n, alpha, z);
      if (std::fabs(z) > 5)
        return fail(fmt("%s: the diffuse fraction %.4f of %zu hits differs from the accommodation %.4g by %.1f standard "
                        "deviations (allowed 5)", label.c_str(), m / n, n, alpha, z));
    }
  }
  const std::string data = "normal |v_y| against p(v) = (m v/T_w) exp(-m v^2/2T_w): " + cn.text("") +
                           "; tangential v_x, v_z against Gaussians of variance T_w/m: " + cx.text("v_x") + ", " +
                           cz.text("v_z") + "; " + t_source + mixed;
  // Diffuse means the same emission whatever the incoming state. A wall with a parameter
  // 'temperature' claims that; one without whose emission follows the incoming state is not diffuse
  // (e.g. a Cercignani-Lampis kernel) and is skipped.
  const ChiSquare& ch = t.classes;
  if (!(ch.p > kSignificance)) {
    const std::string m = fmt("%s: the emitted normal component depends on the incoming state (thermal, hot, cold, "
                              "very fast, grazing, normal; independence test on %d bins: ", label.c_str(), kClassBins) +
                          ch.text("") + "); " + data;
    if (!has_t) return skip("not a diffuse wall (and no parameter 'temperature' claims one): " + m);
    return fail("wall flux: " + m);
  }
  const char* names[] = {"normal |v_y|", "tangential v_x", "tangential v_z"};
  const ChiSquare* tests[] = {&cn, &cx, &cz};
  for (int k = 0; k < 3; ++k)
    if (!(tests[k]->p > kSignificance))
      return fail(fmt("%s: wall flux: the emitted %s does not follow the half-range Maxwellian flux at T_w "
                      "(p = %.3g < %.0e): ", label.c_str(), names[k], tests[k]->p, kSignificance) + data);
  return pass(fmt("%s: %zu hits from %zu classes of incoming state, both planes; Pearson chi-square on %d equiprobable "
                  "bins, each p > %.0e (fixed seed): ", label.c_str(), n, kClassCount, kBins, kSignificance) + data +
              fmt("; independent of the incoming state (%zu classes x %d bins of |v_y|): ", kClassCount, kClassBins) +
              ch.text(""));
}

Result fed_flux(const Subject& s, const Assignment& a, const std::string& label, std::vector<Emission>& em,
                std::unique_ptr<SlabHarness>& h) {
  h = make_slab(s, a, 16);
  if (!h->refusal.empty()) return skip(h->refusal + " (a refusal in begin() is allowed)");
  Result r = feed_hits(s, *h, em);
  if (r.status != Status::pass) return fail(label + ": " + r.message);
  return diffuse_flux(*h, em, label);
}

bool has_real_param(const Subject& s, const char* name) {
  for (const auto& p : s.desc().parameters)
    if (p.name == name && p.type == ParamType::real) return true;
  return false;
}

}  // namespace

Result check_boundary_wall_flux(const Subject& s) {
  {
    auto h = make_slab(s, base_assignment(s), 16);
    if (h->boundary->transfers())
      return skip("transfers particles to the opposite plane (transfers() is true): not a wall (see boundary.transfer)");
  }
  std::vector<Emission> em;
  std::unique_ptr<SlabHarness> h;
  return fed_flux(s, base_assignment(s), "with " + describe_assignment(s, base_assignment(s)), em, h);
}

// A wall with a parameter `accommodation`: 0 must reproduce specular reflection, 1 diffuse emission.
Result check_boundary_accommodation(const Subject& s) {
  if (!has_real_param(s, "accommodation")) return skip("no real parameter 'accommodation'");
  std::vector<std::string> notes;
  {
    Assignment a = base_assignment(s);
    a["accommodation"] = "0";
    std::vector<Emission> em;
    std::unique_ptr<SlabHarness> h;
    h = make_slab(s, a, 16);
    if (!h->refusal.empty()) return skip(h->refusal + " (a refusal in begin() is allowed)");
    const Result fed = feed_hits(s, *h, em);
    if (fed.status != Status::pass) return fail("accommodation 0: " + fed.message);
    for (const auto& e : em)
      if (!e.specular || !e.deterministic)
        return fail(fmt("accommodation 0 does not reproduce specular reflection: a %s particle hitting the %s plane with "
                        "v = %s was re-emitted with v = %s%s", kClasses[e.cls], e.side < 0 ? "y_min" : "y_max",
                        vec_text(e.in).c_str(), vec_text(e.out).c_str(),
                        e.deterministic ? "" : " (and differently from another random stream)"));
    notes.push_back(fmt("accommodation 0: all %zu hits reflected specularly (|v_y|, v_x, v_z kept exactly)", em.size()));
  }
  {
    Assignment a = base_assignment(s);
    a["accommodation"] = "1";
    std::vector<Emission> em;
    std::unique_ptr<SlabHarness> h;
    const Result r = fed_flux(s, a, "accommodation 1", em, h);
    if (r.status != Status::pass) return r.status == Status::skip ? fail("accommodation 1 is not diffuse: " + r.message) : r;
    for (const auto& e : em)
      if (e.deterministic)
        return fail(fmt("accommodation 1 is not fully diffuse: a %s hit with v = %s was re-emitted deterministically "
                        "with v = %s", kClasses[e.cls], vec_text(e.in).c_str(), vec_text(e.out).c_str()));
    notes.push_back(r.message);
  }
  return pass(join(notes, "; "));
}

// A transferring boundary (periodic, Lees-Edwards): re-entry on the opposite plane with v_y and v_z
// kept and v_x changed by exactly -+ a L (a = the published "shear_rate", 0 when none).
Result check_boundary_transfer(const Subject& s) {
  Streamed r = streamed_slab(s, base_assignment(s));
  SlabHarness& h = *r.h;
  if (!h.boundary->transfers()) return skip("a wall (transfers() is false): nothing is transferred");
  if (!h.refusal.empty()) return skip(h.refusal + " (a refusal in begin() is allowed)");
  if (!r.error.empty()) return skip("needs a boundary that passes boundary.containment (the mover stopped: " + r.error + ")");
  const double* published = h.board.find("shear_rate");
  const double a = published ? *published : 0.0, L = h.sys.box[1], slip = a * L;
  const double half = 0.5 * L;
  double scale = 0;
  for (const HitRecord& hr : h.recorder->log) {
    const Vec3 &vi = hr.in.velocity, &vo = hr.out.velocity;
    scale += std::fabs(vi.x) + std::fabs(slip);
    if (hr.result != HitResult::transferred)
      return fail("transfers() is true but a hit was reflected: " + hit_text(hr));
    if (std::fabs(hr.out.position.y + hr.in.side * half) > 1e-12 * L)
      return fail(fmt("re-entry not on the opposite plane y = %g: ", -hr.in.side * half) + hit_text(hr));
    if ((vo.y != vi.y && vi.y != 0) || vo.z != vi.z)
      return fail("v_y or v_z changed by a transfer (momentum in the sheared frame not kept): " + hit_text(hr));
    const double dvx = vo.x - vi.x, expected = -hr.in.side * slip;
    if (std::fabs(dvx - expected) > 4 * kEps * (std::fabs(vi.x) + std::fabs(slip)))
      return fail(fmt("v_x changed by %.17g at a transfer, expected -+ a L = %.17g (a = %g %s, L = %g): momentum in the "
                      "sheared frame not kept: ", dvx, expected, a, published ? "published 'shear_rate'" : "(none published)",
                      L) + hit_text(hr));
  }
  const auto n_up = static_cast<double>(h.tally.sides[1].hits), n_down = static_cast<double>(h.tally.sides[0].hits);
  const double sum = h.tally.sides[0].momentum[0] + h.tally.sides[1].momentum[0];
  const double expected = -slip * (n_up - n_down);
  const double tol = 8 * kEps * scale + 1e-300;
  if (std::fabs(sum - expected) > tol)
    return fail(fmt("momentum in the sheared frame not kept: the sum of Delta v_x over the transfers is %.17g, "
                    "-(a L)(N_up - N_down) = %.17g (a = %g, L = %g, N_up = %.0f through y_max, N_down = %.0f through y_min; "
                    "round-off tolerance %.3g)", sum, expected, a, L, n_up, n_down, tol));
  return pass(fmt("%s: %.0f transfers (%.0f through y_max, %.0f through y_min), each re-entering on the opposite plane "
                  "with v_y, v_z kept; sum of Delta v_x = %.12g = -(a L)(N_up - N_down) = %.12g with a = %.6g (%s), L = %g "
                  "(difference %.2g, round-off tolerance %.2g): momentum kept in the sheared frame", kSetup, n_up + n_down,
                  n_up, n_down, sum, expected, a, published ? "published 'shear_rate'" : "none published: 0", L,
                  std::fabs(sum - expected), tol));
}

}  // namespace gdsmc::host::conformance
