// The conformance harness (see harness.hpp), built from the engine's pieces.
#include "config/system_info.hpp"
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {

Snapshot Particles::save() {
  const ParticleSpan p = span();
  Snapshot s;
  auto copy = [&](const double* d) { return d ? std::vector<double>(d, d + p.count) : std::vector<double>(); };
  s.id.assign(p.id, p.id + p.count);
  s.x = copy(p.x.data); s.y = copy(p.y.data); s.z = copy(p.z.data);
  s.vx = copy(p.vx.data); s.vy = copy(p.vy.data); s.vz = copy(p.vz.data);
  for (std::size_t a = 0; a < p.attribute_count; ++a)
    s.attributes.emplace_back(p.attribute_data[a], p.attribute_data[a] + p.count * p.attribute_specs[a].components);
  return s;
}

void Particles::restore(const Snapshot& s, const std::vector<std::uint32_t>* perm) {
  const ParticleSpan p = span();
  std::uint32_t* id = store.ids();
  for (std::size_t k = 0; k < p.count; ++k) {
    const std::size_t i = perm ? (*perm)[k] : k;
    id[k] = s.id[i];
    if (p.x) {
      p.x[k] = s.x[i]; p.y[k] = s.y[i]; p.z[k] = s.z[i];
    }
    p.vx[k] = s.vx[i]; p.vy[k] = s.vy[i]; p.vz[k] = s.vz[i];
    for (std::size_t a = 0; a < p.attribute_count; ++a) {
      const std::size_t comps = static_cast<std::size_t>(p.attribute_specs[a].components);
      for (std::size_t c = 0; c < comps; ++c) p.attribute_data[a][c * p.count + k] = s.attributes[a][c * p.count + i];
    }
  }
}

std::shared_ptr<PluginObject> Harness::fresh_subject() const { return create_object(*use->plugin, use->params); }

void Harness::randomize_zero_attributes(Rng& rng) {
  const ParticleSpan p = span();
  for (std::size_t a = 0; a < p.attribute_count; ++a) {
    const std::size_t n = p.count * static_cast<std::size_t>(p.attribute_specs[a].components);
    double* d = p.attribute_data[a];
    if (std::all_of(d, d + n, [](double v) { return v == 0.0; }))
      for (std::size_t k = 0; k < n; ++k) d[k] = rng.normal();
  }
}

CollisionStage::Totals Harness::collide(double dt, double sigma) {
  const auto* rule = static_cast<const CollisionRule*>(collision.get());
  factory.set_step(ctx.step);
  const CollisionStage::Totals t = stage.run(*rule, span(), grid, grid.is_slab() ? cells.data() : nullptr,
                                             global.temperature, sys.mass, sigma > 0 ? sigma : sys.sigma, dt, factory);
  ctx.collisions += t.accepted;
  ctx.candidates += t.candidates;
  ctx.majorant_exceeded += t.majorant_exceeded;
  ctx.collision_energy_change += t.energy_change;
  update_moments();
  return t;
}

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
  for (std::size_t b = 0; b < p.boundaries.size(); ++b)  // a slab context's (Lees-Edwards publishes 'shear_rate')
    if (b == 0 || p.boundaries[b].plugin != p.boundaries[0].plugin)
      objects.push_back(create_object(*p.boundaries[b].plugin, p.boundaries[b].params));
  for (const auto& o : objects)
    for (auto& at : o->attributes()) h->attributes.push_back(std::move(at));
  h->sys = system_info(p, n, 0);
  h->particles.allocate(n, h->attributes, h->sys.geometry == Geometry::slab);
  for (const auto& o : objects) o->publish(h->board);

  h->sys.seed = s.cfg.seed;
  auto* rule = static_cast<CollisionRule*>(h->collision.get());
  rule->begin(h->sys, h->board);  // after every publish, as the engine does
  h->stage.set_tally_count(rule->tallies().size());
  if (h->sys.geometry == Geometry::slab) {
    h->grid.slab(n, h->sys.cells, h->sys.box[1], h->sys.cross_section());
    h->ctx.boundaries = h->tallies.data();
    h->ctx.boundary_count = 2;
  } else {
    h->grid.homogeneous(n, h->sys.volume);
  }
  h->grid.set_sampling_system(&h->sys);  // the bins of SampledMoments::bin_sums
  h->factory = StreamFactory(s.cfg.seed, 0);

  StepContext& ctx = h->ctx;
  ctx.system = &h->sys;
  ctx.quantities = &h->board;
  ctx.dt = kTimeStepTau0 * h->sys.time_unit0;

  h->factory.set_step(0);
  static_cast<InitialState*>(h->initial.get())
      ->generate(h->sys, h->board, h->span(), h->factory.streams(StreamPurpose::initial_state, 0));
  static_cast<CollisionRule*>(h->collision.get())->bind(h->span());  // once: the storage never moves
  h->grid.assign_and_sort(h->span().y.data, h->particles.cells(), n);
  h->update_moments();
  ctx.cells = h->cells.data();
  ctx.cell_count = h->cells.size();
  ctx.global = &h->global;
  return h;
}

