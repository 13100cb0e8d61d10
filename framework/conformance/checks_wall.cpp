// Boundary checks: containment (and the wall flux, not available yet).
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Boundaries, initial states, diagnostics

Result check_boundary_containment(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  h->sys.geometry = Geometry::slab;
  auto* b = static_cast<Boundary*>(h->subject.get());
  const ParticleSpan p = h->span();
  const double L[3] = {h->sys.box[0], h->sys.box[1], h->sys.box[2]};
  constexpr int steps = 20;
  for (int k = 0; k < steps; ++k) {
    const double dt = 0.5 * h->sys.time_unit0;  // long enough that many particles cross a face
    for (std::size_t i = 0; i < n; ++i) {
      p.x[i] += p.vx[i] * dt;
      p.y[i] += p.vy[i] * dt;
      p.z[i] += p.vz[i] * dt;
    }
    h->ctx.dt = dt;
    h->update_moments();
    Rng rng = h->ctx.rng(StreamPurpose::boundary, 0);
    b->apply(h->ctx, p, rng);
    h->ctx.time += dt;
    ++h->ctx.step;
    const std::string bad = nonfinite_in(p);
    if (!bad.empty()) return fail(fmt("particle lost: after step %d %s", k + 1, bad.c_str()));
    for (std::size_t i = 0; i < n; ++i) {
      const double tol = 1e-9;
      const bool inside = p.x[i] >= -tol * L[0] && p.x[i] <= L[0] * (1 + tol) && p.y[i] >= -0.5 * L[1] * (1 + tol) &&
                          p.y[i] <= 0.5 * L[1] * (1 + tol) && p.z[i] >= -tol * L[2] && p.z[i] <= L[2] * (1 + tol);
      if (!inside)
        return fail(fmt("particle left outside the domain [0, %g] x [-%g, %g] x [0, %g] after step %d: particle %zu at %s",
                        L[0], 0.5 * L[1], 0.5 * L[1], L[2], k + 1, i, vec_text(p.position(i)).c_str()));
    }
  }
  return pass(fmt("%zu particles streamed %d times across the faces: none lost, none left outside the domain", n, steps));
}

Result check_boundary_wall_flux(const Subject&) {
  return skip("goodness-of-fit of the half-range Maxwellian flux emitted by diffuse walls: not available until the SDK "
              "describes walls (temperature, velocity) to the runner");
}


}  // namespace gdsmc::host::conformance
