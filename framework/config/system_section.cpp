// The `system:` and `output:` sections.
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "config/host_schema.hpp"
#include "config/sections.hpp"
#include "config/system_info.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {

// A length: a bare number in lambda0, or {value: X, unit: lambda0 | sigma}; `what` names it in the
// error of a length that is not positive and finite.
std::optional<double> read_length(Checker& c, const YAML::Node& n, const std::string& path, Pipeline& p,
                                  const char* what = "a box edge") {
  double value = 0;
  std::string unit = "lambda0";
  if (n.IsMap()) {
    c.check_keys(n, path, {"value", "unit"});
    if (!n["value"]) {
      c.error(path, n, "missing 'value'");
      return std::nullopt;
    }
    auto v = c.real(n["value"], path + ".value");
    if (!v) return std::nullopt;
    value = *v;
    if (n["unit"]) unit = n["unit"].Scalar();
  } else {
    auto v = c.real(n, path);
    if (!v) return std::nullopt;
    value = *v;
    if (!read_bare(c, p, path, n, value, dimensions_of(Dimension::length))) return std::nullopt;
  }
  if (!(value > 0) || !std::isfinite(value)) {
    c.error(path, n, std::string(what) + " must be a positive finite length");
    return std::nullopt;
  }
  if (unit == "lambda0") return value * p.mean_free_path0();
  if (unit == "sigma") return value * p.sigma;
  c.error(path, n["unit"] ? n["unit"] : n, "unknown length unit '" + unit + "'; valid: lambda0, sigma");
  return std::nullopt;
}

constexpr const char* kLayersGrammar =
    "valid: layers: M (M layers of equal width), layers: {uniform: M} (the same), or layers: {mean_free_paths: w, "
    "after: T[, max_width: L]} (layers at most w local mean free paths and at most L wide, set from the density "
    "profile of the transient t < T tau0 and frozen after it)";

// system.layers as a mapping: {uniform: M} or {mean_free_paths: w, after: T[, max_width: L]}.
void parse_layers(Checker& c, const YAML::Node& n, Pipeline& p) {
  c.check_keys(n, "system.layers", {"uniform", "mean_free_paths", "after", "max_width"});
  if (n["uniform"] && (n["mean_free_paths"] || n["after"] || n["max_width"])) {
    c.error("system.layers", n, std::string("give either uniform: M or mean_free_paths: w with after: T, not both; ") +
                                    kLayersGrammar);
    return;
  }
  if (n["uniform"]) {
    if (auto m = c.integer(n["uniform"], "system.layers.uniform")) {
      if (*m < 1 || *m > 100000000) c.error("system.layers.uniform", n["uniform"], "layers must be between 1 and 1e8");
      else p.layers = static_cast<std::size_t>(*m);
    }
    return;
  }
  if (!n["mean_free_paths"]) {
    c.error("system.layers", n, std::string("missing 'mean_free_paths' (the largest layer width in local mean free "
                                            "paths, e.g. 0.5) or 'uniform'; ") + kLayersGrammar);
    return;
  }
  double w = 0;  // 0: refused (reported)
  if (const std::optional<double> v = c.real(n["mean_free_paths"], "system.layers.mean_free_paths")) {
    if (*v > 0 && std::isfinite(*v))
      w = *v;
    else
      c.error("system.layers.mean_free_paths", n["mean_free_paths"],
              fmt("the layer width in local mean free paths must be a positive finite number (e.g. 0.5), got %g", *v));
  }
  if (!n["after"]) {
    c.error("system.layers", n, "missing 'after: T': the end of the transient (t in tau0) whose density profile sets "
                                "the layers, e.g. {mean_free_paths: 0.5, after: 100}");
    return;
  }
  double after_tau0 = -1;  // -1: refused (reported)
  if (const std::optional<double> after = time_in_tau0(c, n["after"], "system.layers.after", p)) {
    if (!(*after > 0 && std::isfinite(*after)))
      c.error("system.layers.after", n["after"],
              fmt("the transient must last a positive finite time (tau0), got %g: the layers are set from the density "
                  "profile measured over its second half",
                  *after));
    else if (p.stop_time_tau0 && *after >= *p.stop_time_tau0)
      c.error("system.layers.after", n["after"],
              fmt("the layers would be set at t = %g tau0, not before the run stops (run.stop.time %g tau0); give a "
                  "time before the stop, e.g. after: %g",
                  *after, *p.stop_time_tau0, 0.5 * *p.stop_time_tau0));
    else
      after_tau0 = *after;
  }
  double max_width = 0;  // 0: no bound in length; -1: refused (reported)
  if (n["max_width"]) {
    const std::optional<double> l =
        read_length(c, n["max_width"], "system.layers.max_width", p, "the widest layer (lambda0 or sigma)");
    max_width = l ? *l : -1.0;
  }
  if (!(w > 0) || after_tau0 < 0 || !(p.box_y > 0) || max_width < 0) return;
  // Ly/(w lambda0) local-mean-free-path units and Ly/L length units in all (AdaptiveLayers::edges_from_profile).
  const double units = p.box_y / (w * p.mean_free_path0()) + (max_width > 0 ? p.box_y / max_width : 0.0);
  const double layers = std::ceil(units * (1.0 - 1e-12));
  if (!(layers >= 1 && layers <= 100000000)) {
    c.error(max_width > 0 ? "system.layers" : "system.layers.mean_free_paths", max_width > 0 ? n : n["mean_free_paths"],
            fmt("%g local mean free paths%s would make %.3g layers (Ly = %.4g lambda0 holds Ly/lambda0 mean free "
                "paths in all): the count must be between 1 and 1e8",
                w, max_width > 0 ? fmt(" and max_width %.4g lambda0", max_width / p.mean_free_path0()).c_str() : "",
                layers, p.box_y / p.mean_free_path0()));
    return;
  }
  p.layers = static_cast<std::size_t>(layers);
  p.layers_mean_free_paths = w;
  p.layers_max_width = max_width;
  p.layers_after_tau0 = after_tau0;
}

