// Checks every plugin kind gets that run it twice and compare to the bit: determinism (the same
// seed, the same bits), two runs at once on two threads, and a checkpoint saved and restored; and
// the comparisons of outputs and particles they use.
#include "conformance/internal.hpp"

#include <exception>
#include <thread>

namespace gdsmc::host::conformance {

bool close(double a, double b, double rel, double abs) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;
  return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs;
}

// Compare two diagnostics' outputs; returns "" or where they differ. rel = abs = 0: bitwise.
std::string compare_outputs(const DiagnosticOutput& a, const DiagnosticOutput& b, double rel, double abs) {
  auto vec = [&](const std::string& what, const std::vector<double>& x, const std::vector<double>& y) -> std::string {
    if (x.size() != y.size()) return fmt("%s has %zu values in one run and %zu in the other", what.c_str(), x.size(), y.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const bool same = (rel == 0 && abs == 0) ? std::memcmp(&x[k], &y[k], sizeof(double)) == 0 : close(x[k], y[k], rel, abs);
      if (!same) return fmt("%s[%zu] is %.17g in one run and %.17g in the other", what.c_str(), k, x[k], y[k]);
    }
    return "";
  };
  if (a.columns.size() != b.columns.size() || a.profiles.size() != b.profiles.size() || a.arrays.size() != b.arrays.size() ||
      a.histograms.size() != b.histograms.size() || a.scalars.size() != b.scalars.size())
    return "the two runs declared different datasets";
  std::string d;
  for (std::size_t k = 0; k < a.columns.size() && d.empty(); ++k)
    d = vec("series '" + a.columns[k].name + "'", a.columns[k].values, b.columns[k].values);
  for (std::size_t k = 0; k < a.profiles.size() && d.empty(); ++k)
    d = vec("profile '" + a.profiles[k].name + "'", a.profiles[k].values, b.profiles[k].values);
  for (std::size_t k = 0; k < a.arrays.size() && d.empty(); ++k)
    d = vec("array '" + a.arrays[k].name + "'", a.arrays[k].data, b.arrays[k].data);
  for (std::size_t k = 0; k < a.histograms.size() && d.empty(); ++k) {
    d = vec("histogram '" + a.histograms[k].name + "' edges", a.histograms[k].edges, b.histograms[k].edges);
    if (d.empty()) d = vec("histogram '" + a.histograms[k].name + "'", a.histograms[k].values, b.histograms[k].values);
  }
  for (std::size_t k = 0; k < a.scalars.size() && d.empty(); ++k)
    d = vec("scalar '" + a.scalars[k].name + "'", {a.scalars[k].value}, {b.scalars[k].value});
  return d;
}

std::string compare_particles(const ParticleSpan& a, const ParticleSpan& b) {
  const std::pair<const char*, std::pair<const double*, const double*>> arrays[] = {
      {"x", {a.x.data, b.x.data}}, {"y", {a.y.data, b.y.data}}, {"z", {a.z.data, b.z.data}},
      {"vx", {a.vx.data, b.vx.data}}, {"vy", {a.vy.data, b.vy.data}}, {"vz", {a.vz.data, b.vz.data}}};
  for (const auto& [name, d] : arrays) {
    if (!d.first || !d.second) continue;  // a homogeneous system keeps no positions
    for (std::size_t k = 0; k < a.count; ++k)
      if (std::memcmp(&d.first[k], &d.second[k], sizeof(double)) != 0)
        return fmt("%s of particle %zu is %.17g in one run and %.17g in the other", name, k, d.first[k], d.second[k]);
  }
  for (std::size_t at = 0; at < a.attribute_count; ++at) {
    const std::size_t n = a.count * static_cast<std::size_t>(a.attribute_specs[at].components);
    for (std::size_t k = 0; k < n; ++k)
      if (std::memcmp(&a.attribute_data[at][k], &b.attribute_data[at][k], sizeof(double)) != 0)
        return fmt("attribute '%s' entry %zu differs between the runs", a.attribute_specs[at].name.c_str(), k);
  }
  return "";
}

