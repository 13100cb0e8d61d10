// Equivalent elastic hard spheres (EHS): elastic collisions at a collision rate reduced by beta(alpha).
#include <string>

#include <gdsmc/gdsmc.hpp>

namespace {

struct EquivalentElasticHardSpheres {
  static constexpr const char* name = "equivalent_elastic_hard_spheres";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* summary =
      "Elastic hard spheres whose collision rate is scaled by beta(alpha) (EHS that mimic IHS)";
  static constexpr const char* documentation =
      "The (frictional) elastic hard spheres of paper 000, Sec. II.B: elastic collisions, i.e. the\n"
      "rule (2.8) with alpha = 1,\n"
      "  v1' = v1 - (g.s) s,   v2' = v2 + (g.s) s,\n"
      "which conserve momentum and kinetic energy exactly (the declared energy change is 0), with the\n"
      "hard-sphere kernel multiplied by beta(alpha) = (sigma'/sigma)^2 (Eq. 2.20, beta J^(1)[f, f]): the\n"
      "number of candidate pairs is beta times that of the IHS gas (Eq. 4.23b). beta_model:\n"
      "  linear    beta = (1 + alpha)/2                  (Eq. 2.21, the paper's choice)\n"
      "  quadratic beta = (1 + alpha)(2 + alpha)/6       (Sec. VI: reproduces the NS shear viscosity)\n"
      "alpha is the restitution coefficient of the IHS gas being mimicked; the EHS collisions\n"
      "themselves are elastic. Pair this rule with the 'drag' forcing (gamma = zeta0/2, Eq. 4.22), which\n"
      "supplies the cooling. Publishes 'restitution' = alpha (the mimicked value, read by drag and the\n"
      "theory diagnostics) and 'rate_factor' = beta (read by local_equilibrium_clock and\n"
      "bgk_usf_theory). Note: the IHS-only diagnostic hcs_theory would misread this rule's\n"
      "'restitution' as a collisional inelasticity.";

  static std::vector<gdsmc::ParamSpec> parameters() {
    return {gdsmc::ParamSpec::real("alpha", "coefficient of normal restitution of the IHS gas being mimicked")
                .range(0.0, 1.0)
                .default_value(1.0),
            gdsmc::ParamSpec::choice("beta_model", {"linear", "quadratic"},
                                     "collision-rate factor: linear (1+alpha)/2 (Eq. 2.21) or quadratic "
                                     "(1+alpha)(2+alpha)/6 (Sec. VI)")
                .default_value("linear")};
  }
  static double beta_of(double alpha, const std::string& model) {
    return model == "quadratic" ? (1.0 + alpha) * (2.0 + alpha) / 6.0 : 0.5 * (1.0 + alpha);
  }
  explicit EquivalentElasticHardSpheres(const gdsmc::Params& p)
      : alpha(p.real("alpha")), beta(beta_of(alpha, p.string("beta_model"))) {}

  double rate_scale() const { return beta; }

  void publish(gdsmc::QuantityBoard& board) const {
    board.publish("restitution", alpha);
    board.publish("rate_factor", beta);
  }

  double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& s, gdsmc::PairContext&) const {
    const double gs = dot(v1 - v2, s);
    const gdsmc::Vec3 dv = gs * s;  // Eq. (2.8) with alpha = 1
    v1 -= dv;
    v2 += dv;
    return 0.0;
  }

  double alpha;
  double beta;
};

}  // namespace

GDSMC_PLUGIN(EquivalentElasticHardSpheres)