std::string SlabHarness::side_name(int side) const {
  return std::string(side < 0 ? "boundaries.y_min" : "boundaries.y_max") + " (plugin '" +
         use->plugin->descriptor->name + "')";
}

void SlabHarness::stream(int steps, double dt) {
  const Boundary* b = pool ? boundary : recorder.get();
  const Mover mover(sys.box, Vec3{0, 0, 0}, {Mover::Side{b, side_name(-1)}, Mover::Side{b, side_name(+1)}});
  const ParticleSpan p = span();
  for (int k = 0; k < steps; ++k) {
    factory.set_step(step);
    ctx.step = step;
    ctx.time = time;
    ctx.dt = dt;
    mover.stream(p, particles.cells(), grid.block_counts(p.count), grid, time, dt, ctx, factory, tally, pool);
    grid.sort_counted(particles.cells(), p.count);
    time += dt;
    ++step;
  }
}

std::unique_ptr<SlabHarness> make_slab(const Subject& s, const Assignment& a, std::size_t n) {
  auto h = std::make_unique<SlabHarness>();
  h->pipeline = load_test_pipeline(s, a, n);
  const Pipeline& p = *h->pipeline;
  h->use = &slot(p, PluginKind::boundary);
  h->object = create_object(*h->use->plugin, h->use->params);
  h->boundary = static_cast<Boundary*>(h->object.get());
  h->recorder = std::make_unique<RecordingBoundary>(h->boundary);
  h->object->publish(h->board);
  h->particles.allocate(n, h->object->attributes());

  SystemInfo& sys = h->sys;
  sys = system_info(p, n, 0);
  sys.seed = s.cfg.seed;
  sys.geometry = Geometry::slab;
  for (double& e : sys.box) e = SlabHarness::kEdge;
  sys.cells = sys.bins = 10;
  sys.volume = sys.box[0] * sys.box[1] * sys.box[2];
  sys.number_density = static_cast<double>(n) / sys.volume;
  h->ctx.system = &sys;
  h->ctx.quantities = &h->board;
  h->ctx.boundaries = h->tally.sides.data();
  h->ctx.boundary_count = 2;
  try {
    h->boundary->begin(sys, h->board, Vec3{0, 0, 0});
  } catch (const ParameterError& e) {
    h->refusal = fmt("begin() refused a %zu-particle slab of %g x %g x %g without body acceleration (parameter '%s'): %s",
                     n, sys.box[0], sys.box[1], sys.box[2], e.parameter().c_str(), e.what());
  }
  // The harness's own draws: a Maxwellian at T = 1, uniform in the box.
  sample_maxwellian(sys, h->span(), SlabHarness::kTemperature,
                    StreamFactory::standalone_streams(s.cfg.seed, StreamPurpose::host, 0));
  h->grid.slab(n, sys.cells, sys.box[1], sys.cross_section());
  h->grid.set_sampling_system(&sys);
  h->grid.assign_and_sort(h->span().y.data, h->particles.cells(), n);
  h->factory = StreamFactory(s.cfg.seed, 0);
  return h;
}

bool all_finite(const double* d, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(d[k])) return false;
  return true;
}

// First non-finite entry of the particle state, or "" when everything is finite.
std::string nonfinite_in(const ParticleSpan& p, bool positions) {
  const std::pair<const char*, const double*> arrays[] = {{"x", p.x.data}, {"y", p.y.data}, {"z", p.z.data},
                                                           {"vx", p.vx.data}, {"vy", p.vy.data}, {"vz", p.vz.data}};
  for (const auto& [name, d] : arrays) {
    if ((!positions && name[0] != 'v') || !d) continue;
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
