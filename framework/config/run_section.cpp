// The `run:` section: seed, particles, time step, stop conditions, sampling, realizations.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "config/host_schema.hpp"
#include "config/sections.hpp"
#include "config/work_limits.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

std::optional<double> time_in_tau0(Checker& c, const YAML::Node& t, const std::string& key, Pipeline& p) {
  if (!t.IsMap() || !t["unit"]) {
    const YAML::Node v = t.IsMap() ? t["value"] : t;
    const std::string path = t.IsMap() ? key + ".value" : key;
    if (!v) {
      c.error(key, t, "expected a number of tau0 or {value: T, unit: tau0}");
      return std::nullopt;
    }
    if (t.IsMap()) c.check_keys(t, key, {"value", "unit"});
    const std::optional<double> value = c.real(v, path);
    if (value && !read_bare(c, p, path, v, *value, dimensions_of(Dimension::time))) return std::nullopt;
    return value;
  }
  c.check_keys(t, key, {"value", "unit"});
  if (t["unit"] && t["unit"].Scalar() != "tau0")
    c.error(key + ".unit", t["unit"], "unknown unit '" + t["unit"].Scalar() + "' (valid: tau0)");
  if (!t["value"]) {
    c.error(key, t, "expected a number of tau0 or {value: T, unit: tau0}");
    return std::nullopt;
  }
  return c.real(t["value"], key + ".value");
}

