// Fluxes of particles, momentum and energy through the two boundaries of a slab, per unit area and
// time, from the host's boundary tallies.
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include <gdsmc/gdsmc.hpp>

namespace {

class WallFluxes final : public gdsmc::Diagnostic {
 public:
  static constexpr const char* name = "wall_fluxes";
  static constexpr const char* version = "1.3.1";
  static constexpr const char* summary =
      "Hit rate, momentum flux and energy flux given to the gas by each boundary, per unit area and time";
  static constexpr const char* documentation =
      "Slab systems only. The host tallies every boundary interaction (hits, m (v_after - v_before),\n"
      "(m/2)(v_after^2 - v_before^2)) since the start of the run. Between two records, over the time\n"
      "dt_w between them and the boundary area A = Lx Lz, for each boundary w = y_min, y_max:\n"
      "  <w>_hit_rate        = d(hits) / (A dt_w)                          [1/(lambda0^2 tau0)]\n"
      "  <w>_momentum_flux_<a> = d(momentum_a) / (A dt_w), a = x, y, z      [n0 T0]\n"
      "      the momentum per unit area and time the boundary gives to the gas: the x component is\n"
      "      minus the tangential stress the gas exerts on that boundary (in a steady shear flow\n"
      "      +P_xy at y_min and -P_xy at y_max); the y component is the normal (pressure) force on\n"
      "      the gas (+P_yy at y_min, -P_yy at y_max for a wall)\n"
      "  <w>_energy_flux     = d(energy) / (A dt_w)                        [n0 T0 sqrt(2T0/m)]\n"
      "      the energy per unit area and time given to the gas (the wall heat flux into the gas;\n"
      "      for Lees-Edwards planes the viscous heating of 000 Sec. III).\n"
      "The tallies are read at each sample; each record uses the last one (so dt_w is the time\n"
      "between records; the first record, at t = 0, has dt_w = 0 and gives NaN). Errors out at the\n"
      "first sample if the run has no boundary tallies. Mixtures (gdsmc.species): the host's tallies weigh each\n"
      "hit by its species' mass, so these are the whole gas's fluxes; species_moments splits them by species.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit WallFluxes(const gdsmc::Params&) {}

  void begin(const gdsmc::SystemInfo& sys, const gdsmc::QuantityBoard&, gdsmc::OutputSink& out) override {
    if (sys.geometry != gdsmc::Geometry::slab)
      throw std::runtime_error("wall_fluxes: needs a slab system (system.domain: slab)");
    area_ = sys.cross_section();
    const double v0 = std::sqrt(2.0 * sys.initial_temperature / sys.mass);
    const double nT0 = sys.number_density * sys.initial_temperature;
    rate_unit_ = 1.0 / (sys.mean_free_path0 * sys.mean_free_path0 * sys.time_unit0);
    momentum_unit_ = nT0;
    energy_unit_ = nT0 * v0;
    const char* walls[2] = {"y_min", "y_max"};
    for (int w = 0; w < 2; ++w) {
      const std::string p = walls[w];
      ids_[w][0] = out.series(p + "_hit_rate", "1/(lambda0^2 tau0)", "hits on " + p + " per unit area and time");
      const char* axis[3] = {"x", "y", "z"};
      for (int a = 0; a < 3; ++a)
        ids_[w][1 + a] = out.series(p + "_momentum_flux_" + axis[a], "n0 T0",
                                    std::string(a == 0 ? "x momentum given to the gas by " + p +
                                                             " per unit area and time (minus the wall shear stress)"
                                                       : std::string(axis[a]) + " momentum given to the gas by " + p +
                                                             " per unit area and time"));
      ids_[w][4] = out.series(p + "_energy_flux", "n0 T0 sqrt(2T0/m)",
                              "energy given to the gas by " + p + " per unit area and time (wall heat flux into the gas)");
    }
    previous_[0] = previous_[1] = current_[0] = current_[1] = gdsmc::BoundaryTally{};
    previous_time_ = current_time_ = 0;
    checked_ = false;
  }

