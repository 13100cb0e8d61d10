// Inelastic hard spheres under the Enskog collision operator, for uniform shear flow in the
// Lagrangian frame (paper 002, Eqs. 2, 5, 6).
#include <cmath>
#include <cstdlib>
#include <string>

#include <gdsmc/gdsmc.hpp>
#include <gdsmc/physics/kinetic_theory.hpp>

namespace {

// Random close packing is not a limit of the Enskog theory, but no hard-sphere state exists beyond
// the close packing of spheres, pi / (3 sqrt 2); the Carnahan-Starling pole phi = 1 lies beyond it.
constexpr double kClosePacking = 0.74048048969306104;

struct EnskogHardSpheres {
  static constexpr const char* name = "enskog_hard_spheres";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Inelastic hard spheres, Enskog collisions: contact value chi(phi), shear-shifted partner (002 Eq. 2)";
  static constexpr const char* documentation =
      "Smooth inelastic hard spheres of diameter sigma at packing fraction phi = (pi/6) n sigma^3 (n and\n"
      "sigma of the system section), with the Enskog collision operator of paper 002, Eq. (2): the\n"
      "collision frequency is chi(phi) times the Boltzmann one, chi the contact value of the pair\n"
      "correlation function: Carnahan-Starling chi = (1 - phi/2)/(1 - phi)^3 (002, after Eq. 18) unless\n"
      "contact_value gives a number.\n"
      "In uniform shear flow (Lagrangian frame, velocities V peculiar to each particle's own position)\n"
      "the partner at r + sigma sigma_hat moves with the extra flow velocity a.sigma = a sigma sigma_hat_y\n"
      "x_hat, so a pair (V1, V2) collides through the relative velocity g = V1 - V2 - a.sigma (002 Eq. 2:\n"
      "f(V1 - a.sigma)): the kernel is chi sigma^2 Theta(s.g)(s.g) with that g, drawn with sigma_hat\n"
      "uniform on the sphere and accepted against the bound chi (w + a sigma / 2) (s.g <= |V1 - V2| +\n"
      "a sigma |s_x s_y|, |s_x s_y| <= 1/2), and\n"
      "  V1' = V1 - (1+alpha)/2 (s.g) s,   V2' = V2 + (1+alpha)/2 (s.g) s.\n"
      "The kinetic energy changes by -(1-alpha^2)/4 (s.g)^2 (inelastic dissipation, Eq. 6) minus\n"
      "(1+alpha)/2 a sigma (s.g) s_x s_y (the collisional part of the viscous heating, -a P^c_xy).\n"
      "The shear rate a is the 'shear_rate' a uniform_shear forcing publishes (sheared: true, the\n"
      "default: a pipeline without one is refused); sheared: false is the unsheared Enskog gas (HCS,\n"
      "equilibrium). At phi -> 0 (chi -> 1, a sigma -> 0 against the thermal speed) this is\n"
      "inelastic_hard_spheres.\n"
      "Tallies (StepContext::collision_tallies, running sums over accepted collisions):\n"
      "  collisional_transfer_ij (i, j in x, y, z) = sum sigma s_i dp_j, dp = (1+alpha)/2 (s.g) s the\n"
      "    momentum carried across the distance sigma s: the collisional transfer pressure tensor of\n"
      "    Eq. (5) is P^c_ij = (its increase) / (volume x elapsed time);\n"
      "  dissipated_energy = sum (1-alpha^2)/4 (s.g)^2: the cooling rate of Eq. (6) is\n"
      "    zeta = (its increase) / ((3/2) N T x elapsed time); anti_drag and hcs_replacement use it.\n"
      "Publishes 'restitution' = alpha, and in begin 'packing_fraction' = phi and 'contact_value' = chi.\n"
      "Homogeneous systems only in this version: in a slab the partner would sit at distance sigma in\n"
      "a neighbouring layer, which the per-layer collision stage cannot offer yet.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution").range(0.0, 1.0).default_value(1.0),
            gdsmc::ParamSpec::string("contact_value",
                                     "chi: carnahan_starling (from phi) or a number > 0 (a given contact value)")
                .default_value("carnahan_starling"),
            gdsmc::ParamSpec::boolean("sheared",
                                      "true: shift the partner by a.sigma with the published shear rate (required); "
                                      "false: no shear")
                .default_value(true)};
  }
  explicit EnskogHardSpheres(const gdsmc::Params& p)
      : alpha(p.real("alpha")), half_one_plus_alpha(0.5 * (1.0 + alpha)), sheared(p.boolean("sheared")) {
    const std::string c = p.string("contact_value");
    if (c != "carnahan_starling") {
      char* end = nullptr;
      given_chi = std::strtod(c.c_str(), &end);
      if (c.empty() || *end != '\0' || !std::isfinite(given_chi))
        throw gdsmc::ParameterError("contact_value", "'" + c + "' is neither carnahan_starling nor a number");
      if (!(given_chi > 0))
        throw gdsmc::ParameterError("contact_value", "the contact value chi must be > 0, got " + c);
    }
  }

  void publish(gdsmc::QuantityBoard& board) const { board.publish("restitution", alpha); }

  void begin(const gdsmc::SystemInfo& sys, gdsmc::QuantityBoard& board) {
    if (sys.geometry != gdsmc::Geometry::homogeneous)
      throw std::runtime_error("serves homogeneous systems only (system.domain: homogeneous): in a slab the partner at "
                               "distance sigma may sit in another layer");
    phi = M_PI / 6.0 * sys.number_density * sys.sigma * sys.sigma * sys.sigma;
    if (!(phi > 0) || !(phi < kClosePacking))
      throw std::runtime_error("system.density and system.sigma give the packing fraction phi = (pi/6) n sigma^3 = " +
                               std::to_string(phi) + "; an Enskog gas needs 0 < phi < " + std::to_string(kClosePacking) +
                               " (close packing; the Carnahan-Starling pole is phi = 1)");
    chi = given_chi > 0 ? given_chi : gdsmc::carnahan_starling_contact_value(phi);  // 002, after Eq. 18
    const double* a = board.find("shear_rate");
    if (sheared && !a)
      throw gdsmc::ParameterError("sheared", "no plugin publishes 'shear_rate': add the uniform_shear forcing (the "
                                             "shift a.sigma of Eq. 2 needs its shear rate), or set sheared: false");
    if (!sheared && a && *a != 0)
      throw gdsmc::ParameterError("sheared", "a shear rate " + std::to_string(*a) +
                                                 " is published (uniform_shear) but sheared is false: the partner's "
                                                 "shift a.sigma of Eq. 2 would be missing; set sheared: true");
    a_sigma = sheared ? *a * sys.sigma : 0.0;
    board.publish("packing_fraction", phi);
    board.publish("contact_value", chi);
  }

  std::vector<std::string> tallies() const {
    return {"collisional_transfer_xx", "collisional_transfer_xy", "collisional_transfer_xz",
            "collisional_transfer_yx", "collisional_transfer_yy", "collisional_transfer_yz",
            "collisional_transfer_zx", "collisional_transfer_zy", "collisional_transfer_zz",
            "dissipated_energy"};
  }

  // s.g with the partner's velocity shifted by a.sigma = a sigma s_y x_hat (Eq. 2).
  double shifted_normal_speed(const gdsmc::Vec3& g, const gdsmc::Vec3& s) const { return dot(g, s) - a_sigma * s.x * s.y; }

  double rate(const gdsmc::Vec3& g, const gdsmc::Vec3& s) const {
    const double gs = shifted_normal_speed(g, s);
    return gs > 0 ? chi * gs : 0.0;
  }
  double rate_bound(double speed) const { return chi * (speed + 0.5 * std::fabs(a_sigma)); }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext& pair) const {
    const double gs = shifted_normal_speed(v1 - v2, s);
    const gdsmc::Vec3 dp = (half_one_plus_alpha * gs) * s;  // momentum given by 1 to 2
    v1 -= dp;
    v2 += dp;
    if (double* t = pair.tally) {
      const double r[3] = {pair.sigma * s.x, pair.sigma * s.y, pair.sigma * s.z};
      const double q[3] = {dp.x, dp.y, dp.z};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) t[3 * i + j] += r[i] * q[j];  // sigma s_i dp_j (Eq. 5)
      t[9] += 0.25 * (1.0 - alpha * alpha) * gs * gs;            // Eq. (6)
    }
    return -0.25 * (1.0 - alpha * alpha) * gs * gs - half_one_plus_alpha * a_sigma * gs * s.x * s.y;
  }

  double alpha;
  double half_one_plus_alpha;
  bool sheared;
  double given_chi = 0;
  double phi = 0, chi = 1, a_sigma = 0;
};

}  // namespace

GDSMC_PLUGIN(EnskogHardSpheres)

// What `gdsmc conformance` runs it in when no --context is given.
// A dense, uniformly sheared gas (sheared: true, the default, reads the shear rate).
GDSMC_CONFORMANCE_CONTEXT(
    "system: {density: 0.4, sigma: 1, temperature: 1.0, domain: homogeneous}\n"
    "forcings: [{plugin: uniform_shear, shear_rate: 0.2}]")
