// gdsmc SDK: collision rules written as a small struct; the SDK instantiates the per-cell DSMC
// loop (candidate count from the majorant, acceptance, the rule's update) inside the plugin, so
// the physics is inlined and the host makes one call per cell.
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
// collide() is called concurrently for different cells: it must not modify the rule.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gdsmc/plugin.hpp"

namespace gdsmc {

// What a rule's collide() may use besides the two velocities: the pair's indices (to read or
// update extra attributes), the diameter, the cell's random stream and the rule's tallies (one
// entry per name of tallies(), to which the collision adds its contribution; nullptr if none).
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

  double collide_pair(const ParticleSpan& p, std::uint32_t i, std::uint32_t j, const Vec3& s, double sigma,
                      Rng& rng) const override {
    Vec3 v1 = p.velocity(i), v2 = p.velocity(j);
    std::vector<double> scratch(tallies().size());  // conformance only: the sums are discarded
    PairContext pair{p, i, j, sigma, rng, scratch.empty() ? nullptr : scratch.data()};
    const double de = rule_.collide(v1, v2, s, pair);
    p.set_velocity(i, v1);
    p.set_velocity(j, v2);
    return de;
  }

  // Majorant-frequency scheme (000 Eqs. 4.13, 4.23): 2 P_c sigma^2 Omega_B w dt / (2 V_c)
  // candidate pairs, with P_c = c.pairs the host's pair count (N_c (N_c - 1)/2 or N_c^2/2), each accepted with probability rate / w. For the hard-sphere kernel the
  // sigma_hat-integrated rate pi |g| is used for acceptance (Omega_B = pi) and sigma_hat is then
  // drawn from Theta(g.s)(g.s); a general kernel draws sigma_hat uniformly (Omega_B = 4 pi) and
  // is accepted against W = rate_bound(w), its own bound for |g| <= w.
  void collide_cell(CellCollision& c) const override {
    if (c.count < 2 || c.majorant <= 0) {
      c.remainder = 0;
      return;
    }
    constexpr bool general = detail::HasGeneralKernel<Rule>;
    const double solid_angle = general ? 4.0 * M_PI : M_PI;
    const double w = c.majorant;
    // The bound the candidates are drawn and accepted against: |g| <= w (hard-sphere kernel, the
    // scale multiplies the candidate count), or the rule's own bound of rate(g, s).
    const double bound = general ? rate_bound(w) : w;
    const double expected =
        c.pairs * c.sigma * c.sigma * solid_angle * (general ? 1.0 : scale()) * bound * c.dt / c.volume + c.remainder;
    const auto candidates = static_cast<std::uint64_t>(expected);
    c.remainder = expected - static_cast<double>(candidates);

    const ParticleSpan& p = c.particles;
    const std::uint32_t* members = c.members;
    const std::uint64_t first = c.first, stride = c.stride, total = p.count;
    const std::uint64_t barrett = total ? ~std::uint64_t{0} / total : 0;
    const std::uint32_t count = c.count;
    // Particle a of the cell: a member list (slab layers), a contiguous range, or a strided one
    // (the sub-populations of a homogeneous system).
    auto particle = [&](std::uint32_t a) -> std::uint32_t {
      if (members) return members[a];
      if (stride == 1) return static_cast<std::uint32_t>(first + a);
      return strided_particle(first, stride, a, total, barrett);
    };
    // A local copy of the stream (written back below): its state then stays in registers instead
    // of being reloaded and stored through c.rng around every draw (~9% fewer instructions).
    Rng rng = *c.rng;
    double* const vx = p.vx;
    double* const vy = p.vy;
    double* const vz = p.vz;
    std::uint64_t accepted = 0, exceeded = 0;
    double max_rate = c.max_rate, energy = 0;
    // Candidates in batches: each batch's pairs (and acceptance numbers) are drawn first and their
    // velocities prefetched, so the memory of a large cell is fetched kBatch pairs at a time
    // instead of one; the candidates are then tested and collided in order, each on the current
    // velocities, exactly as one at a time.
    std::uint32_t batch_i[kBatch], batch_j[kBatch];
    double batch_u[kBatch];
    for (std::uint64_t k = 0; k < candidates; k += kBatch) {
      const auto m = static_cast<std::uint32_t>(std::min<std::uint64_t>(kBatch, candidates - k));
      for (std::uint32_t q = 0; q < m; ++q) {
        const std::uint32_t a = rng.below(count);
        std::uint32_t b = rng.below(count - 1);
        b += (b >= a);
        const std::uint32_t i = particle(a);
        const std::uint32_t j = particle(b);
        batch_i[q] = i;
        batch_j[q] = j;
        batch_u[q] = rng.uniform32();
        prefetch(vx + i), prefetch(vy + i), prefetch(vz + i);
        prefetch(vx + j), prefetch(vy + j), prefetch(vz + j);
      }
      for (std::uint32_t q = 0; q < m; ++q) {
        const std::uint32_t i = batch_i[q], j = batch_j[q];
        Vec3 v1{vx[i], vy[i], vz[i]}, v2{vx[j], vy[j], vz[j]};
        const Vec3 g = v1 - v2;
        double rate;
        Vec3 s;
        if constexpr (general) {
          s = rng.unit_vector();
          rate = rule_.rate(g, s);
        } else {
          rate = norm(g);
        }
        const double u = batch_u[q];
        if (rate > bound) {
          ++exceeded;
          // In units of w (what the host raises): the same factor over the bound.
          max_rate = std::max(max_rate, general ? w * rate / bound : rate);
        } else if (u * bound >= rate) {
          continue;
        }
        if constexpr (!general) s = hard_sphere_impact_direction(g, rate, rng);
        PairContext pair{p, i, j, c.sigma, rng, c.tally};
        energy += rule_.collide(v1, v2, s, pair);
        vx[i] = v1.x; vy[i] = v1.y; vz[i] = v1.z;
        vx[j] = v2.x; vy[j] = v2.y; vz[j] = v2.z;
        ++accepted;
      }
    }
    *c.rng = rng;
    c.candidates += candidates;
    c.accepted += accepted;
    c.majorant_exceeded += exceeded;
    c.max_rate = max_rate;
    c.energy_change += energy;
  }

 private:
  static constexpr std::uint32_t kBatch = 32;
  static void prefetch(const double* a) {
#if defined(__GNUC__)
    __builtin_prefetch(a, 1, 3);  // written if the pair collides
#else
    (void)a;
#endif
  }
  double scale() const {
    if constexpr (detail::HasRateScale<Rule>) return rule_.rate_scale();
    else return 1.0;
  }
  Rule rule_;
};

}  // namespace gdsmc