namespace {

// The boundary checks' slab (engine Mover, plugin on both planes) for `steps` steps.
std::unique_ptr<SlabHarness> run_slab(const Subject& s, const Assignment& a, int steps) {
  auto h = make_slab(s, a);
  if (h->refusal.empty()) h->stream(steps, 0.05);
  return h;
}

std::string compare_slabs(SlabHarness& h1, SlabHarness& h2) {
  std::string d = compare_particles(h1.span(), h2.span());
  for (int side = 0; side < 2 && d.empty(); ++side) {
    const BoundaryTally &t1 = h1.tally.sides[side], &t2 = h2.tally.sides[side];
    if (t1.hits != t2.hits || std::memcmp(&t1.energy, &t2.energy, sizeof(double)) != 0 ||
        std::memcmp(t1.momentum, t2.momentum, sizeof t1.momentum) != 0)
      d = fmt("the %s tallies differ (%llu hits, energy %.17g against %llu hits, energy %.17g)", side ? "y_max" : "y_min",
              static_cast<unsigned long long>(t1.hits), t1.energy, static_cast<unsigned long long>(t2.hits), t2.energy);
  }
  return d;
}

std::string compare_engines(const Subject& s, Engine& e1, Engine& e2) {
  std::string d = compare_particles(e1.particles(), e2.particles());
  if (d.empty() && e1.context().collisions != e2.context().collisions)
    d = fmt("%llu collisions in one run and %llu in the other", static_cast<unsigned long long>(e1.context().collisions),
            static_cast<unsigned long long>(e2.context().collisions));
  if (d.empty() && s.kind() == PluginKind::diagnostic)
    d = compare_outputs(e1.diagnostics().at(0), e2.diagnostics().at(0), 0, 0);
  return d;
}

constexpr int kSteps = 20, kSlabSteps = 100;

}  // namespace

Result check_determinism(const Subject& s) {
  const Assignment a = base_assignment(s);
  if (s.kind() == PluginKind::boundary) {
    auto h1 = run_slab(s, a, kSlabSteps), h2 = run_slab(s, a, kSlabSteps);
    if (!h1->refusal.empty()) return skip(h1->refusal + " (a refusal in begin() is allowed)");
    const std::string d = compare_slabs(*h1, *h2);
    if (!d.empty()) return fail("not deterministic: the same seed twice gives different results: " + d);
    return pass(fmt("seed %llu twice: bit-identical particles and boundary tallies after %d steps of a %zu-particle slab "
                    "(%llu hits)", static_cast<unsigned long long>(s.cfg.seed), kSlabSteps, h1->span().count,
                    static_cast<unsigned long long>(h1->tally.sides[0].hits + h1->tally.sides[1].hits)));
  }
  auto p1 = load_test_pipeline(s, a), p2 = load_test_pipeline(s, a);
  Engine e1(*p1), e2(*p2);
  for (int k = 0; k < kSteps; ++k) {
    e1.step();
    e2.step();
  }
  const std::string d = compare_engines(s, e1, e2);
  if (!d.empty()) return fail("not deterministic: the same seed twice gives different results: " + d);
  return pass(fmt("seed %llu twice: bit-identical particles%s after %d steps of a %zu-particle pipeline",
                  static_cast<unsigned long long>(s.cfg.seed),
                  s.kind() == PluginKind::diagnostic ? " and output" : "", kSteps, p1->particles));
}

// Runs at once (run.threads): two instances of the plugin, each in its own run on its own thread,
// at the same time, must give the bits of one run alone. Shared mutable state (a static counter,
// cache or generator) shows up as a difference, or as a crash.
Result check_threads(const Subject& s) {
  const Assignment a = base_assignment(s);
  auto concurrently = [](const std::function<void()>& f1, const std::function<void()>& f2) {
    std::exception_ptr x1, x2;
    std::thread t1([&] { try { f1(); } catch (...) { x1 = std::current_exception(); } });
    std::thread t2([&] { try { f2(); } catch (...) { x2 = std::current_exception(); } });
    t1.join();
    t2.join();
    if (x1) std::rethrow_exception(x1);
    if (x2) std::rethrow_exception(x2);
  };
  if (s.kind() == PluginKind::boundary) {
    auto alone = run_slab(s, a, kSlabSteps);
    if (!alone->refusal.empty()) return skip(alone->refusal + " (a refusal in begin() is allowed)");
    std::unique_ptr<SlabHarness> h1, h2;
    concurrently([&] { h1 = run_slab(s, a, kSlabSteps); }, [&] { h2 = run_slab(s, a, kSlabSteps); });
    std::string d = compare_slabs(*alone, *h1);
    if (d.empty()) d = compare_slabs(*alone, *h2);
    if (!d.empty()) return fail("two runs at once (run.threads: 2) differ from one alone: " + d +
                                "; keep mutable state in the object, not in static or global variables");
    // Threads inside one run: the mover's blocks on two threads call interact() at once.
    const std::size_t n = 3 * Mover::kBlock;
    auto serial = make_slab(s, a, n), threaded = make_slab(s, a, n);
    WorkPool pool(2), one(1);
    serial->pool = &one;  // the plugin called directly in both
    threaded->pool = &pool;
    serial->stream(kSlabSteps, 0.05);
    threaded->stream(kSlabSteps, 0.05);
    d = compare_slabs(*serial, *threaded);
    if (!d.empty()) return fail("one run on two threads (interact() called from two threads at once) differs from the "
                                "same run on one: " + d + "; interact() is const: it must not change the object");
    return pass(fmt("two %d-step slabs on two threads at once, and one %zu-particle slab whose blocks ran on two threads: "
                    "the bits of one thread alone", kSlabSteps, n));
  }
  auto p0 = load_test_pipeline(s, a), p1 = load_test_pipeline(s, a), p2 = load_test_pipeline(s, a);
  Engine alone(*p0);
  for (int k = 0; k < kSteps; ++k) alone.step();
  std::unique_ptr<Engine> e1, e2;
  auto run = [&](std::unique_ptr<Engine>& e, const Pipeline& p) {
    e = std::make_unique<Engine>(p);
    for (int k = 0; k < kSteps; ++k) e->step();
  };
  concurrently([&] { run(e1, *p1); }, [&] { run(e2, *p2); });
  std::string d = compare_engines(s, alone, *e1);
  if (d.empty()) d = compare_engines(s, alone, *e2);
  if (!d.empty()) return fail("two runs at once (run.threads: 2) differ from one alone: " + d +
                              "; keep mutable state in the object, not in static or global variables");
  // Threads inside one run: sub-populations of 256 (or the layers of a slab) collide on two threads
  // at once, through the one collision rule object.
  auto p3 = load_test_pipeline(s, a, 4000), p4 = load_test_pipeline(s, a, 4000);
  p3->subpopulation = p4->subpopulation = 256;
  Engine serial(*p3, 0, 1), threaded(*p4, 0, 2);
  for (int k = 0; k < kSteps; ++k) {
    serial.step();
    threaded.step();
  }
  d = compare_engines(s, serial, threaded);
  if (!d.empty()) return fail("one run on two threads (sub-populations of 256 colliding at once) differs from the same run "
                              "on one: " + d + "; collide() is const: it must not change the rule");
  return pass(fmt("two %d-step runs on two threads at once, and one 4000-particle run whose collision groups ran on two "
                  "threads: the bits%s of one thread alone", kSteps,
                  s.kind() == PluginKind::diagnostic ? " (particles and output)" : ""));
}

