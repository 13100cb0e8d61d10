// Diagnostic checks: output shape and independence of the particle order.
#include "conformance/internal.hpp"

namespace gdsmc::host::conformance {


struct DiagnosticRun {
  std::vector<std::string> summary;
  std::unique_ptr<DiagnosticOutput> out;
  std::size_t records = 0;
};

// Feed a fresh diagnostic a fixed sequence of states (optionally with the particles permuted)
// the way the engine does: begin, sample every state, record every other one, finish.
// The diagnostic's streams come from `streams` (the harness's factory, or another seed's), its
// shared moments from the host's CellGrid::sampled_moments, as in the engine (the MomentsPart `parts`);
// `no_particles`: an empty span, as a decomposed run hands a diagnostic that reads none.
DiagnosticRun run_diagnostic(Harness& h, const std::vector<Snapshot>& states, const std::vector<StepContext>& ctxs,
                             const std::vector<std::uint32_t>* perm, const StreamFactory& streams,
                             std::uint32_t parts = moments_known, bool no_particles = false) {
  DiagnosticRun r;
  r.out = std::make_unique<DiagnosticOutput>(h.use->instance_name, &r.summary);
  r.out->set_bins(bin_centres_lambda0(h.sys));  // as the engine does
  auto obj = h.fresh_subject();
  auto* d = static_cast<Diagnostic*>(obj.get());
  d->begin(h.sys, h.board, *r.out);
  const std::string& name = h.use->plugin->descriptor->name;
  for (std::size_t k = 0; k < states.size(); ++k) {
    h.restore(states[k], perm);
    h.ctx = ctxs[k];
    h.sample_moments(parts);
    h.plugin_streams_for(StreamPurpose::diagnostic, &streams);
    d->sample(h.ctx, no_particles ? ParticleSpan{} : h.span());
    h.ctx.moments = nullptr;
    if (k % 2 == 0 || k + 1 == states.size()) {
      r.out->begin_record(h.ctx.time_in_tau0(), h.ctx.collisions_per_particle());
      d->record(h.ctx, *r.out);
      r.out->check_record(name);
      ++r.records;
    }
  }
  d->finish(h.ctx, *r.out);
  return r;
}

struct DiagnosticStates {
  std::unique_ptr<Harness> h;
  std::vector<Snapshot> states;
  std::vector<StepContext> ctxs;
};

DiagnosticStates diagnostic_states(const Subject& s, std::size_t n) {
  DiagnosticStates d;
  d.h = make_harness(s, base_assignment(s), n);
  Harness& h = *d.h;
  Rng attr_rng = h.host_rng(4);
  h.randomize_zero_attributes(attr_rng);
  h.update_moments();
  for (int k = 0; k < 7; ++k) {
    h.ctx.in_average_window = k >= 3;  // the later states lie in the steady averaging window
    d.states.push_back(h.save());
    d.ctxs.push_back(h.ctx);
    const double dt = 0.5 * h.sys.time_unit0;
    h.ctx.dt = dt;
    h.collide(dt);
    h.ctx.time += dt;
    ++h.ctx.step;
  }
  return d;
}

Result check_diagnostic_output(const Subject& s) {
  auto d = diagnostic_states(s, 500);
  DiagnosticRun r;
  try {
    r = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, d.h->factory);
  } catch (const std::exception& e) {
    return fail(std::string("malformed output: ") + e.what());
  }
  const DiagnosticOutput& o = *r.out;
  std::vector<std::string> problems;
  for (const auto& c : o.columns) {
    if (c.unit.empty()) problems.push_back("series '" + c.name + "' has no unit");
    if (c.values.size() != r.records)
      problems.push_back(fmt("series '%s' has %zu values after %zu records", c.name.c_str(), c.values.size(), r.records));
  }
  for (const auto& pr : o.profiles) {
    if (pr.unit.empty()) problems.push_back("profile '" + pr.name + "' has no unit");
    if (pr.values.size() != r.records * o.bin_centres.size())
      problems.push_back(fmt("profile '%s' has %zu values after %zu records of %zu bins", pr.name.c_str(),
                             pr.values.size(), r.records, o.bin_centres.size()));
  }
  for (const auto& a : o.arrays)
    if (a.unit.empty()) problems.push_back("array '" + a.name + "' has no unit");
  for (const auto& hg : o.histograms) {
    if (hg.edge_unit.empty() || hg.value_unit.empty()) problems.push_back("histogram '" + hg.name + "' lacks a unit");
    if (hg.edges.size() != hg.values.size() + 1) problems.push_back("histogram '" + hg.name + "' edges do not match");
    for (std::size_t k = 1; k < hg.edges.size(); ++k)
      if (!(hg.edges[k] > hg.edges[k - 1])) {
        problems.push_back("histogram '" + hg.name + "' edges are not increasing");
        break;
      }
  }
  for (const auto& sc : o.scalars)
    if (sc.unit.empty()) problems.push_back("scalar '" + sc.name + "' has no unit");
  if (o.columns.empty() && o.profiles.empty() && o.arrays.empty() && o.histograms.empty() && o.scalars.empty())
    problems.push_back("it wrote nothing");
  if (!problems.empty()) return fail("malformed output: " + join(problems, "; "));
  return pass(fmt("%zu records: %zu series with one value per record, %zu profiles with one row per record, %zu arrays, "
                  "%zu histograms, %zu scalars, all with units", r.records, o.columns.size(), o.profiles.size(),
                  o.arrays.size(), o.histograms.size(), o.scalars.size()));
}