// domain: homogeneous (default) or slab with box {y[, x]}, layers and bins (000 Sec. IV.A).
void parse_domain(Checker& c, const YAML::Node& sys, Pipeline& p) {
  const bool slab_keys = sys["box"] || sys["layers"] || sys["bins"];
  if (sys["domain"]) {
    const YAML::Node d = sys["domain"];
    if (d.IsScalar() && d.Scalar() == "slab") p.geometry = Geometry::slab;
    else if (!(d.IsScalar() && d.Scalar() == "homogeneous"))
      c.error("system.domain", d, "unknown domain; valid: homogeneous (one cell, no positions) or slab (layers "
                                  "along y between two boundaries, x and z periodic)");
  }
  if (p.geometry != Geometry::slab) {
    if (slab_keys) c.error("system", sys, "box, layers and bins describe a slab: add domain: slab");
    return;
  }
  if (!(p.number_density > 0)) return;  // lengths in lambda0 need the density (already reported)
  const YAML::Node box = sys["box"];
  if (!box || !box.IsMap() || !box["y"]) {
    c.error("system.box", box ? box : sys, "a slab needs its gap: box: {y: L} (L in lambda0, or {value: L, unit: sigma}); "
                                           "x is optional (default: Lx = Lz, from N/n = Lx Ly Lz)");
  } else {
    c.check_keys(box, "system.box", {"x", "y"});
    if (auto y = read_length(c, box["y"], "system.box.y", p)) p.box_y = *y;
    if (box["x"])
      if (auto x = read_length(c, box["x"], "system.box.x", p)) p.box_x = *x;
  }
  if (!sys["layers"]) {
    c.error("system.layers", sys, "a slab needs its number of layers M (collision cells along y; paper 000 uses 50)");
  } else if (sys["layers"].IsMap()) {
    parse_layers(c, sys["layers"], p);
  } else if (auto m = c.integer(sys["layers"], "system.layers")) {
    if (*m < 1 || *m > 100000000) c.error("system.layers", sys["layers"], "layers must be between 1 and 1e8");
    else p.layers = static_cast<std::size_t>(*m);
  }
}

