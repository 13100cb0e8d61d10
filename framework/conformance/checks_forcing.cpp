// Forcing checks: declared conservation, the energy apply() returns, the declared mean energy input
// of a stochastic forcing, and the integration order.
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Forcings

namespace {

// A forcing that declares a constant acceleration is integrated by the host's mover and never
// applied: returns its g, or nothing.
std::optional<Vec3> declared_acceleration(const Forcing& f) {
  Vec3 g{0, 0, 0};
  if (f.acceleration(g)) return g;
  return std::nullopt;
}

// One apply() of the forcing at the harness's current step, with its own streams; returns what
// apply() returned.
double apply_once(Harness& h, Forcing& f) {
  h.update_moments();
  h.plugin_streams_for(StreamPurpose::forcing);
  const double added = f.apply(h.ctx, h.span());
  h.ctx.streams = nullptr;
  h.ctx.time += h.ctx.dt;
  ++h.ctx.step;
  return added;
}

}  // namespace

Result check_forcing_conservation(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  auto* f = static_cast<Forcing*>(h->subject.get());
  const Conservation c = f->conserves();
  if (const auto g = declared_acceleration(*f)) {
    // Integrated exactly by the host (x += v t + g t^2/2): it adds momentum g per unit time and
    // mass, so it conserves neither momentum nor energy unless g = 0.
    const bool zero = g->x == 0 && g->y == 0 && g->z == 0;
    if (!zero && (c.momentum || c.energy))
      return fail(fmt("declares the constant acceleration g = %s (integrated by the host) but conserves() claims %s: "
                      "a nonzero body acceleration conserves neither momentum nor energy", vec_text(*g).c_str(),
                      c.momentum ? "momentum" : "energy"));
    return skip(fmt("declares the constant acceleration g = %s: the host integrates it during free flight and never "
                    "calls apply(); conserves() claims nothing it cannot keep", vec_text(*g).c_str()));
  }
  const ParticleSpan p = h->span();
  auto totals = [&](Vec3& mom, double& energy, double& abs_sum) { velocity_totals(p, mom, energy, abs_sum); };
  Vec3 p0, p1;
  double e0, e1, a0, a1;
  totals(p0, e0, a0);
  constexpr int steps = 10;
  for (int k = 0; k < steps; ++k) {
    (void)apply_once(*h, *f);
    const std::string bad = nonfinite_in(p);
    if (!bad.empty()) return fail(fmt("not finite after %d steps: %s", k + 1, bad.c_str()));
  }
  totals(p1, e1, a1);
  std::vector<std::string> ok;
  if (c.momentum) {
    const double tol = 64 * kEps * (a0 + a1) * steps;
    if (norm(p1 - p0) > tol)
      return fail(fmt("momentum not conserved although conserves() declares it: total momentum changed by %s "
                      "(|dp| = %.3g, tolerance %.3g) in %d steps of dt = %g tau0", vec_text(p1 - p0).c_str(),
                      norm(p1 - p0), tol, steps, kTimeStepTau0));
    ok.push_back(fmt("momentum (|dp| = %.2g)", norm(p1 - p0)));
  }
  if (c.energy) {
    const double tol = 64 * kEps * (e0 + e1) * steps;
    if (std::fabs(e1 - e0) > tol)
      return fail(fmt("energy not conserved although conserves() declares it: kinetic energy changed from %.12g to "
                      "%.12g (tolerance %.3g) in %d steps of dt = %g tau0", e0, e1, tol, steps, kTimeStepTau0));
    ok.push_back(fmt("energy (|dE| = %.2g)", std::fabs(e1 - e0)));
  }
  if (ok.empty())
    return skip(fmt("conserves() declares neither momentum nor energy: nothing to check (the state stayed finite "
                    "over %d steps)", steps));
  return pass("conserves what it declares over " + std::to_string(steps) + " steps: " + join(ok, "; "));
}

