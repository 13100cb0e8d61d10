#include "config/host_schema.hpp"

#include <cstdint>

#include "config/params.hpp"

namespace gdsmc::host {

namespace {

std::int64_t whole(const ParamValue& v) { return std::get<std::int64_t>(v); }
const std::string& text(const ParamValue& v) { return std::get<std::string>(v); }

// A key whose value is a whole number stored in `field`.
template <class T>
HostKey whole_key(ParamSpec spec, T Pipeline::*field) {
  return {std::move(spec), [field](Pipeline& p, const ParamValue& v) { p.*field = static_cast<T>(whole(v)); }};
}
HostKey flag_key(ParamSpec spec, bool Pipeline::*field) {
  return {std::move(spec), [field](Pipeline& p, const ParamValue& v) { p.*field = std::get<bool>(v); }};
}

HostSection make_run() {
  HostSection s{"run", {}, {"time_step", "stop", "average_after", "checkpoint", "subpopulation"}};
  s.values.push_back(whole_key(ParamSpec::integer("seed", "the seed of every random stream of the study (keyed with "
                                                          "the case, the realization, the cell and the particle)")
                                   .at_least(0)
                                   .default_value(1),
                               &Pipeline::seed));
  s.values.push_back(whole_key(ParamSpec::integer("particles", "the number of simulated particles N").range(2, 4e9),
                               &Pipeline::particles));
  s.values.push_back(whole_key(ParamSpec::integer("realizations", "independent runs of each case, averaged")
                                   .range(1, 100000)
                                   .default_value(1),
                               &Pipeline::realizations));
  s.values.push_back(whole_key(ParamSpec::integer("threads", "threads of the study: 0 (every core) or a count (1: one "
                                                             "run at a time); results do not depend on it")
                                   .range(0, 4096)
                                   .default_value(0),
                               &Pipeline::threads));
  for (const auto& [name, doc, field, fallback] :
       {std::tuple{"sample_every", "steps between two samples of each diagnostic", &Pipeline::sample_every, 1},
        std::tuple{"record_every", "steps between two records of each diagnostic's series", &Pipeline::record_every, 1},
        std::tuple{"moments_every", "steps between two updates of the layers' moments and majorants",
                   &Pipeline::moments_every, 4}})
    s.values.push_back(whole_key(ParamSpec::integer(name, doc).at_least(1).default_value(fallback), field));
  s.values.push_back({ParamSpec::choice("candidate_pairs", {"distinct", "squared"},
                                        "distinct: N_c (N_c - 1)/2 pairs per cell, the Boltzmann collision rate "
                                        "whatever the cell's occupation; squared: N_c^2/2, as paper 000 Eq. 4.13 "
                                        "writes it (1/N_c more collisions)")
                          .default_value("distinct"),
                      [](Pipeline& p, const ParamValue& v) { p.candidate_pairs_squared = text(v) == "squared"; }});
  s.values.push_back({ParamSpec::choice("pair_selection", {"weighted", "auto", "uniform"},
                                        "weighted: a slab layer, or a homogeneous system of one group, draws its pairs "
                                        "in proportion to their particles' peculiar speeds (68-72 % of the candidates "
                                        "accepted in paper 004's channels); auto: weighted in slab layers, and in a "
                                        "homogeneous system of one group once one majorant would accept below 30 %; "
                                        "uniform: every pair of a group alike, against one majorant (11-32 % "
                                        "accepted); see the user guide")
                          .default_value("auto"),
                      [](Pipeline& p, const ParamValue& v) {
                        p.pair_selection = text(v) == "uniform" ? 0 : text(v) == "weighted" ? 1 : 2;
                      }});
  s.values.push_back({ParamSpec::choice("sampling", {"bracketed", "after_step"},
                                        "bracketed: a diagnostic that supports it samples the state before and after "
                                        "the collision stage of each sampled step, so that stresses and fluxes carry "
                                        "no O(dt) bias from sampling at one end of the splitting; after_step: every "
                                        "diagnostic once, after the step (the rule before SDK 6.1)")
                          .default_value("bracketed"),
                      [](Pipeline& p, const ParamValue& v) { p.sampling_bracketed = text(v) == "bracketed"; }});
  return s;
}

HostSection make_system() {
  HostSection s{"system", {}, {"density", "mean_free_path", "domain", "box", "layers", "species"}};
  s.values.push_back({ParamSpec::real("sigma", "the particle diameter (the unit of length)").above(0).default_value(1.0),
                      [](Pipeline& p, const ParamValue& v) { p.sigma = std::get<double>(v); }});
  s.values.push_back({ParamSpec::real("temperature", "the initial temperature T0 (the unit of temperature)")
                          .above(0)
                          .default_value(1.0),
                      [](Pipeline& p, const ParamValue& v) { p.temperature = std::get<double>(v); }});
  s.values.push_back(whole_key(ParamSpec::integer("bins", "sampling bins along y of a slab (default: one per layer)")
                                   .range(1, 1e8),
                               &Pipeline::bins));
  return s;
}

HostSection make_output() {
  HostSection s{"output", {}, {"file"}};
  s.values.push_back(flag_key(ParamSpec::boolean("particles", "write the final particle state (/particles)")
                                  .default_value(false),
                              &Pipeline::output_particles));
  s.values.push_back(flag_key(ParamSpec::boolean("realizations", "also write each realization's own diagnostics")
                                  .default_value(false),
                              &Pipeline::output_realizations));
  s.values.push_back(flag_key(ParamSpec::boolean("plots", "draw the output with `gdsmc plot` after a successful run")
                                  .default_value(false),
                              &Pipeline::output_plots));
  return s;
}

}  // namespace

std::vector<std::string> HostSection::keys() const {
  std::vector<std::string> out;
  for (const auto& k : values) out.push_back(k.spec.name);
  out.insert(out.end(), other_keys.begin(), other_keys.end());
  return out;
}

const HostSection& run_section() {
  static const HostSection s = make_run();
  return s;
}
const HostSection& system_section() {
  static const HostSection s = make_system();
  return s;
}
const HostSection& output_section() {
  static const HostSection s = make_output();
  return s;
}

void read_host_values(Checker& c, const YAML::Node& node, const HostSection& section, Pipeline& p) {
  for (const auto& key : section.values) {
    const std::string path = section.name + "." + key.spec.name;
    if (const YAML::Node v = node[key.spec.name]) {
      if (auto value = read_value(c, p, key.spec, v, path, section.name + " key '" + key.spec.name + "' (" + key.spec.doc + ")"))
        key.apply(p, *value);
    } else if (key.spec.default_) {
      key.apply(p, *key.spec.default_);
    }
  }
}

}  // namespace gdsmc::host