// Every scale the host derives from n, sigma, T0, N and the time step must be a normal finite
// number: 0, a subnormal, infinity or NaN would make a step test no pair or infinitely many, or
// never move the clock. The products the moments need (V^6 for a3) are checked too. The first
// scale that fails is reported, at the system value furthest from 1 (the likely culprit); the
// scales are then unusable, so the density is cleared and the plugins (whose units need lambda0
// and tau0) are not checked.
void check_derived_scales(Checker& c, const YAML::Node& sys, Pipeline& p) {
  const double n = p.number_density, T0 = p.temperature, sigma2 = p.sigma * p.sigma;
  const double N = static_cast<double>(p.particles);
  std::vector<std::pair<std::string, double>> scales = {
      {"the number density n", n},
      {"sigma^2", sigma2},
      {"n sigma^2", n * sigma2},
      {"the mean free path lambda0 = 1/(sqrt(2) pi n sigma^2)", p.mean_free_path0()},
      {"the thermal speed sqrt(2 T0/m)", std::sqrt(2.0 * T0)},
      {"the time unit tau0 = lambda0/sqrt(2 T0/m)", p.time_unit0()},
  };
  if (N > 0 && (p.geometry != Geometry::slab || p.box_y > 0)) {
    const SystemInfo info = system_info(p, p.particles, 0);
    scales.insert(scales.end(), {{"the volume N/n", info.volume},
                                 {"the box edge Lx", info.box[0]},
                                 {"the box edge Ly", info.box[1]},
                                 {"the box edge Lz", info.box[2]},
                                 {"the cell volume", info.volume / static_cast<double>(info.cells)},
                                 {"the sum of V^6 over the particles, 105 N T0^3 (for a3)", 105.0 * N * T0 * T0 * T0}});
  }
  if (p.time_step_tau0 > 0) scales.push_back({"the time step dt = run.time_step tau0", p.time_step_tau0 * p.time_unit0()});
  if (p.stop_time_tau0) scales.push_back({"the stop time run.stop.time tau0", *p.stop_time_tau0 * p.time_unit0()});
  for (const auto& [name, value] : scales) {
    if (std::isnormal(value)) continue;
    const std::string what = value == 0 ? "0"
                             : std::isnan(value) ? "NaN"
                             : std::isinf(value) ? "infinite"
                                                 : fmt("%.3g, a subnormal number (it has lost precision)", value);
    // The given value furthest from 1 in magnitude.
    std::string key = "system";
    YAML::Node node;
    node.reset(sys);
    double worst = -1;
    for (const char* k : {"density", "mean_free_path", "sigma", "temperature"})
      if (sys[k] && sys[k].IsScalar()) {
        const double v = std::fabs(std::log10(std::fabs(std::strtod(sys[k].Scalar().c_str(), nullptr))));
        if (std::isfinite(v) && v > worst) {
          worst = v;
          key = std::string("system.") + k;
          node.reset(sys[k]);  // rebinds (node = ... would overwrite the system mapping itself)
        }
      }
    c.error(key, node,
            name + " is " + what + fmt(" (from n = %.3g, sigma = %.3g, T0 = %.3g, N = %.0f): every scale derived from the "
                                       "system must be a normal finite number; choose values nearer 1 in reduced units "
                                       "(e.g. sigma = 1, T0 = 1, n = 1e-3)",
                                       n, p.sigma, T0, N));
    p.number_density = 0;
    return;
  }
}

}  // namespace

void parse_system(Checker& c, const YAML::Node& sys, Pipeline& p) {
  if (!sys.IsMap()) {
    c.error("system", sys, "expected a mapping");
  } else {
    c.check_keys(sys, "system", system_section().keys());
    read_host_values(c, sys, system_section(), p);
    bool have_density = false;
    if (sys["density"] && sys["mean_free_path"]) {
      c.error("system", sys, "give either density or mean_free_path, not both");
    } else if (sys["density"]) {
      if (auto v = c.real(sys["density"], "system.density")) {
        if (*v <= 0) {
          c.error("system.density", sys["density"], "number density must be > 0 (particles per sigma^3)");
        } else {
          p.number_density = *v;
          have_density = true;
        }
      }
    } else if (sys["mean_free_path"]) {
      if (auto v = c.real(sys["mean_free_path"], "system.mean_free_path")) {
        if (*v <= 0) {
          c.error("system.mean_free_path", sys["mean_free_path"], "mean free path must be > 0 (sigma units)");
        } else {
          p.number_density = 1.0 / (std::sqrt(2.0) * M_PI * p.sigma * p.sigma * *v);  // may be 0 or inf: checked below
          have_density = true;
        }
      }
    } else {
      c.error("system", sys, "missing 'density' (n, per sigma^3) or 'mean_free_path' (lambda0, in sigma)");
    }
    parse_domain(c, sys, p);
    if (sys["species"]) parse_species(c, sys["species"], p);
    if (have_density) check_derived_scales(c, sys, p);
  }
}

void parse_output(Checker& c, const YAML::Node& out, Pipeline& p) {
  if (!out.IsMap()) {
    c.error("output", out, "expected {file: NAME.h5}");
  } else {
    c.check_keys(out, "output", output_section().keys());
    read_host_values(c, out, output_section(), p);
    if (const YAML::Node f = out["file"]) {
      if (f.IsScalar() && !f.Scalar().empty()) {
        p.output_file = f.Scalar();
        p.output_file_where = c.where("output.file", f);
      } else {
        c.error("output.file", f, "expected a file name such as NAME.h5, got " +
                                      (f.IsScalar() ? std::string("an empty name") : Checker::describe(f)));
      }
    }
  }
}

}  // namespace gdsmc::host
