// The `run:` section: seed, particles, time step, stop conditions, sampling, realizations.
#include <cstdint>
#include <optional>
#include <string>

#include "config/sections.hpp"

namespace gdsmc::host {

namespace {

void parse_average_after(Checker& c, const YAML::Node& aa, Pipeline& p) {
  if (!aa.IsMap()) {
    c.error("run.average_after", aa, "expected {collisions_per_particle: S} or {time: T (tau0)}");
  } else {
    c.check_keys(aa, "run.average_after", {"collisions_per_particle", "time"});
    if (aa["collisions_per_particle"])
      if (auto v = c.real(aa["collisions_per_particle"], "run.average_after.collisions_per_particle")) {
        if (*v < 0) c.error("run.average_after.collisions_per_particle", aa["collisions_per_particle"], "must be >= 0");
        else p.average_after_collisions_per_particle = *v;
      }
    if (aa["time"])
      if (auto v = c.real(aa["time"], "run.average_after.time")) {
        if (*v < 0) c.error("run.average_after.time", aa["time"], "must be >= 0 (tau0)");
        else p.average_after_time_tau0 = *v;
      }
    if (aa["collisions_per_particle"] && aa["time"])
      c.error("run.average_after", aa, "give collisions_per_particle or time, not both");
  }
}

void parse_time_step(Checker& c, const YAML::Node& run, Pipeline& p) {
  const YAML::Node ts = run["time_step"];
  std::optional<double> v;
  std::string unit = "tau0";
  if (ts.IsMap()) {
    c.check_keys(ts, "run.time_step", {"value", "unit", "follow_temperature"});
    if (!ts["value"]) c.error("run.time_step", ts, "missing 'value'");
    else v = c.real(ts["value"], "run.time_step.value");
    if (ts["unit"]) unit = ts["unit"].Scalar();
    if (ts["follow_temperature"])
      if (auto b = c.boolean(ts["follow_temperature"], "run.time_step.follow_temperature"))
        p.time_step_follows_temperature = *b;
  } else {
    v = c.real(ts, "run.time_step");
  }
  if (unit != "tau0") c.error("run.time_step.unit", ts["unit"], "unknown unit '" + unit + "' (valid: tau0)");
  if (v && *v <= 0) c.error("run.time_step", ts, "time step must be > 0, got " + value_text(*v));
  else if (v) p.time_step_tau0 = *v;
}

void parse_steady(Checker& c, const YAML::Node& st, const YAML::Node& sd, Pipeline& p) {
  if (!sd.IsMap()) {
    c.error("run.stop.steady", sd, "expected {series: GROUP/COLUMN, window: S, tolerance: X}");
  } else {
    c.check_keys(sd, "run.stop.steady", {"series", "window", "tolerance"});
    SteadyStop ss;
    bool ok = true;
    const std::string series = sd["series"] ? sd["series"].Scalar() : "";
    const auto slash = series.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == series.size()) {
      c.error("run.stop.steady.series", sd["series"] ? sd["series"] : sd,
              "expected a series as GROUP/COLUMN, e.g. temperature/temperature");
      ok = false;
    } else {
      ss.group = series.substr(0, slash);
      ss.column = series.substr(slash + 1);
    }
    const double window = sd["window"] ? c.real(sd["window"], "run.stop.steady.window").value_or(0.0) : 0.0;
    const double tol = sd["tolerance"] ? c.real(sd["tolerance"], "run.stop.steady.tolerance").value_or(0.0) : 0.0;
    if (!(window > 0)) {
      c.error("run.stop.steady.window", sd["window"] ? sd["window"] : sd, "window must be > 0 collisions per particle");
      ok = false;
    }
    if (!(tol > 0)) {
      c.error("run.stop.steady.tolerance", sd["tolerance"] ? sd["tolerance"] : sd, "tolerance must be > 0 (relative)");
      ok = false;
    }
    if (ok) {
      ss.window = window;
      ss.tolerance = tol;
      p.stop_steady = ss;
    }
    if (!st["collisions_per_particle"] && !st["time"])
      c.error("run.stop", st, "a steady stop also needs collisions_per_particle or time as an upper limit");
  }
}

void parse_stop_time(Checker& c, const YAML::Node& t, Pipeline& p) {
  std::optional<double> v;
  if (t.IsMap()) {
    c.check_keys(t, "run.stop.time", {"value", "unit"});
    if (t["value"]) v = c.real(t["value"], "run.stop.time.value");
    if (t["unit"] && t["unit"].Scalar() != "tau0")
      c.error("run.stop.time.unit", t["unit"], "unknown unit '" + t["unit"].Scalar() + "' (valid: tau0)");
  } else {
    v = c.real(t, "run.stop.time");
  }
  if (v && *v <= 0) c.error("run.stop.time", t, "must be > 0");
  else if (v) p.stop_time_tau0 = *v;
}

void parse_stop(Checker& c, const YAML::Node& st, Pipeline& p) {
  if (!st.IsMap()) {
    c.error("run.stop", st, "expected {collisions_per_particle: S} and/or {time: T (tau0)}");
  } else {
    c.check_keys(st, "run.stop", {"collisions_per_particle", "time", "steady"});
    if (const YAML::Node sd = st["steady"]) parse_steady(c, st, sd, p);
    if (st["collisions_per_particle"])
      if (auto v = c.real(st["collisions_per_particle"], "run.stop.collisions_per_particle")) {
        if (*v <= 0) c.error("run.stop.collisions_per_particle", st["collisions_per_particle"], "must be > 0");
        else p.stop_collisions_per_particle = *v;
      }
    if (st["time"]) parse_stop_time(c, st["time"], p);
    if (!st["collisions_per_particle"] && !st["time"])
      c.error("run.stop", st, "give collisions_per_particle and/or time");
  }
}

}  // namespace

