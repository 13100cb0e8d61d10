// Forcing checks: declared conservation and integration order.
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Forcings

Result check_forcing_conservation(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  auto* f = static_cast<Forcing*>(h->subject.get());
  const Conservation c = f->conserves();
  const ParticleSpan p = h->span();
  auto totals = [&](Vec3& mom, double& energy, double& abs_sum) { velocity_totals(p, mom, energy, abs_sum); };
  Vec3 p0, p1;
  double e0, e1, a0, a1;
  totals(p0, e0, a0);
  constexpr int steps = 10;
  for (int k = 0; k < steps; ++k) {
    h->update_moments();
    Rng rng = h->ctx.rng(StreamPurpose::forcing, 0);
    f->apply(h->ctx, p, rng);
    h->ctx.time += h->ctx.dt;
    ++h->ctx.step;
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

Result check_forcing_order(const Subject& s) {
  constexpr std::size_t n = 500;
  auto h = make_harness(s, base_assignment(s), n);
  const Snapshot s0 = h->save();
  const double scale = std::sqrt(h->global.temperature);
  auto run = [&](double dt, int substeps, std::uint32_t unit) {
    h->restore(s0);
    auto obj = h->fresh_subject();
    auto* f = static_cast<Forcing*>(obj.get());
    h->ctx.step = 0;
    h->ctx.time = 0;
    for (int k = 0; k < substeps; ++k) {
      h->update_moments();
      h->ctx.dt = dt;
      Rng rng(h->ctx.key, StreamPurpose::forcing, unit, h->ctx.step);
      f->apply(h->ctx, h->span(), rng);
      h->ctx.time += dt;
      ++h->ctx.step;
    }
    return h->save();
  };
  auto diff = [&](const Snapshot& a, const Snapshot& b) {
    double d = 0;
    for (std::size_t i = 0; i < n; ++i)
      d = std::max({d, std::fabs(a.vx[i] - b.vx[i]), std::fabs(a.vy[i] - b.vy[i]), std::fabs(a.vz[i] - b.vz[i])});
    return d / scale;
  };
  const double dt0 = kTimeStepTau0 * h->sys.time_unit0;
  if (diff(run(dt0, 1, 0), run(dt0, 1, 1u << 16)) > 0)
    return skip("the forcing is stochastic (its result depends on the random stream): the dt-scaling check applies "
                "to deterministic forcings");
  const int order = static_cast<Forcing*>(h->subject.get())->order();
  double D[3];
  for (int k = 0; k < 3; ++k) {
    const double dt = dt0 / std::pow(2.0, k);
    D[k] = diff(run(dt, 1, 0), run(0.5 * dt, 2, 0));
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