// apply() returns the kinetic energy it added: it must equal the measured change of the
// particles' kinetic energy to round-off (relative 1e-9 of the total kinetic energy).
Result check_forcing_energy(const Subject& s) {
  constexpr std::size_t n = 1000;
  constexpr int steps = 10;
  constexpr double rel = 1e-9;
  auto h = make_harness(s, base_assignment(s), n);
  auto* f = static_cast<Forcing*>(h->subject.get());
  if (const auto g = declared_acceleration(*f))
    return skip(fmt("declares the constant acceleration g = %s: the host integrates it and records its energy; "
                    "apply() is never called", vec_text(*g).c_str()));
  const ParticleSpan p = h->span();
  double worst = 0, total_added = 0, total_returned = 0;
  for (int k = 0; k < steps; ++k) {
    Vec3 mom;
    double e0, e1, speeds;
    velocity_totals(p, mom, e0, speeds);
    const double returned = apply_once(*h, *f);
    velocity_totals(p, mom, e1, speeds);
    if (!std::isfinite(returned)) return fail(fmt("apply() returned the energy %g at step %d", returned, k + 1));
    const double diff = std::fabs((e1 - e0) - returned), scale = std::max(e0, e1);
    if (diff > rel * scale)
      return fail(fmt("the energy apply() returns differs from the measured change: at step %d apply() returned %.12g, "
                      "the particles' kinetic energy changed by %.12g (from %.12g to %.12g; tolerance %.0e of the total "
                      "kinetic energy = %.3g)", k + 1, returned, e1 - e0, e0, e1, rel, rel * scale));
    worst = std::max(worst, diff / scale);
    total_added += e1 - e0;
    total_returned += returned;
  }
  return pass(fmt("%d steps of dt = %g tau0 on %zu particles: apply() returned %.10g in total, the measured change is "
                  "%.10g (worst step: %.2g of the kinetic energy, tolerance %.0e)", steps, kTimeStepTau0, n,
                  total_returned, total_added, worst, rel));
}

// A forcing that declares its mean energy input (expected_energy_rate(), e.g. a white-noise
// thermostat's heating rate): over many steps the mean measured input per unit time must agree
// with the declared rate (queried before each step, from the state apply() will see) within
// 4 standard errors, estimated from the scatter of batch means (batches of 10 steps, so that short
// step-to-step correlations do not shrink the error), plus a round-off allowance.
Result check_forcing_expected_energy(const Subject& s) {
  constexpr std::size_t n = 1000;
  constexpr int batches = 40, batch_steps = 10;
  constexpr double z_max = 4;
  auto h = make_harness(s, base_assignment(s), n);
  auto* f = static_cast<Forcing*>(h->subject.get());
  if (const auto g = declared_acceleration(*f))
    return skip(fmt("declares the constant acceleration g = %s: the host integrates it and records its energy",
                    vec_text(*g).c_str()));
  const ParticleSpan p = h->span();
  double probe = 0;
  h->update_moments();
  if (!f->expected_energy_rate(h->ctx, p, probe))
    return skip("declares no expected energy input (expected_energy_rate() returns false): nothing to compare; "
                "forcing.energy still checks what apply() returns");
  const double dt = h->ctx.dt;
  std::vector<double> excess(batches, 0.0);  // per batch: mean (measured - declared) input per unit time
  double measured_total = 0, declared_total = 0, scale = 0;
  for (int b = 0; b < batches; ++b) {
    for (int k = 0; k < batch_steps; ++k) {
      h->update_moments();
      double rate = 0;
      if (!f->expected_energy_rate(h->ctx, p, rate))
        return fail(fmt("expected_energy_rate() declared a rate at the first step but not at step %d",
                        b * batch_steps + k + 1));
      if (!std::isfinite(rate)) return fail(fmt("expected_energy_rate() declared the rate %g", rate));
      Vec3 mom;
      double e0, e1, speeds;
      velocity_totals(p, mom, e0, speeds);
      (void)apply_once(*h, *f);
      velocity_totals(p, mom, e1, speeds);
      if (!std::isfinite(e1)) return fail(fmt("the kinetic energy is %g after step %d", e1, b * batch_steps + k + 1));
      measured_total += e1 - e0;
      declared_total += rate * dt;
      excess[b] += ((e1 - e0) - rate * dt) / (batch_steps * dt);
      scale = std::max({scale, e0, e1});
    }
  }
  const int steps = batches * batch_steps;
  const double time = steps * dt;
  const double mean = std::accumulate(excess.begin(), excess.end(), 0.0) / batches;
  double var = 0;
  for (double x : excess) var += (x - mean) * (x - mean);
  var /= batches - 1;
  const double se = std::sqrt(var / batches);
  const double roundoff = 1e-9 * scale / dt;  // per unit time
  const double tol = z_max * se + roundoff;
  const std::string data =
      fmt("over %d steps of dt = %g tau0 on %zu particles the measured mean energy input is %.6g per unit time "
          "(%.6g per tau0), the declared %.6g (%.6g per tau0): difference %.4g = %.2f standard errors (standard "
          "error %.3g from the scatter of %d batch means of %d steps; tolerance %g standard errors)",
          steps, kTimeStepTau0, n, measured_total / time, measured_total / time * h->sys.time_unit0,
          declared_total / time, declared_total / time * h->sys.time_unit0, mean, se > 0 ? mean / se : 0.0, se,
          batches, batch_steps, z_max);
  if (std::fabs(mean) > tol)
    return fail("the mean energy input differs from the declared expected_energy_rate(): " + data);
  return pass("the mean energy input agrees with the declared expected_energy_rate(): " + data);
}

