// Periodic boundary along y: a particle leaving through one plane re-enters through the other.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class Periodic final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "periodic";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary = "Periodic boundary along y: re-entry through the opposite plane, velocity unchanged";
  static constexpr const char* documentation =
      "Periodic y boundary: the slab is repeated along y with period Ly (the Lees-Edwards condition,\n"
      "paper 000 Eq. 3.1, with U = 0; see lees_edwards). At the exact crossing time of the plane\n"
      "y = +Ly/2 (y_max) the particle is moved to y = -Ly/2, and from y = -Ly/2 (y_min) to +Ly/2, with\n"
      "x, z and the velocity unchanged; the host then streams the remaining flight time of the step\n"
      "(under the body acceleration, if any) from the opposite plane. Both y_min and y_max must be\n"
      "this plugin (transfers() = true). No parameters. Conserves mass, momentum and energy exactly:\n"
      "the boundary tallies stay zero. (The only change it can make to a velocity: a v_y that is\n"
      "exactly 0 at the crossing becomes the smallest positive double pointing inward.)\n"
      "Mixtures (system.species): runs in them (gdsmc.species). The transfer moves a particle and\n"
      "keeps its velocity whatever its mass, so it conserves every species' number, momentum and\n"
      "energy exactly.";

  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit Periodic(const gdsmc::Params&) {}

  // The boundary does not involve the particle's mass (see the documentation): runs in mixtures.
  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  bool transfers() const override { return true; }
  gdsmc::HitResult interact(const gdsmc::StepContext& ctx, gdsmc::WallHit& hit, gdsmc::Rng&) const override {
    gdsmc::transfer_to_opposite_plane(hit, ctx.system->box[1]);
    return gdsmc::HitResult::transferred;
  }
};

}  // namespace

GDSMC_PLUGIN(Periodic)
