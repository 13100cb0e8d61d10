// The `system:` and `output:` sections.
#include <cmath>

#include "config/sections.hpp"

namespace gdsmc::host {

void parse_system(Checker& c, const YAML::Node& sys, Pipeline& p) {
  if (!sys.IsMap()) {
    c.error("system", sys, "expected a mapping");
  } else {
    c.check_keys(sys, "system", {"density", "mean_free_path", "sigma", "temperature", "domain"});
    if (sys["sigma"])
      if (auto v = c.real(sys["sigma"], "system.sigma")) {
        if (*v <= 0) c.error("system.sigma", sys["sigma"], "sigma must be > 0");
        else p.sigma = *v;
      }
    if (sys["temperature"])
      if (auto v = c.real(sys["temperature"], "system.temperature")) {
        if (*v <= 0) c.error("system.temperature", sys["temperature"], "the initial temperature T0 must be > 0");
        else p.temperature = *v;
      }
    if (sys["density"] && sys["mean_free_path"]) {
      c.error("system", sys, "give either density or mean_free_path, not both");
    } else if (sys["density"]) {
      if (auto v = c.real(sys["density"], "system.density")) {
        if (*v <= 0) c.error("system.density", sys["density"], "number density must be > 0 (particles per sigma^3)");
        else p.number_density = *v;
      }
    } else if (sys["mean_free_path"]) {
      if (auto v = c.real(sys["mean_free_path"], "system.mean_free_path")) {
        if (*v <= 0) c.error("system.mean_free_path", sys["mean_free_path"], "mean free path must be > 0 (sigma units)");
        else p.number_density = 1.0 / (std::sqrt(2.0) * M_PI * p.sigma * p.sigma * *v);
      }
    } else {
      c.error("system", sys, "missing 'density' (n, per sigma^3) or 'mean_free_path' (lambda0, in sigma)");
    }
    if (sys["domain"]) {
      const YAML::Node d = sys["domain"];
      if (!(d.IsScalar() && d.Scalar() == "homogeneous"))
        c.error("system.domain", d, "this version runs homogeneous systems only (domain: homogeneous); slab "
                                    "domains with layers and walls are not available yet");
    }
  }
}

void parse_output(Checker& c, const YAML::Node& out, Pipeline& p) {
  if (!out.IsMap()) {
    c.error("output", out, "expected {file: NAME.h5}");
  } else {
    c.check_keys(out, "output", {"file", "particles"});
    if (out["file"]) p.output_file = out["file"].Scalar();
    if (out["particles"])
      if (auto b = c.boolean(out["particles"], "output.particles")) p.output_particles = *b;
  }
}

}  // namespace gdsmc::host
