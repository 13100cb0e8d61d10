// Checks every plugin kind gets: load, ABI, descriptor, schema, defaults, bounds, interior,
// out-of-range and wrong-type values. Determinism, runs at once and checkpoints: checks_repeat.cpp.
#include "conformance/internal.hpp"

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
    return fail("does not construct from its defaults (" + describe_assignment(s, a) + "): " +
                error_text(own_errors(e, s.kind()), e));
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
      if (std::any_of(own.begin(), own.end(), [](const ConfigError& error) {
            return error.origin == ErrorOrigin::refused_by_plugin;
          })) {
        ++refused;
        continue;
      }
      return fail("with " + v.label + ", inside the declared range, the plugin failed instead of constructing or "
                  "refusing the value with a ParameterError: " + error_text(own, e));
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
    for (const auto& error : own_errors(e, s.kind()))
      if (error.parameter == param) {
        note = error.text();
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
      const auto own = own_errors(e, s.kind());
      if (std::none_of(own.begin(), own.end(),
                       [](const ConfigError& error) { return error.parameter == "no_such_parameter_xyz"; }))
        return fail("an unknown parameter was refused without an error naming it: " + error_text(own, e));
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

}  // namespace gdsmc::host::conformance
