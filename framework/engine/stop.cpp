#include "engine/stop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gdsmc::host {

std::optional<bool> is_steady(const SteadyStop& st, const DiagnosticOutput& out) {
  const DiagnosticOutput::Column* col = nullptr;
  for (const auto& c : out.columns)
    if (c.name == st.column) col = &c;
  if (!col) {
    throw std::runtime_error("run.stop.steady: diagnostic '" + st.group + "' has no series '" + st.column + "'");
  }
  const auto& s = out.collisions_per_particle;
  if (s.empty() || s.back() < 2 * st.window) return std::nullopt;
  double sum[2] = {0, 0};
  std::size_t n[2] = {0, 0};
  for (std::size_t k = s.size(); k-- > 0;) {
    const double age = s.back() - s[k];
    if (age >= 2 * st.window) break;
    const int w = age < st.window ? 1 : 0;
    sum[w] += col->values[k];
    ++n[w];
  }
  if (n[0] < 3 || n[1] < 3) return std::nullopt;
  const double older = sum[0] / static_cast<double>(n[0]), newer = sum[1] / static_cast<double>(n[1]);
  return std::fabs(newer - older) <= st.tolerance * std::fabs(newer);
}

bool finished(const Pipeline& p, const StepContext& ctx, bool steady) {
  if (steady) return true;
  if (p.stop_collisions_per_particle && ctx.collisions_per_particle() >= *p.stop_collisions_per_particle) return true;
  if (p.stop_time_tau0 && ctx.time_in_tau0() >= *p.stop_time_tau0 * (1.0 - 1e-12)) return true;
  return false;
}

double stop_fraction(const Pipeline& p, const StepContext& ctx) {
  double f = 0;
  if (p.stop_collisions_per_particle) f = std::max(f, ctx.collisions_per_particle() / *p.stop_collisions_per_particle);
  if (p.stop_time_tau0) f = std::max(f, ctx.time_in_tau0() / *p.stop_time_tau0);
  return std::min(1.0, f);
}

}  // namespace gdsmc::host
