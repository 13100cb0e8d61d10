// gdsmc SDK: what happens to a particle at a boundary plane y = side * Ly/2, for Boundary plugins
// (plugin.hpp): re-emission from thermal walls (004 Eqs. 6-9), specular reflection, Maxwell's
// partially diffuse wall (004 Sec. VI) and the transfer of periodic-type boundaries (000 Eqs. 3.1,
// 4.11). Every function works on the hit at the exact crossing time; the host streams the
// remaining flight time (WallHit::remaining) afterwards, under the body acceleration (004
// Eqs. 10-12). Reduced units; `mass` is SystemInfo::mass.
#pragma once
#include <cmath>
#include <limits>
#include <vector>

#include "gdsmc/params.hpp"
#include "gdsmc/plugin.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/vec3.hpp"

namespace gdsmc {

// The y component of a velocity that leaves the plane of `side` (-1: y = -Ly/2, +1: y = +Ly/2)
// into the gas, with magnitude |vy|: -side |vy|. The host requires it to be strictly nonzero, so
// an exact 0 (a grazing hit, or a rounding of the crossing time at the apex of a parabolic flight)
// becomes the smallest positive double. It also repairs a vy whose sign the host's crossing
// computation rounded the wrong way; otherwise it returns vy or -vy exactly.
inline double inward_normal_velocity(int side, double vy) {
  double speed = std::fabs(vy);
  if (!(speed > 0.0)) speed = std::numeric_limits<double>::denorm_min();
  return side > 0 ? -speed : speed;
}

// A normal speed from the Rayleigh ("biased Gaussian") flux distribution of a wall at temperature
// T_w, p(v) = (m v / T_w) exp(-m v^2 / 2 T_w) for v > 0 (004 Eqs. 7 and 9), by inversion:
// v = sqrt(-2 (T_w/m) ln U) with U uniform on (0, 1]. Mean sqrt(pi T_w / 2m), second moment
// 2 T_w / m. U = 1 gives exactly 0: that draw returns the smallest positive double, so the result
// is always > 0.
inline double rayleigh_normal_speed(double wall_temperature, double mass, Rng& rng) {
  const double v = std::sqrt(-2.0 * (wall_temperature / mass) * std::log(rng.uniform_open0()));
  return v > 0.0 ? v : std::numeric_limits<double>::denorm_min();
}

// The velocity with which a fully diffuse thermal wall on `side` re-emits a particle (004 Eqs. 6-9):
// the tangential components x and z Gaussian with variance T_w/m about the wall's velocity
// (Eqs. 6, 8), the normal component from the Rayleigh flux distribution (Eqs. 7, 9), pointing into
// the gas (vy > 0 at side -1, vy < 0 at side +1). The emitted flux is the half-Maxwellian at T_w
// about the wall velocity, so the wall is in detailed balance with a gas at rest relative to it at
// T_w. wall_velocity.y is ignored: a wall moves only within its plane. The "+ a t_post" of Eq. 6
// is not applied here: it is the host's streaming of the remaining time under the body
// acceleration. Draws two Gaussians and one uniform from rng.
inline Vec3 diffuse_emission(int side, double wall_temperature, const Vec3& wall_velocity, double mass, Rng& rng) {
  const double thermal = std::sqrt(wall_temperature / mass);
  Vec3 v;
  v.x = wall_velocity.x + thermal * rng.normal();                                   // Eq. 6
  v.z = wall_velocity.z + thermal * rng.normal();                                   // Eq. 8
  v.y = inward_normal_velocity(side, rayleigh_normal_speed(wall_temperature, mass, rng));  // Eqs. 7, 9
  return v;
}

// Specular reflection on the plane of the hit: v_y -> -v_y (the inward sign is enforced, see
// inward_normal_velocity), v_x and v_z unchanged. Every speed, hence the energy and the
// tangential momentum, is kept exactly; the gas receives the normal momentum 2 m |v_y|.
inline void specular_reflection(WallHit& hit) { hit.velocity.y = inward_normal_velocity(hit.side, hit.velocity.y); }

// The largest wall temperature a thermal wall takes (reduced units): its re-emitted speeds
// sqrt(-2 (T_w/m) ln U), ln U >= -745, and their squares then stay finite.
inline constexpr double kMaxWallTemperature = 1e100;

// A thermal wall: temperature T_w and in-plane velocity (u_x, 0, u_z). The parameter schema and
// the re-emission shared by diffuse_wall, maxwell_wall and third-party thermal walls.
struct ThermalWall {
  double temperature = 1.0;  // T_w (reduced units)
  Vec3 velocity{0, 0, 0};    // the wall's velocity; y is always 0

  // Parameters "temperature" (> 0, T0 units), "velocity_x" and "velocity_z" (sqrt(2 T0/m) units).
  static std::vector<ParamSpec> parameters() {
    return {ParamSpec::real("temperature", "wall temperature T_w (bare numbers: T_w / T0)")
                .above(0.0)
                .below(kMaxWallTemperature)
                .unit(Dimension::temperature)
                .default_value(1.0),
            ParamSpec::real("velocity_x", "velocity of the wall along x (bare numbers: units of sqrt(2 T0/m))")
                .unit(Dimension::velocity)
                .default_value(0.0),
            ParamSpec::real("velocity_z", "velocity of the wall along z (bare numbers: units of sqrt(2 T0/m))")
                .unit(Dimension::velocity)
                .default_value(0.0)};
  }
  ThermalWall() = default;
  explicit ThermalWall(const Params& p)
      : temperature(p.real("temperature")), velocity{p.real("velocity_x"), 0.0, p.real("velocity_z")} {}

  // Fully diffuse re-emission of the hit particle (004 Eqs. 6-9, diffuse_emission above).
  void reemit(WallHit& hit, double mass, Rng& rng) const {
    hit.velocity = diffuse_emission(hit.side, temperature, velocity, mass, rng);
  }
};

// Maxwell's partially diffuse wall (004 Sec. VI): with probability `accommodation` the diffuse
// re-emission of `wall`, otherwise specular reflection. accommodation = 1 draws exactly as a fully
// diffuse wall and 0 exactly as a specular one (no extra uniform is drawn at either end), so both
// limits reproduce those walls bit for bit.
inline void maxwell_reflection(WallHit& hit, double accommodation, const ThermalWall& wall, double mass, Rng& rng) {
  const bool diffuse = accommodation >= 1.0 || (accommodation > 0.0 && rng.uniform() < accommodation);
  if (diffuse)
    wall.reemit(hit, mass, rng);
  else
    specular_reflection(hit);
}

// The transfer of a periodic-type boundary (periodic, Lees-Edwards 000 Eq. 3.1): the particle that
// crossed the plane of hit.side re-enters through the opposite plane, y = -side * Ly/2 exactly,
// with its velocity pointing inward from there (the sign it crossed with; see
// inward_normal_velocity). x, z and the other velocity components are left to the caller.
inline void transfer_to_opposite_plane(WallHit& hit, double box_y) {
  hit.position.y = hit.side > 0 ? -0.5 * box_y : 0.5 * box_y;
  hit.velocity.y = inward_normal_velocity(-hit.side, hit.velocity.y);
}

}  // namespace gdsmc