// Checkpoints (PluginObject::save_state / load_state): a run saved between two records, restored
// into freshly set-up plugin objects and continued to its stop (finish() included) must give the
// bits of the run uninterrupted. A member the plugin forgot to save shows up as a difference.
Result check_checkpoint(const Subject& s) {
  const Assignment a = base_assignment(s);
  constexpr std::size_t kParticles = 1000;
  constexpr std::uint64_t kRecordEvery = 7;  // records fall between checkpoints: open windows are saved too
  auto prepare = [&] {
    auto p = load_test_pipeline(s, a, kParticles);
    p->stop_collisions_per_particle = 2.0;
    for (auto& d : p->diagnostics) d.record_every = kRecordEvery;
    return p;
  };
  auto p0 = prepare(), p1 = prepare();
  Engine alone(*p0);
  alone.run();
  const std::uint64_t steps = alone.context().step;
  if (steps < 2) return skip(fmt("the test run ends after %llu step(s): nothing to resume", static_cast<unsigned long long>(steps)));
  std::uint64_t save_at = steps / 2;
  if (save_at % kRecordEvery == 0) ++save_at;
  Engine first(*p1);
  for (std::uint64_t k = 0; k < save_at; ++k) first.step();
  BufferStateWriter saved;
  first.save(saved);
  BufferStateReader reader(saved.bytes());
  std::unique_ptr<Engine> resumed;
  try {
    resumed = std::make_unique<Engine>(*p1, 0, 1, reader);
  } catch (const std::exception& e) {
    return fail(fmt("a checkpoint saved at step %llu could not be restored: ", static_cast<unsigned long long>(save_at)) +
                e.what());
  }
  resumed->run();
  std::string d = compare_engines(s, alone, *resumed);
  if (d.empty() && alone.context().step != resumed->context().step)
    d = fmt("%llu steps against %llu", static_cast<unsigned long long>(alone.context().step),
            static_cast<unsigned long long>(resumed->context().step));
  if (!d.empty())
    return fail(fmt("a run saved at step %llu of %llu and resumed differs from the run uninterrupted: ",
                    static_cast<unsigned long long>(save_at), static_cast<unsigned long long>(steps)) +
                d + "; save_state must write every member that changes during the run (accumulators, sample counts, "
                    "values remembered from an earlier step, a reservoir) and load_state read them back");
  return pass(fmt("a %zu-particle run saved at step %llu (records every %llu steps), its state %zu bytes, restored into "
                  "fresh objects and run to its stop (%llu steps, finish() included): the bits%s of the run uninterrupted",
                  kParticles, static_cast<unsigned long long>(save_at), static_cast<unsigned long long>(kRecordEvery),
                  saved.bytes().size(), static_cast<unsigned long long>(steps),
                  s.kind() == PluginKind::diagnostic ? " (particles and output)" : ""));
}

}  // namespace gdsmc::host::conformance
