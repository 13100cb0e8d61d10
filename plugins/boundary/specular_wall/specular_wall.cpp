// Specular wall: v_y -> -v_y.
#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics.hpp>

namespace {

class SpecularWall final : public gdsmc::Boundary {
 public:
  static constexpr const char* name = "specular_wall";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* summary = "Specular (perfectly smooth, elastic) wall: v_y -> -v_y, every speed kept exactly";
  static constexpr const char* documentation =
      "Specularly reflecting wall (the accommodation coefficient 0 limit of paper 004, Sec. VI; see\n"
      "maxwell_wall). At the exact crossing time the particle stays on the plane and its normal velocity\n"
      "is reversed, v_y -> -v_y, pointing into the gas; v_x, v_z are unchanged\n"
      "(gdsmc::specular_reflection in gdsmc/physics/walls.hpp). The host then streams the remaining flight\n"
      "time of the step (under the body acceleration, if any). No parameters. Conserves mass, energy\n"
      "and the tangential (x, z) momentum exactly: every speed is kept to the last bit; the gas\n"
      "receives the normal momentum 2 m |v_y| per hit (the pressure on the wall). A v_y that is exactly\n"
      "0 at the crossing (a grazing hit) becomes the smallest positive double pointing inward.\n"
      "Mixtures (system.species): runs in them (gdsmc.species). Reversing v_y does not involve the\n"
      "mass: every particle of every species keeps its speed, so each species' energy and tangential\n"
      "momentum are conserved exactly and the gas receives 2 m_s |v_y| per hit of species s.";

  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit SpecularWall(const gdsmc::Params&) {}

  // The boundary does not involve the particle's mass (see the documentation): runs in mixtures.
  const void* extension(const char* id) const override { return gdsmc::offer_species(id); }

  gdsmc::HitResult interact(const gdsmc::StepContext&, gdsmc::WallHit& hit, gdsmc::Rng&) const override {
    gdsmc::specular_reflection(hit);
    return gdsmc::HitResult::reflected;
  }
};

}  // namespace

GDSMC_PLUGIN(SpecularWall)
