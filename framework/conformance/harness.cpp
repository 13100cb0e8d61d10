// A small engine-like harness for direct calls on plugin objects (see harness.hpp).
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// A small engine-like harness for direct calls on plugin objects


std::unique_ptr<Harness> make_harness(const Subject& s, const Assignment& a, std::size_t n) {
  auto h = std::make_unique<Harness>();
  h->pipeline = load_test_pipeline(s, a, n);
  const Pipeline& p = *h->pipeline;
  h->use = &slot(p, s.kind());
  h->initial = create_object(*p.initial_state.plugin, p.initial_state.params);
  h->collision = create_object(*p.collision.plugin, p.collision.params);
  if (s.kind() == PluginKind::initial_state) h->subject = h->initial;
  else if (s.kind() == PluginKind::collision_rule) h->subject = h->collision;
  else h->subject = h->fresh_subject();
  std::vector<std::shared_ptr<PluginObject>> objects{h->initial, h->collision};
  if (h->subject != h->initial && h->subject != h->collision) objects.push_back(h->subject);
  for (const auto& f : p.forcings)  // the context's forcings (they may publish quantities)
    if (&f != h->use) objects.push_back(create_object(*f.plugin, f.params));
  for (const auto& o : objects)
    for (auto& at : o->attributes()) h->attributes.push_back(std::move(at));
  h->store.allocate(n, h->attributes);
  for (const auto& o : objects) o->publish(h->board);

  h->sys = p.system_info(n, 0);
  h->sys.seed = s.cfg.seed;
  const SystemInfo& sys = h->sys;

  StepContext& ctx = h->ctx;
  ctx.system = &h->sys;
  ctx.quantities = &h->board;
  ctx.key = stream_key(s.cfg.seed, 0);
  ctx.cells = &h->global;
  ctx.cell_count = 1;
  ctx.global = &h->global;
  ctx.dt = kTimeStepTau0 * sys.time_unit0;

  Rng rng(ctx.key, StreamPurpose::initial_state, 0, 0);
  static_cast<InitialState*>(h->initial.get())->generate(h->sys, h->span(), rng);
  h->update_moments();
  return h;
}

bool all_finite(const double* d, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(d[k])) return false;
  return true;
}

// First non-finite entry of the particle state, or "" when everything is finite.
std::string nonfinite_in(const ParticleSpan& p, bool positions) {
  const std::pair<const char*, const double*> arrays[] = {{"x", p.x}, {"y", p.y}, {"z", p.z},
                                                           {"vx", p.vx}, {"vy", p.vy}, {"vz", p.vz}};
  for (const auto& [name, d] : arrays) {
    if (!positions && name[0] != 'v') continue;
    for (std::size_t k = 0; k < p.count; ++k)
      if (!std::isfinite(d[k])) return fmt("%s of particle %zu is %g", name, k, d[k]);
  }
  for (std::size_t a = 0; a < p.attribute_count; ++a) {
    const std::size_t n = p.count * static_cast<std::size_t>(p.attribute_specs[a].components);
    for (std::size_t k = 0; k < n; ++k)
      if (!std::isfinite(p.attribute_data[a][k]))
        return fmt("attribute '%s' entry %zu is %g", p.attribute_specs[a].name.c_str(), k, p.attribute_data[a][k]);
  }
  return "";
}

}  // namespace gdsmc::host::conformance