void parse_run(Checker& c, const YAML::Node& run, Pipeline& p) {
  if (!run.IsMap()) {
    c.error("run", run, "expected a mapping");
  } else {
    c.check_keys(run, "run", {"seed", "particles", "time_step", "stop", "sample_every", "record_every", "moments_every",
                              "realizations", "average_after", "candidate_pairs"});
    if (const YAML::Node cp = run["candidate_pairs"]) {
      if (cp.IsScalar() && cp.Scalar() == "squared") p.candidate_pairs_squared = true;
      else if (!(cp.IsScalar() && cp.Scalar() == "distinct"))
        c.error("run.candidate_pairs", cp,
                "valid: distinct (N_c (N_c - 1)/2 pairs per cell, the default: the Boltzmann collision rate whatever "
                "the cell's occupation) or squared (N_c^2/2, as paper 000 Eq. 4.13 writes it: 1/N_c more collisions)");
    }
    if (run["realizations"]) {
      if (auto v = c.integer(run["realizations"], "run.realizations")) {
        if (*v < 1 || *v > 100000) c.error("run.realizations", run["realizations"], "realizations must be between 1 and 100000");
        else p.realizations = static_cast<std::uint32_t>(*v);
      }
    }
    if (const YAML::Node aa = run["average_after"]) parse_average_after(c, aa, p);
    if (run["seed"]) {
      if (auto v = c.integer(run["seed"], "run.seed")) {
        if (*v < 0) c.error("run.seed", run["seed"], "seed must be >= 0");
        else p.seed = static_cast<std::uint64_t>(*v);
      }
    }
    if (!run["particles"]) {
      c.error("run", run, "missing required key 'particles' (number of simulated particles, >= 2)");
    } else if (auto v = c.integer(run["particles"], "run.particles")) {
      if (*v < 2 || *v > 4000000000LL)
        c.error("run.particles", run["particles"], "particles must be between 2 and 4e9, got " + std::to_string(*v));
      else
        p.particles = static_cast<std::size_t>(*v);
    }
    if (!run["time_step"]) {
      c.error("run", run, "missing required key 'time_step' (e.g. {value: 0.01, unit: tau0, follow_temperature: true})");
    } else {
      parse_time_step(c, run, p);
    }
    if (!run["stop"]) {
      c.error("run", run, "missing required key 'stop' (e.g. {collisions_per_particle: 50} or {time: 100})");
    } else {
      parse_stop(c, run["stop"], p);
    }
    for (auto [key, field] : {std::pair{"sample_every", &p.sample_every}, std::pair{"record_every", &p.record_every},
                              std::pair{"moments_every", &p.moments_every}}) {
      if (!run[key]) continue;
      const std::string sub = std::string("run.") + key;
      if (auto v = c.integer(run[key], sub)) {
        if (*v < 1) c.error(sub, run[key], std::string(key) + " must be a whole number of steps >= 1");
        else *field = static_cast<std::uint64_t>(*v);
      }
    }
  }
}

}  // namespace gdsmc::host