Result check_forcing_order(const Subject& s) {
  constexpr std::size_t n = 500;
  auto h = make_harness(s, base_assignment(s), n);
  if (const auto g = declared_acceleration(*static_cast<Forcing*>(h->subject.get())))
    return skip(fmt("declares the constant acceleration g = %s: integrated exactly by the host's mover",
                    vec_text(*g).c_str()));
  const Snapshot s0 = h->save();
  const double scale = std::sqrt(h->global.temperature);
  // `seed` picks the run's streams: the same seed for every dt, another to detect a stochastic forcing.
  auto run = [&](double dt, int substeps, std::uint64_t seed) {
    h->restore(s0);
    auto obj = h->fresh_subject();
    auto* f = static_cast<Forcing*>(obj.get());
    h->factory = StreamFactory(seed, 0);
    h->ctx.step = 0;
    h->ctx.time = 0;
    h->ctx.dt = dt;
    for (int k = 0; k < substeps; ++k) (void)apply_once(*h, *f);
    return h->save();
  };
  auto diff = [&](const Snapshot& a, const Snapshot& b) {
    double d = 0;
    for (std::size_t i = 0; i < n; ++i)
      d = std::max({d, std::fabs(a.vx[i] - b.vx[i]), std::fabs(a.vy[i] - b.vy[i]), std::fabs(a.vz[i] - b.vz[i])});
    return d / scale;
  };
  const double dt0 = kTimeStepTau0 * h->sys.time_unit0;
  const std::uint64_t seed = s.cfg.seed;
  if (diff(run(dt0, 1, seed), run(dt0, 1, seed + 1)) > 0)
    return skip("the forcing is stochastic (its result depends on the random stream): the dt-scaling check applies "
                "to deterministic forcings");
  const int order = static_cast<Forcing*>(h->subject.get())->order();
  double D[3];
  for (int k = 0; k < 3; ++k) {
    const double dt = dt0 / std::pow(2.0, k);
    D[k] = diff(run(dt, 1, seed), run(0.5 * dt, 2, seed));
    if (!std::isfinite(D[k])) return fail(fmt("one step of dt = %g tau0 or two of dt/2 gave non-finite velocities", dt / h->sys.time_unit0));
  }
  const double floor = 1e-12;
  const std::string data = fmt("|one step of dt - two of dt/2| / sqrt(T) = %.3g, %.3g, %.3g at dt = %g, %g, %g tau0", D[0],
                               D[1], D[2], kTimeStepTau0, kTimeStepTau0 / 2, kTimeStepTau0 / 4);
  if (order <= 0) {
    if (D[0] > floor) return fail("declares order 0 (exact) but " + data);
    return pass("exact as declared (order 0): " + data);
  }
  if (D[0] <= floor) return pass(fmt("agrees to round-off (better than the declared order %d): ", order) + data);
  const double q = D[2] > floor ? std::log2(D[1] / D[2]) : D[1] > floor ? std::log2(D[0] / D[1]) : INFINITY;
  if (q < order + 1 - 0.3)
    return fail(fmt("declares order %d (one-step error O(dt^%d)) but the difference between one step of dt and two of "
                    "dt/2 scales as dt^%.2f: ", order, order + 1, q) + data);
  return pass(fmt("declared order %d: the one-step difference scales as dt^%.2f (expected >= %d): ", order, q, order + 1) + data);
}

}  // namespace gdsmc::host::conformance
