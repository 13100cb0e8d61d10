// Initial-state checks.
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

Result check_initial_state(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  const std::string bad = nonfinite_in(h->span());
  if (!bad.empty()) return fail("the generated state is not finite: " + bad);
  const double T = h->global.temperature;
  if (!(T > 0) || !std::isfinite(T)) return fail(fmt("the generated state has temperature %g", T));
  return pass(fmt("%zu particles: finite positions, velocities and attributes; T = %.6g T0, mean velocity %s", n,
                  T / h->sys.initial_temperature,
                  vec_text({h->global.mean_velocity[0], h->global.mean_velocity[1], h->global.mean_velocity[2]}).c_str()));
}

}  // namespace gdsmc::host::conformance
