// gdsmc SDK: collision rules written as a small struct. The host owns the DSMC scheme (how many
// candidates a cell tests, which pairs, the majorant); the SDK turns the struct into a
// CollisionRule whose pair kernel, collide_batch, the host calls once per batch of candidate pairs,
// with the rule's physics inlined inside.
//
// A rule struct provides:
//   static constexpr const char* name, version, summary, documentation;
//   static std::vector<gdsmc::ParamSpec> parameters();
//   explicit Rule(const gdsmc::Params&);
//   // Post-collision velocities for impact direction sigma_hat (g . sigma_hat > 0 for the
//   // hard-sphere kernel); returns the kinetic-energy change it declares (m = 1).
//   double collide(gdsmc::Vec3& v1, gdsmc::Vec3& v2, const gdsmc::Vec3& sigma_hat,
//                  gdsmc::PairContext& pair) const;
// and, optionally:
//   double rate_scale() const;  // hard-sphere kernel B = rate_scale * Theta(g.s)(g.s)  (default 1)
//   double rate(const gdsmc::Vec3& g, const gdsmc::Vec3& sigma_hat) const;
//                               // a general kernel B(g, s) instead of the hard-sphere one
//   void publish(gdsmc::QuantityBoard&) const;
//   std::vector<gdsmc::AttributeSpec> attributes() const;  // extra per-particle attributes
//   void bind(const gdsmc::ParticleSpan&);  // called once before the first step: look attributes
//                                           // up here, not per pair (storage never moves)
//   void begin(const gdsmc::SystemInfo&, gdsmc::QuantityBoard&);  // see CollisionRule::begin
//   std::vector<std::string> tallies() const;  // names of the sums collide() adds to pair.tally[k]
//   double rate_bound(double speed) const;  // general kernels: max over s of rate(g, s) for
//                                           // |g| <= speed (default: speed, i.e. rate <= |g|)
//   static constexpr bool species_aware = true;  // runs in mixtures (SDK 6.5): collide() weighs
//                                           // the pair by its species' masses (pair.particles
//                                           // .species_of(pair.i), SystemInfo::species_mass) and
//                                           // pair.sigma is their sigma_ab
// collide() is called concurrently for different cells: it must not modify the rule.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gdsmc/plugin.hpp"

namespace gdsmc {

// What a rule's collide() may use besides the two velocities: the pair's storage indices (to read
// or update extra attributes, or the species: particles.species_of(i)), the pair's diameter, the
// cell's kernel stream and the rule's tallies (one entry per name of tallies(), to which the
// collision adds its contribution; nullptr if none).
struct PairContext {
  const ParticleSpan& particles;
  std::uint32_t i, j;
  double sigma;
  Rng& rng;
  double* tally = nullptr;
};

namespace detail {
template <class R>
concept HasGeneralKernel = requires(const R& r, const Vec3& g) {
  { r.rate(g, g) } -> std::convertible_to<double>;
};
template <class R>
concept HasRateScale = requires(const R& r) {
  { r.rate_scale() } -> std::convertible_to<double>;
};
template <class R>
concept HasPublish = requires(const R& r, QuantityBoard& b) { r.publish(b); };
template <class R>
concept HasBind = requires(R& r, const ParticleSpan& p) { r.bind(p); };
template <class R>
concept HasBegin = requires(R& r, const SystemInfo& s, QuantityBoard& b) { r.begin(s, b); };
template <class R>
concept HasTallies = requires(const R& r) {
  { r.tallies() } -> std::convertible_to<std::vector<std::string>>;
};
template <class R>
concept HasRateBound = requires(const R& r, double speed) {
  { r.rate_bound(speed) } -> std::convertible_to<double>;
};
template <class R>
concept SpeciesAware = requires { requires R::species_aware; };
template <class R>
concept HasAttributes = requires(const R& r) {
  { r.attributes() } -> std::convertible_to<std::vector<AttributeSpec>>;
};
}  // namespace detail

// Impact direction for the hard-sphere kernel Theta(g.s)(g.s): density proportional to the
// cosine of the angle to g on the forward hemisphere, drawn as normalize(g_hat + u) with u
// uniform on the unit sphere. Requires |g| = gnorm > 0.
inline Vec3 hard_sphere_impact_direction(const Vec3& g, double gnorm, Rng& rng) {
  const Vec3 s = (1.0 / gnorm) * g + rng.unit_vector();
  const double len = norm(s);
  if (len < 1e-300) return (1.0 / gnorm) * g;  // measure-zero event: u = -g_hat
  return (1.0 / len) * s;
}

template <class Rule>
class CollisionRuleAdapter final : public CollisionRule {
 public:
  explicit CollisionRuleAdapter(Rule rule) : rule_(std::move(rule)) {}