// Root-mean-square relative difference over every value two outputs hold (NaN pairs ignored).
double rms_relative_difference(const DiagnosticOutput& a, const DiagnosticOutput& b) {
  double sum = 0;
  std::size_t n = 0;
  auto add = [&](const std::vector<double>& x, const std::vector<double>& y) {
    for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
      if (std::isnan(x[k]) || std::isnan(y[k])) continue;
      const double d = (x[k] - y[k]) / (0.5 * (std::fabs(x[k]) + std::fabs(y[k])) + 1e-12);
      sum += d * d;
      ++n;
    }
  };
  for (std::size_t k = 0; k < std::min(a.columns.size(), b.columns.size()); ++k) add(a.columns[k].values, b.columns[k].values);
  for (std::size_t k = 0; k < std::min(a.profiles.size(), b.profiles.size()); ++k) add(a.profiles[k].values, b.profiles[k].values);
  for (std::size_t k = 0; k < std::min(a.arrays.size(), b.arrays.size()); ++k) add(a.arrays[k].data, b.arrays[k].data);
  for (std::size_t k = 0; k < std::min(a.histograms.size(), b.histograms.size()); ++k)
    add(a.histograms[k].values, b.histograms[k].values);
  for (std::size_t k = 0; k < std::min(a.scalars.size(), b.scalars.size()); ++k) add({a.scalars[k].value}, {b.scalars[k].value});
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

Result check_diagnostic_order(const Subject& s) {
  constexpr std::size_t n = 500;
  auto d = diagnostic_states(s, n);
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  Rng rng = d.h->host_rng(5);
  for (std::size_t k = n - 1; k > 0; --k) std::swap(perm[k], perm[rng.below(static_cast<std::uint32_t>(k + 1))]);
  const StreamFactory same = d.h->factory;
  const DiagnosticRun a = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, same);
  const DiagnosticRun b = run_diagnostic(*d.h, d.states, d.ctxs, &perm, same);
  // A diagnostic that draws random numbers (e.g. one that samples pairs) depends on the order
  // only through its random stream: compare the effect of the permutation with that of the seed.
  const DiagnosticRun c = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, StreamFactory(s.cfg.seed + 1, 7));
  if (compare_outputs(*a.out, *c.out, 0, 0).empty()) {
    const std::string diff = compare_outputs(*a.out, *b.out, 1e-9, 1e-12);
    if (!diff.empty())
      return fail("values depend on the particle order: with the particles permuted " + diff +
                  " (tolerance: relative 1e-9, absolute 1e-12)");
    return pass(fmt("the same %zu states with the %zu particles in a random order give the same output to round-off",
                    d.states.size(), n));
  }
  const double by_order = rms_relative_difference(*a.out, *b.out);
  const double by_seed = rms_relative_difference(*a.out, *c.out);
  if (!(by_order <= 5 * by_seed + 1e-9))
    return fail(fmt("values depend on the particle order beyond their statistical noise: permuting the particles changes "
                    "the output by %.3g (rms relative), another random stream by %.3g", by_order, by_seed));
  return pass(fmt("stochastic diagnostic (its output depends on its random stream): permuting the %zu particles changes "
                  "the output by %.3g (rms relative), no more than another random stream does (%.3g)", n, by_order,
                  by_seed));
}

// A diagnostic that declares the parts of the sampled moments it reads (MomentsRead) gives the same
// output, bit for bit, when the host measures only those parts (the others NaN) as when it measures all;
// one that declares it reads no particle, the same again on an empty span.
Result check_diagnostic_moments_read(const Subject& s) {
  auto d = diagnostic_states(s, 500);
  const auto object = d.h->fresh_subject();
  const auto* read = static_cast<const MomentsRead*>(object->extension(moments_read_id));
  if (!read) return pass("offers no moments_read extension: the host measures every part of the sampled moments for it");
  const std::uint32_t parts = read->parts & moments_known;
  auto names = [](std::uint32_t bits) {
    std::vector<std::string> n;
    if (bits & moments_means) n.push_back("means (local.mean, cell_mean_velocity)");
    if (bits & moments_energy) n.push_back("kinetic_energy");
    if (bits & moments_peculiar) n.push_back("peculiar moments (local.second, temperature, fourth, sixth)");
    if (bits & moments_cells) n.push_back("cells");
    if (bits & (moments_bins | moments_bin_heat)) n.push_back((bits & moments_bin_heat) ? "bin sums with |v|^2 v" : "bin sums");
    return n.empty() ? std::string("none") : join(n, ", ");
  };
  const StreamFactory same = d.h->factory;
  const DiagnosticRun all = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, same);
  const DiagnosticRun declared = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, same, parts);
  const std::string diff = compare_outputs(*all.out, *declared.out, 0, 0);
  if (!diff.empty())
    return fail("it declares that it reads " + names(parts) + " of ctx.moments, but with only those measured (" +
                names(moments_known & ~parts) + " NaN or nullptr) its output changes: " + diff +
                "; declare every part its sample reads (MomentsRead, plugin.hpp)");
  const bool no_particles = read->version >= 2 && read->particles == 0;
  if (no_particles) {
    const DiagnosticRun empty = run_diagnostic(*d.h, d.states, d.ctxs, nullptr, same, parts, true);
    const std::string by_span = compare_outputs(*declared.out, *empty.out, 0, 0);
    if (!by_span.empty())
      return fail("it declares that its sample reads no particle (MomentsRead::particles = 0), but on an empty span its "
                  "output changes: " + by_span + "; a decomposed run hands it none: declare particles = 1 "
                  "(offer_moments_read<Parts>) if it reads them");
  }
  return pass("reads " + names(parts) + " of ctx.moments" + (no_particles ? " and no particle" : "") +
              ": with only those measured" + (no_particles ? ", and on an empty span," : "") +
              " its output is the same to the bit");
}

}  // namespace gdsmc::host::conformance
