// Checks every plugin kind gets: load, ABI, descriptor, schema, defaults, bounds, out-of-range and wrong-type values, determinism, two runs at once.
#include "conformance/internal.hpp"

#include <exception>
#include <thread>

namespace gdsmc::host::conformance {

// --------------------------------------------------------------------------------------------
// Generic checks

// Loading and the ABI are checked by the loader's own steps (plugins/loader.hpp), so that the
// conformance runner and the host refuse exactly the same files.
Result check_load(const Subject& s) {
  try {
    auto lib = open_library(s.file);
    (void)plugin_entry(*lib, s.file);
  } catch (const PluginLoadError& e) {
    return fail(e.what());
  }
  return pass("loads with every symbol resolved (rtld_now) and exports the gdsmc plugin entry");
}

Result check_abi(const Subject& s) {
  auto lib = open_library(s.file);
  const AbiCheck abi = host::check_abi(plugin_entry(*lib, s.file));
  if (!abi.problem.empty()) return fail("wrong ABI version: " + abi.problem + " (" + abi.versions + "); " + abi.remedy);
  return pass(abi.versions + "; layout fingerprint matches");
}

bool good_identifier(const std::string& n) {
  if (n.empty()) return false;
  for (char c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

Result check_descriptor(const Subject& s) {
  LoadedPlugin lp = load_plugin(s.file);
  const PluginDescriptor& d = *lp.descriptor;
  std::vector<std::string> problems;
  const int k = static_cast<int>(d.kind);
  if (k < 1 || k > 5) problems.push_back(fmt("kind %d is not a plugin kind", k));
  if (!good_identifier(d.name)) problems.push_back("name '" + d.name + "' is not a plain identifier (letters, digits, _ or -)");
  if (d.version.empty()) problems.push_back("no version");
  if (d.summary.empty()) problems.push_back("no summary");
  if (d.summary.find('\n') != std::string::npos) problems.push_back("the summary is more than one line");
  if (d.documentation.empty()) problems.push_back("no documentation");
  if (!d.create) problems.push_back("no factory");
  if (!problems.empty()) return fail("descriptor incomplete: " + join(problems, "; "));
  return pass(fmt("%s plugin '%s' version %s: name, summary, documentation (%zu characters), factory",
                  to_string(d.kind), d.name.c_str(), d.version.c_str(), d.documentation.size()));
}

Result check_schema(const Subject& s) {
  const auto& specs = s.desc().parameters;
  std::vector<std::string> problems;
  std::set<std::string> names;
  const std::vector<std::string>& reserved = all_reserved_keys();
  for (const auto& p : specs) {
    const std::string who = "parameter '" + p.name + "'";
    if (p.name.empty()) problems.push_back("a parameter has an empty name");
    else if (!good_identifier(p.name)) problems.push_back(who + ": the name is not a plain identifier");
    if (!names.insert(p.name).second) problems.push_back(who + " is declared twice");
    if (std::find(reserved.begin(), reserved.end(), p.name) != reserved.end())
      problems.push_back(who + ": the name is reserved by the pipeline");
    if (p.doc.empty()) problems.push_back(who + " has no documentation");
    if ((p.min || p.max) && p.type != ParamType::real && p.type != ParamType::integer)
      problems.push_back(who + ": a range on a parameter that is not a number");
    if (p.min && p.max && (*p.min > *p.max || (*p.min == *p.max && !(p.min_inclusive && p.max_inclusive))))
      problems.push_back(who + ": the range " + p.range_text() + " is empty");
    if (p.dimension != Dimension::none && p.type != ParamType::real)
      problems.push_back(who + ": a unit on a parameter that is not real");
    if (p.type == ParamType::choice) {
      if (p.choices.empty()) problems.push_back(who + ": a choice with no choices");
      std::set<std::string> c(p.choices.begin(), p.choices.end());
      if (c.size() != p.choices.size()) problems.push_back(who + ": repeated choices");
      if (c.count("")) problems.push_back(who + ": an empty choice");
    }
    if (!p.default_) continue;
    const ParamValue& v = *p.default_;
    bool type_ok = false;
    double x = 0;
    switch (p.type) {
      case ParamType::real:
        if (auto d = std::get_if<double>(&v)) type_ok = true, x = *d;
        if (auto i = std::get_if<std::int64_t>(&v)) type_ok = true, x = static_cast<double>(*i);
        break;
      case ParamType::integer:
        if (auto i = std::get_if<std::int64_t>(&v)) type_ok = true, x = static_cast<double>(*i);
        break;
      case ParamType::boolean: type_ok = std::holds_alternative<bool>(v); break;
      case ParamType::string: type_ok = std::holds_alternative<std::string>(v); break;
      case ParamType::choice:
        type_ok = std::holds_alternative<std::string>(v);
        if (type_ok && std::find(p.choices.begin(), p.choices.end(), std::get<std::string>(v)) == p.choices.end())
          problems.push_back(who + ": the default '" + std::get<std::string>(v) + "' is not one of its choices");
        break;
    }
    if (!type_ok) {
      problems.push_back(who + ": the default " + value_text(v) + " is not of type " + to_string(p.type));
      continue;
    }
    if (p.type == ParamType::real && !std::isfinite(x)) problems.push_back(who + ": the default is not finite");
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool low = p.min && (p.min_inclusive ? x < *p.min : x <= *p.min);
      const bool high = p.max && (p.max_inclusive ? x > *p.max : x >= *p.max);
      if (low || high) problems.push_back(who + ": the default " + value_text(v) + " is outside its range " + p.range_text());
    }
  }
  if (!problems.empty()) return fail("parameter schema not well-formed: " + join(problems, "; "));
  return pass(fmt("%zu parameters: names unique, documented, defaults typed and within their ranges", specs.size()));
}

// Build the plugin in a small pipeline and (when the host can run it) take a few steps.
Result check_defaults(const Subject& s) {
  const Assignment a = base_assignment(s);
  std::unique_ptr<Pipeline> p;
  try {
    p = load_test_pipeline(s, a);
  } catch (const PipelineError& e) {
    auto own = own_errors(e, s.kind());
    return fail("does not construct from its defaults (" + describe_assignment(s, a) + "): " +
                join(own.empty() ? e.messages() : own, "; "));
  }
  Engine engine(*p);
  constexpr int steps = 10;
  // The engine's own checks of what a plugin returns (a non-finite declared energy, say) stop a
  // step with an error: here the state is judged as before, and the property itself by its own
  // check (collision.finite, ...), so the stop is only noted.
  std::string stopped;
  int taken = 0;
  try {
    for (; taken < steps; ++taken) engine.step();
  } catch (const std::runtime_error& e) {
    stopped = e.what();
  }
  const double T = engine.context().global ? engine.context().global->temperature : 0;
  const std::string bad = nonfinite_in(engine.particles());
  if (!bad.empty()) return fail("after a few steps of a pipeline with its defaults the state is not finite: " + bad);
  if (!(T > 0) || !std::isfinite(T)) return fail(fmt("after a few steps with its defaults the temperature is %g", T));
  if (!stopped.empty())
    return pass(fmt("constructs from %s; a %zu-particle pipeline sets up; the host stopped it in step %d: ",
                    describe_assignment(s, a).c_str(), p->particles, taken + 1) + stopped);
  return pass(fmt("constructs from %s; a %zu-particle pipeline sets up and runs %d steps", describe_assignment(s, a).c_str(),
                  p->particles, steps));
}

struct Variant {
  std::string label;
  Assignment params;
};

// Values at and just inside the declared bounds, every choice and both booleans.
std::vector<Variant> bound_variants(const Subject& s) {
  const Assignment base = base_assignment(s);
  std::vector<Variant> out;
  auto add = [&](const ParamSpec& p, const std::string& value, const std::string& what) {
    Variant v{p.name + " = " + value + " (" + what + ")", base};
    v.params[p.name] = value;
    out.push_back(std::move(v));
  };
  // Parameters given by --params are swept too: the set is the point the others stay at.
  for (const auto& p : s.desc().parameters) {
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool integer = p.type == ParamType::integer;
      auto inside = [&](double bound, bool inclusive, double dir) {
        if (inclusive) return bound;
        if (integer) return dir > 0 ? std::floor(bound) + 1 : std::ceil(bound) - 1;
        return bound + dir * std::max(1e-6, 1e-6 * std::fabs(bound));
      };
      auto text = [&](double v) { return integer ? fmt("%.0f", v) : num(v); };
      if (p.min) add(p, text(inside(*p.min, p.min_inclusive, +1)), p.min_inclusive ? "lower bound" : "just above the lower bound");
      if (p.max) add(p, text(inside(*p.max, p.max_inclusive, -1)), p.max_inclusive ? "upper bound" : "just below the upper bound");
    } else if (p.type == ParamType::boolean) {
      add(p, "true", "boolean");
      add(p, "false", "boolean");
    } else if (p.type == ParamType::choice) {
      for (const auto& c : p.choices) add(p, quoted(c), "choice");
    }
  }
  return out;
}

PairReport pair_suite(CollisionRule& rule, const std::vector<AttributeSpec>& attributes, std::uint64_t seed,
                      std::size_t random_pairs);
std::string pair_failure(const PairReport& r);

// Build the plugin with each variant's values (through the host's validation): each must construct
// or be refused with a ParameterError; a collision rule must also pass the pair checks there.
// Returns a failure, or nothing and the counts.
std::optional<Result> sweep(const Subject& s, const std::vector<Variant>& variants, std::size_t& built,
                            std::size_t& refused) {
  built = refused = 0;
  for (const auto& v : variants) {
    std::unique_ptr<Pipeline> p;
    try {
      p = load_test_pipeline(s, v.params);
    } catch (const PipelineError& e) {
      const auto own = own_errors(e, s.kind());
      const std::string m = join(own.empty() ? e.messages() : own, "; ");
      if (m.find("refused parameter") != std::string::npos) {
        ++refused;
        continue;
      }
      return fail("with " + v.label + ", inside the declared range, the plugin failed instead of constructing or "
                  "refusing the value with a ParameterError: " + m);
    }
    if (s.kind() == PluginKind::collision_rule) {
      std::optional<BegunRule> r;
      try {
        r = begun_rule(*p);  // begun as in a run: a rule may compute what collide() uses there
      } catch (const ParameterError&) {
        ++refused;  // a refusal in begin() (a value that does not fit the context) is allowed
        continue;
      }
      ++built;
      const std::string f = pair_failure(pair_suite(r->rule(), r->object->attributes(), s.cfg.seed, 2000));
      if (!f.empty()) return fail("with " + v.label + ": " + f);
    } else {
      ++built;
    }
  }
  return std::nullopt;
}

Result check_bounds(const Subject& s) {
  const auto variants = bound_variants(s);
  if (variants.empty()) return pass("no parameter with bounds or choices to vary");
  std::size_t built = 0, refused = 0;
  if (auto failure = sweep(s, variants, built, refused)) return *failure;
  return pass(fmt("%zu values at or inside the bounds: %zu construct%s, %zu refused with a message", variants.size(),
                  built, s.kind() == PluginKind::collision_rule ? " (and collide soundly)" : "", refused));
}

// Inside the range: the interval a numeric parameter's interior and random values come from. Both
// bounds: the range itself; one bound: from it to twice the distance to the default (or the
// in-range filler value), at least 2 wide; none: nothing (the parameter stays where it is).
std::optional<std::pair<double, double>> sample_interval(const ParamSpec& p) {
  if (p.type != ParamType::real && p.type != ParamType::integer) return std::nullopt;
  if (p.min && p.max) return std::make_pair(*p.min, *p.max);
  if (!p.min && !p.max) return std::nullopt;
  double ref = std::atof(in_range_value(p).c_str());
  if (p.default_) {
    if (auto d = std::get_if<double>(&*p.default_)) ref = *d;
    if (auto i = std::get_if<std::int64_t>(&*p.default_)) ref = static_cast<double>(*i);
  }
  const double bound = p.min ? *p.min : *p.max;
  const double width = std::max(2.0, 2 * std::fabs(ref - bound));
  return p.min ? std::make_pair(bound, bound + width) : std::make_pair(bound - width, bound);
}

// The value at fraction u in (0, 1) of a parameter's interval, strictly inside an exclusive bound.
std::optional<std::string> value_at(const ParamSpec& p, double u) {
  const auto iv = sample_interval(p);
  if (!iv) return std::nullopt;
  const auto [lo, hi] = *iv;
  double v = lo + u * (hi - lo);
  if (p.type == ParamType::integer) {
    v = std::round(v);
    if (p.min && (p.min_inclusive ? v < *p.min : v <= *p.min)) v = std::floor(*p.min) + 1;
    if (p.max && (p.max_inclusive ? v > *p.max : v >= *p.max)) v = std::ceil(*p.max) - 1;
    if ((p.min && v < *p.min) || (p.max && v > *p.max)) return std::nullopt;
    return fmt("%.0f", v);
  }
  return num(v);
}

std::string short_value(const std::string& v) {
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  return end && *end == 0 && !v.empty() ? fmt("%.6g", x) : v;
}

constexpr int kRandomPoints = 3;

// Interior values one parameter at a time (1/4, 1/2, 3/4 of its interval, the others at the base
// assignment) and kRandomPoints points with every numeric parameter drawn uniformly from its
// interval (and booleans and choices at random), all from the seed: bugs that vanish at the
// bounds (a (1 - e) that should be (1 - e^2)) or only show when two parameters act together.
std::vector<Variant> interior_variants(const Subject& s) {
  const Assignment base = base_assignment(s);
  std::vector<Variant> out;
  for (const auto& p : s.desc().parameters)
    for (const double u : {0.25, 0.5, 0.75}) {
      const auto v = value_at(p, u);
      if (!v) continue;
      Variant var{fmt("%s = %s (%g of its range)", p.name.c_str(), short_value(*v).c_str(), u), base};
      var.params[p.name] = *v;
      if (std::none_of(out.begin(), out.end(), [&](const Variant& o) { return o.params == var.params; }))
        out.push_back(std::move(var));
    }
  Rng rng = StreamFactory::standalone(s.cfg.seed, 2, StreamPurpose::host);
  for (int k = 0; k < kRandomPoints; ++k) {
    Variant var{"", base};
    std::vector<std::string> parts;
    for (const auto& p : s.desc().parameters) {
      std::optional<std::string> v;
      const double u = 0.02 + 0.96 * rng.uniform();  // drawn for every parameter: stable sequences
      if (p.type == ParamType::boolean) v = u < 0.5 ? "true" : "false";
      else if (p.type == ParamType::choice && !p.choices.empty())
        v = quoted(p.choices[std::min(p.choices.size() - 1, static_cast<std::size_t>(u * p.choices.size()))]);
      else v = value_at(p, u);
      if (!v) continue;
      var.params[p.name] = *v;
      parts.push_back(p.name + " = " + short_value(*v));
    }
    if (parts.empty()) break;
    var.label = fmt("random point %d of %d (", k + 1, kRandomPoints) + join(parts, ", ") + ")";
    out.push_back(std::move(var));
  }
  return out;
}

Result check_interior(const Subject& s) {
  const auto variants = interior_variants(s);
  if (variants.empty()) return pass("no numeric parameter with a range, boolean or choice to vary");
  std::size_t built = 0, refused = 0;
  if (auto failure = sweep(s, variants, built, refused)) return *failure;
  return pass(fmt("%zu interior and random values (seed %llu): %zu construct%s, %zu refused with a message",
                  variants.size(), static_cast<unsigned long long>(s.cfg.seed), built,
                  s.kind() == PluginKind::collision_rule ? " and collide soundly (2000 pairs each)" : "", refused));
}

Result expect_refused(const Subject& s, const std::string& param, const std::string& value, const std::string& what,
                      std::string& note) {
  Assignment a = base_assignment(s);
  a[param] = value;
  try {
    (void)load_test_pipeline(s, a);
  } catch (const PipelineError& e) {
    for (const auto& m : own_errors(e, s.kind()))
      if (m.find("'" + param + "'") != std::string::npos || m.find("." + param + ":") != std::string::npos ||
          m.find("." + param + ".") != std::string::npos) {
        note = m;
        return pass("");
      }
    return fail("parameter '" + param + "' = " + value + " (" + what + ") was refused without a message naming it: " +
                join(e.messages(), "; "));
  }
  return fail("parameter '" + param + "' = " + value + " (" + what + ") was accepted");
}

Result check_out_of_range(const Subject& s) {
  std::size_t n = 0;
  std::string note;
  for (const auto& p : s.desc().parameters) {
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool integer = p.type == ParamType::integer;
      auto text = [&](double v) { return integer ? fmt("%.0f", v) : num(v); };
      if (p.min) {
        const double v = p.min_inclusive ? (integer ? std::ceil(*p.min) - 1 : *p.min - std::max(1.0, std::fabs(*p.min))) : *p.min;
        Result r = expect_refused(s, p.name, text(v), "below its range " + p.range_text(), note);
        if (r.status != Status::pass) return r;
        ++n;
      }
      if (p.max) {
        const double v = p.max_inclusive ? (integer ? std::floor(*p.max) + 1 : *p.max + std::max(1.0, std::fabs(*p.max))) : *p.max;
        Result r = expect_refused(s, p.name, text(v), "above its range " + p.range_text(), note);
        if (r.status != Status::pass) return r;
        ++n;
      }
    } else if (p.type == ParamType::choice) {
      Result r = expect_refused(s, p.name, "not_one_of_the_choices", "not a choice", note);
      if (r.status != Status::pass) return r;
      ++n;
    }
  }
  // An unknown parameter must be refused as well.
  {
    Assignment a = base_assignment(s);
    a["no_such_parameter_xyz"] = "1";
    try {
      (void)load_test_pipeline(s, a);
      return fail("an unknown parameter 'no_such_parameter_xyz' was accepted");
    } catch (const PipelineError& e) {
      if (own_errors(e, s.kind()).empty()) return fail("an unknown parameter was refused without a message naming it");
    }
    ++n;
  }
  return pass(fmt("%zu out-of-range, invalid-choice or unknown values refused with a message (e.g. \"%s\")", n,
                  note.empty() ? "unknown parameter" : note.c_str()));
}

Result check_wrong_type(const Subject& s) {
  std::size_t n = 0;
  std::string note;
  for (const auto& p : s.desc().parameters) {
    std::vector<std::string> values;
    switch (p.type) {
      case ParamType::real: values = {"not_a_number", "[1, 2]"}; break;
      case ParamType::integer: values = {"0.5", "not_a_number"}; break;
      case ParamType::boolean: values = {"not_a_boolean", "2"}; break;
      case ParamType::string:
      case ParamType::choice: values = {"[1, 2]", "{a: 1}"}; break;
    }
    for (const auto& v : values) {
      Result r = expect_refused(s, p.name, v, std::string("wrong type for a ") + to_string(p.type), note);
      if (r.status != Status::pass) return r;
      ++n;
    }
  }
  if (n == 0) return pass("no parameters");
  return pass(fmt("%zu values of the wrong type refused with a message (e.g. \"%s\")", n, note.c_str()));
}

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