  void sample(const gdsmc::StepContext& ctx, const gdsmc::ParticleSpan&) override {
    if (!checked_) {
      if (ctx.boundary_count < 2 || !ctx.boundaries)
        throw std::runtime_error("wall_fluxes: the run has no boundary tallies (boundary_count = " +
                                 std::to_string(ctx.boundary_count) + "); it needs a slab with y_min and y_max boundaries");
      checked_ = true;
    }
    current_[0] = ctx.boundaries[0];
    current_[1] = ctx.boundaries[1];
    current_time_ = ctx.time;
  }

  void record(const gdsmc::StepContext&, gdsmc::OutputSink& out) override {
    const double dt = current_time_ - previous_time_;
    const double inv = dt > 0 ? 1.0 / (area_ * dt) : std::nan("");
    for (int w = 0; w < 2; ++w) {
      const gdsmc::BoundaryTally& c = current_[w];
      const gdsmc::BoundaryTally& p = previous_[w];
      out.append(ids_[w][0], static_cast<double>(c.hits - p.hits) * inv / rate_unit_);
      for (int a = 0; a < 3; ++a) out.append(ids_[w][1 + a], (c.momentum[a] - p.momentum[a]) * inv / momentum_unit_);
      out.append(ids_[w][4], (c.energy - p.energy) * inv / energy_unit_);
      previous_[w] = c;
    }
    previous_time_ = current_time_;
  }
  void save_state(gdsmc::StateWriter& out) const override {
    save_tallies(out, "previous", previous_);
    save_tallies(out, "current", current_);
    out.write("previous_time", previous_time_);
    out.write("current_time", current_time_);
    out.write("checked", checked_);
  }
  void load_state(gdsmc::StateReader& in) override {
    load_tallies(in, "previous", previous_);
    load_tallies(in, "current", current_);
    in.read("previous_time", previous_time_);
    in.read("current_time", current_time_);
    in.read("checked", checked_);
  }
  // Reads none of the host's sampled moments (MomentsRead): the boundary tallies only.
  // Right in a mixture (gdsmc.species): the host's mass-weighted tallies.
  const void* extension(const char* id) const override {
    if (const void* e = gdsmc::offer_species(id)) return e;
    return gdsmc::offer_moments_read<0, gdsmc::reads_no_particles>(id);  // no particle
  }

 private:
  // The two walls' tallies as three arrays (hits, momentum x/y/z, energy), y_min first.
  static void save_tallies(gdsmc::StateWriter& out, const std::string& prefix, const gdsmc::BoundaryTally (&t)[2]) {
    const std::uint64_t hits[2] = {t[0].hits, t[1].hits};
    const double momentum[6] = {t[0].momentum[0], t[0].momentum[1], t[0].momentum[2],
                                t[1].momentum[0], t[1].momentum[1], t[1].momentum[2]};
    const double energy[2] = {t[0].energy, t[1].energy};
    out.write(prefix + ".hits", hits, 2);
    out.write(prefix + ".momentum", momentum, 6);
    out.write(prefix + ".energy", energy, 2);
  }
  static void load_tallies(gdsmc::StateReader& in, const std::string& prefix, gdsmc::BoundaryTally (&t)[2]) {
    std::uint64_t hits[2];
    double momentum[6], energy[2];
    in.read(prefix + ".hits", hits, 2);
    in.read(prefix + ".momentum", momentum, 6);
    in.read(prefix + ".energy", energy, 2);
    for (int w = 0; w < 2; ++w) {
      t[w].hits = hits[w];
      for (int a = 0; a < 3; ++a) t[w].momentum[a] = momentum[3 * w + a];
      t[w].energy = energy[w];
    }
  }

  double area_ = 1, rate_unit_ = 1, momentum_unit_ = 1, energy_unit_ = 1;
  std::size_t ids_[2][5] = {};
  gdsmc::BoundaryTally previous_[2], current_[2];
  double previous_time_ = 0, current_time_ = 0;
  bool checked_ = false;
};

}  // namespace

GDSMC_PLUGIN(WallFluxes)

// What `gdsmc conformance` runs it in when no --context is given.
// A slab between diffuse walls.
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 1.0e-3, temperature: 1.0, domain: slab, box: {y: 1.0}, layers: 4}\n"
    "boundaries: {y: diffuse_wall}")