  const Rule& rule() const { return rule_; }

  // A rule struct that declares `static constexpr bool species_aware = true` runs in mixtures
  // (extension "gdsmc.species", plugin.hpp).
  const void* extension(const char* id) const override {
    if constexpr (detail::SpeciesAware<Rule>) return offer_species(id);
    else return CollisionRule::extension(id);
  }

  std::vector<AttributeSpec> attributes() const override {
    if constexpr (detail::HasAttributes<Rule>) return rule_.attributes();
    else return {};
  }
  void publish(QuantityBoard& board) const override {
    if constexpr (detail::HasPublish<Rule>) rule_.publish(board);
  }
  void begin(const SystemInfo& system, QuantityBoard& board) override {
    if constexpr (detail::HasBegin<Rule>) rule_.begin(system, board);
    else (void)system, (void)board;
  }
  std::vector<std::string> tallies() const override {
    if constexpr (detail::HasTallies<Rule>) return rule_.tallies();
    else return {};
  }
  double rate_bound(double speed) const override {
    if constexpr (detail::HasRateBound<Rule>) return rule_.rate_bound(speed);
    else if constexpr (detail::HasGeneralKernel<Rule>) return speed;
    else return scale() * speed;
  }

  KernelForm kernel_form() const override {
    return detail::HasGeneralKernel<Rule> ? KernelForm::general : KernelForm::hard_sphere;
  }

  double pair_rate(const Vec3& g, const Vec3& s) const override {
    if constexpr (detail::HasGeneralKernel<Rule>) {
      return rule_.rate(g, s);
    } else {
      const double gs = dot(g, s);
      return gs > 0 ? scale() * gs : 0.0;
    }
  }

  void bind(const ParticleSpan& p) override {
    if constexpr (detail::HasBind<Rule>) rule_.bind(p);
    else (void)p;
  }

  // The pair kernel (KernelForm): the hard-sphere form accepts a pair with probability |g| / w
  // (the sigma_hat-integrated rate pi scale |g| against its bound pi scale w) and then draws sigma_hat
  // from Theta(g.s)(g.s); a general kernel draws sigma_hat uniformly and accepts with probability
  // rate(g, s) / W. A candidate above its bound is accepted and reported (exceeded, max_rate).
  void collide_batch(PairBatch& b) const override {
    constexpr bool general = detail::HasGeneralKernel<Rule>;
    // A local copy of the stream (written back below): its state then stays in registers.
    Rng rng = *b.rng;
    std::uint64_t collided = 0, exceeded = 0;
    double max_rate = b.max_rate, energy = 0, missed = 0;
    for (std::uint32_t q = 0; q < b.count; ++q) {
      Vec3 v1 = b.v1[q], v2 = b.v2[q];
      const Vec3 g = v1 - v2;
      Vec3 s;
      if (b.direction) {
        s = b.direction[q];
      } else {
        const double w = b.speed_bounds ? b.speed_bounds[q] : b.speed_bound;
        double bound;
        if constexpr (general) bound = b.speed_bounds ? rate_bound(w) : b.rate_bound;
        else bound = w;
        double rate;
        if constexpr (general) {
          s = rng.unit_vector();
          rate = rule_.rate(g, s);
        } else {
          rate = norm(g);
        }
        if (rate > bound) {
          ++exceeded;
          // In units of w (what the host raises): the same factor over the bound.
          max_rate = std::max(max_rate, general ? w * rate / bound : rate);
          missed += rate / bound - 1.0;
        } else if (b.u[q] * bound >= rate) {
          b.accepted[q] = 0;
          continue;
        }
        if constexpr (!general) s = hard_sphere_impact_direction(g, rate, rng);
      }
      PairContext pair{*b.particles, b.i[q], b.j[q], b.sigma, rng, b.tally};
      energy += rule_.collide(v1, v2, s, pair);
      b.v1[q] = v1;
      b.v2[q] = v2;
      b.accepted[q] = 1;
      ++collided;
    }
    *b.rng = rng;
    b.collided += collided;
    b.exceeded += exceeded;
    b.max_rate = max_rate;
    b.energy_change += energy;
    b.missed += missed;
  }

 private:
  double scale() const {
    if constexpr (detail::HasRateScale<Rule>) return rule_.rate_scale();
    else return 1.0;
  }
  Rule rule_;
};

}  // namespace gdsmc