namespace {

void parse_average_after(Checker& c, const YAML::Node& aa, Pipeline& p) {
  if (!aa.IsMap()) {
    c.error("run.average_after", aa, "expected {collisions_per_particle: S} or {time: T (tau0, or {value: T, unit: tau0})}");
  } else {
    c.check_keys(aa, "run.average_after", {"collisions_per_particle", "time"});
    if (aa["collisions_per_particle"])
      if (auto v = c.real(aa["collisions_per_particle"], "run.average_after.collisions_per_particle")) {
        if (*v < 0) c.error("run.average_after.collisions_per_particle", aa["collisions_per_particle"], "must be >= 0");
        else p.average_after_collisions_per_particle = *v;
      }
    if (aa["time"])
      if (auto v = time_in_tau0(c, aa["time"], "run.average_after.time", p)) {
        if (*v < 0) c.error("run.average_after.time", aa["time"], "must be >= 0 (tau0)");
        else p.average_after_time_tau0 = *v;
      }
    if (aa["collisions_per_particle"] && aa["time"])
      c.error("run.average_after", aa, "give collisions_per_particle or time, not both");
  }
}

// run.checkpoint: {every: 10 min} (wall time: s, min, h), {every: {collisions_per_particle: S}},
// or both clocks in a list.
void parse_checkpoint(Checker& c, const YAML::Node& cp, Pipeline& p) {
  const char* valid = "expected {every: WALL_TIME} (e.g. 600 s, 10 min, 2 h), {every: {collisions_per_particle: S}}, "
                      "or both in a list: {every: [30 min, {collisions_per_particle: 100}]}";
  if (!cp.IsMap() || !cp["every"]) {
    c.error("run.checkpoint", cp, valid);
    return;
  }
  c.check_keys(cp, "run.checkpoint", {"every"});
  const YAML::Node every = cp["every"];
  std::vector<YAML::Node> items;
  if (every.IsSequence())
    for (const auto& e : every) items.push_back(e);
  else
    items.push_back(every);
  bool ok = !items.empty();
  for (const auto& e : items) {
    if (e.IsMap()) {
      c.check_keys(e, "run.checkpoint.every", {"collisions_per_particle"});
      if (!e["collisions_per_particle"]) {
        ok = false;
        c.error("run.checkpoint.every", e, valid);
      } else if (auto v = c.real(e["collisions_per_particle"], "run.checkpoint.every.collisions_per_particle")) {
        if (!(*v > 0)) c.error("run.checkpoint.every.collisions_per_particle", e["collisions_per_particle"], "must be > 0");
        else p.checkpoint_every_collisions_per_particle = *v;
      }
      continue;
    }
    // "10 min": a number and a unit of wall time.
    double value = 0;
    char unit[8] = "";
    const std::string text = e.IsScalar() ? e.Scalar() : "";
    const int fields = std::sscanf(text.c_str(), "%lf %7s", &value, unit);
    const std::string u = fields == 2 ? unit : "";
    const double seconds = u == "s" ? 1 : u == "min" ? 60 : u == "h" ? 3600 : 0;
    if (fields != 2 || seconds == 0 || !(value > 0)) {
      ok = false;
      c.error("run.checkpoint.every", e,
              "'" + text + "' is not a wall time: write a number > 0 and one of s, min, h (e.g. 10 min)");
      continue;
    }
    p.checkpoint_every_seconds = value * seconds;
  }
  p.checkpoint = ok;
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
  if (v && !(ts.IsMap() && ts["unit"]) && !read_bare(c, p, ts.IsMap() ? "run.time_step.value" : "run.time_step",
                                                     ts.IsMap() ? ts["value"] : ts, *v, dimensions_of(Dimension::time)))
    v.reset();
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

void parse_stop(Checker& c, const YAML::Node& st, Pipeline& p) {
  if (!st.IsMap()) {
    c.error("run.stop", st, "expected {collisions_per_particle: S} and/or {time: T (tau0)}");
  } else {
    const bool known_keys = c.check_keys(st, "run.stop", {"collisions_per_particle", "time", "steady"});
    if (const YAML::Node sd = st["steady"]) parse_steady(c, st, sd, p);
    if (st["collisions_per_particle"])
      if (auto v = c.real(st["collisions_per_particle"], "run.stop.collisions_per_particle")) {
        if (*v <= 0) c.error("run.stop.collisions_per_particle", st["collisions_per_particle"], "must be > 0");
        else p.stop_collisions_per_particle = *v;
      }
    if (st["time"])
      if (auto v = time_in_tau0(c, st["time"], "run.stop.time", p)) {
        if (*v <= 0) c.error("run.stop.time", st["time"], "must be > 0");
        else p.stop_time_tau0 = *v;
      }
    // A misspelled key was reported with its close spellings: not a second message about it.
    if (!st["collisions_per_particle"] && !st["time"] && known_keys)
      c.error("run.stop", st, "give collisions_per_particle and/or time, e.g. stop: {collisions_per_particle: 50}");
  }
}

// The time-step checks below estimate with the hard-sphere mean free time kMeanFreeTimeTau0 (and
// the candidate count with the initial majorant): for other kernels they are approximate, which is
// all a warning or a bound needs.

// What one step of c tau0 means at T0, checked before anything runs: a step beyond the mean free
// time is refused (free flight and forcings are split from collisions, which needs dt well below
// it; larger steps made shipped pipelines collapse and never end), one beyond half of it warned
// about (a particle then collides with probability 1 - exp(-1/2) ~ 40 % per step); so are a stop
// that would take more than kMaxSteps steps, more than kMaxCandidatesPerStep candidates per step,
// a last step that overshoots the stop by more than 10 %, and an average window after the stop.
void check_step(Checker& c, const YAML::Node& run, Pipeline& p) {
  const double dt = p.time_step_tau0;
  if (!(dt > 0)) return;
  const YAML::Node ts = run["time_step"];
  const bool map = ts.IsMap() && ts["value"];
  const YAML::Node at = map ? ts["value"] : ts;
  const std::string path = map ? "run.time_step.value" : "run.time_step";
  auto warn = [&](const std::string& where, const YAML::Node& node, const std::string& message) {
    c.warn(c.where(where, node).str() + ": " + where + ": " + message);
  };
  const double free_times = dt / kMeanFreeTimeTau0;
  if (free_times > 1) {
    c.error(path, at,
            fmt("a step of %.3g tau0 is %.3g mean free times (of hard spheres at T0: sqrt(pi)/2 tau0 = %.3f tau0), so "
                "each particle would collide about %.3g times per step; DSMC separates free flight and forcings from "
                "collisions only when the step is well below the mean free time: use at most %.3f (0.001 to 0.01 is usual)",
                dt, free_times, kMeanFreeTimeTau0, free_times, kMeanFreeTimeTau0));
    p.time_step_tau0 = 0;  // refused: nothing derived from it is checked further
    return;
  }
  if (free_times > 0.5)
    warn(path, at,
         fmt("a step of %.3g tau0 is %.2f mean free times (of hard spheres at T0: %.3f tau0): about %.0f %% of the "
             "particles collide in each step, so free flight and collisions are poorly separated; 0.001 to 0.01 is usual",
             dt, free_times, kMeanFreeTimeTau0, 100 * (1 - std::exp(-free_times))));
  // s grows by half a collision per particle per mean free time (each collision involves two).
  const double s_per_step = 0.5 * free_times;
  double steps = HUGE_VAL;
  std::string stop;
  if (p.stop_time_tau0 && *p.stop_time_tau0 / dt < steps) {
    steps = *p.stop_time_tau0 / dt;
    stop = fmt("run.stop.time %.6g tau0", *p.stop_time_tau0);
  }
  if (p.stop_collisions_per_particle && *p.stop_collisions_per_particle / s_per_step < steps) {
    steps = *p.stop_collisions_per_particle / s_per_step;
    stop = fmt("run.stop.collisions_per_particle %.6g, at about %.3g per step at T0", *p.stop_collisions_per_particle,
               s_per_step);
  }
  if (!stop.empty() && steps > kMaxSteps) {  // empty: no stop was read (already reported)
    c.error(path, at, fmt("a step of %.3g tau0 reaches the stop (%s) only after about %.3g steps, more than %.0e: the "
                          "run would never end; use a larger time step or an earlier stop",
                          dt, stop.c_str(), steps, kMaxSteps));
    p.time_step_tau0 = 0;
    return;
  }
  const double candidates = kInitialMajorantRatio * dt / 4 * static_cast<double>(p.particles);
  if (candidates > kMaxCandidatesPerStep)
    c.error(path, at, fmt("one step of %.3g tau0 with %zu particles would test about %.3g candidate pairs (about "
                          "%.2f per particle at T0), more than %.0e per step: use a smaller time step or fewer particles",
                          dt, p.particles, candidates, kInitialMajorantRatio * dt / 4, kMaxCandidatesPerStep));
  // The run stops after the first step at or past the stop.
  if (p.stop_time_tau0) {
    const double end = std::ceil(*p.stop_time_tau0 * (1.0 - 1e-12) / dt) * dt;
    if (end > 1.1 * *p.stop_time_tau0)
      warn(path, at, fmt("with steps of %.3g tau0 the run stops at t = %.3g tau0, %.3g times run.stop.time %.6g tau0%s; "
                         "use a step of at most a tenth of the stop time",
                         dt, end, end / *p.stop_time_tau0, *p.stop_time_tau0,
                         p.time_step_follows_temperature ? " (at T0; the step follows the temperature)" : ""));
  }
  if (p.stop_collisions_per_particle && s_per_step > 0.1 * *p.stop_collisions_per_particle)
    warn(path, at, fmt("each step of %.3g tau0 adds about %.3g collisions per particle (hard spheres at T0), more than "
                       "a tenth of run.stop.collisions_per_particle %.6g: the run may end well past it; use a smaller step",
                       dt, s_per_step, *p.stop_collisions_per_particle));
}

// An average window that starts at or after a stop of the same clock holds at most the last
// record, so the steady averages would be NaN.
void check_average_window(Checker& c, const YAML::Node& run, Pipeline& p) {
  const YAML::Node aa = run["average_after"];
  auto warn = [&](const char* key, double after, double stop) {
    const std::string path = std::string("run.average_after.") + key;
    c.warn(c.where(path, aa[key]).str() + ": " + path +
                         fmt(": the steady window starts at %.6g, not before run.stop.%s %.6g where the run ends: it "
                             "holds at most the last record, so every steady_stderr (and steady_mean, if the run "
                             "stops short of it) would be NaN; start the average earlier",
                             after, key, stop));
  };
  if (p.average_after_collisions_per_particle && p.stop_collisions_per_particle &&
      *p.average_after_collisions_per_particle >= *p.stop_collisions_per_particle)
    warn("collisions_per_particle", *p.average_after_collisions_per_particle, *p.stop_collisions_per_particle);
  if (p.average_after_time_tau0 && p.stop_time_tau0 && *p.average_after_time_tau0 >= *p.stop_time_tau0)
    warn("time", *p.average_after_time_tau0, *p.stop_time_tau0);
}

}  // namespace

void parse_run(Checker& c, const YAML::Node& run, Pipeline& p) {
  if (!run.IsMap()) {
    c.error("run", run, "expected a mapping");
  } else {
    c.check_keys(run, "run", run_section().keys());
    read_host_values(c, run, run_section(), p);
    if (const YAML::Node cp = run["checkpoint"]) parse_checkpoint(c, cp, p);
    if (const YAML::Node sp = run["subpopulation"]) {
      if (sp.IsScalar() && sp.Scalar() == "all") {
        p.subpopulation = 0;
      } else if (auto v = c.integer(sp, "run.subpopulation")) {
        if (*v < 2 && *v != 0)
          c.error("run.subpopulation", sp,
                  "valid: a number of particles >= 2 per collision sub-population of a homogeneous system (default "
                  "32768), or 'all' (or 0) for one population of every particle");
        else p.subpopulation = static_cast<std::size_t>(*v);
      }
    }
    if (const YAML::Node aa = run["average_after"]) parse_average_after(c, aa, p);
    if (!run["particles"]) c.error("run", run, "missing required key 'particles' (number of simulated particles, >= 2)");
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
    check_step(c, run, p);
    if (run["average_after"]) check_average_window(c, run, p);
  }
}

}  // namespace gdsmc::host
