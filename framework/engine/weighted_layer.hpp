// The envelope of a slab layer's weighted pairs (000 Eq. 4.13 with the pair majorant c_a + c_b, c
// the peculiar speed |v - u| about a reference velocity u, so that |g| <= c_a + c_b by the triangle
// inequality whatever u is). CollisionStage::collide_weighted draws its envelope events.
//
// Every member is covered by the bulk bound B_0 (a multiple of the members' root-mean-square
// peculiar speed); the few whose speed is at or above B_0 are listed in classes k of
// [2^k, 2^(k+1)) B_0 with the bound B_k = 2^(k+1) B_0. An envelope event picks the bulk with
// probability N B_0 / E and then a member uniformly (one that is listed is rejected: its class
// covers it), or class k with probability n_k B_k / E and one of its members;
// E = N B_0 + sum_k n_k B_k. The event is a candidate with probability c_a / B(a), B(a) the bound
// of a's class now. The speeds are kept squared (no square root per member): building the
// envelope is a vectorized pass over the members' squared speeds (their sum, and a flag for those
// at or above B_0^2), then the flags read eight at a time to list the fast ones; nothing is sorted.
// A member's speed is kept current after its collisions, and one whose speed reaches its bound is
// listed in a higher class (rise()).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <gdsmc/plugin.hpp>

namespace gdsmc::host {

class WeightedLayer {
 public:
  static constexpr int kClasses = 24;

  // The `count` members (storage indices `members`) about the velocity u, with the bulk bound
  // B_0 = bulk_over_rms times their root-mean-square peculiar speed. False if no member moves
  // relative to the others (no pair can collide) or a speed is not finite.
  bool build(const ParticleSpan& p, const std::uint32_t* members, std::uint32_t count, const double (&u)[3],
             double bulk_over_rms);
  // Particles 0 .. count-1 of storage (a homogeneous system of one group) about u, with a given bulk
  // bound B_0 (any B_0 > 0 covers the bulk; one near kBulkSpeedBound times the rms speed is the
  // efficient one): one pass over the velocities, no gather and no second pass for B_0.
  bool build_contiguous(const ParticleSpan& p, std::uint32_t count, const double (&u)[3], double bulk);

  double envelope() const { return envelope_; }  // E
  double bulk_bound() const { return low_; }      // B_0
  double peculiar_square(double vx, double vy, double vz) const {
    const double dx = vx - u_[0], dy = vy - u_[1], dz = vz - u_[2];
    return dx * dx + dy * dy + dz * dz;
  }

  // An envelope event from x uniform in [0, 1): the member a (local index), whether it was drawn
  // from the bulk, and in `thin` a number uniform in [0, 1) independent of a (the rest of x).
  std::uint32_t pick(double x, double& thin, bool& from_bulk) const {
    x *= envelope_;
    if (x < bulk_ || top_ == 0) {
      const double y = x * inverse_low_;
      std::uint32_t m = y > 0 ? static_cast<std::uint32_t>(y) : 0;
      if (m >= count_) m = count_ - 1;  // round-off at the upper edge
      thin = std::min(std::max(y - m, 0.0), 1.0);
      from_bulk = true;
      return m;
    }
    x -= bulk_;
    int k = 0;
    while (k < top_ - 1 && x >= cumulative_[k]) ++k;
    const std::uint32_t n = static_cast<std::uint32_t>(list_[k].size());
    const double y = (x - (k ? cumulative_[k - 1] : 0.0)) * inverse_[k];
    std::uint32_t m = y > 0 ? static_cast<std::uint32_t>(y) : 0;
    if (m >= n) m = n - 1;  // round-off at the class's upper edge (n > 0: the last filled class)
    thin = std::min(std::max(y - m, 0.0), 1.0);
    from_bulk = false;
    return list_[k][m];
  }
  double speed(std::uint32_t a) const { return std::sqrt(square_[a]); }  // c_a, kept current
  // The thinning of an event that picked a: thin B(a) < c_a, compared squared (thin >= 0). A listed
  // member drawn from the bulk is not a candidate (its class covers it).
  bool candidate(std::uint32_t a, double thin, bool from_bulk) const {
    const std::uint8_t listed = listed_[a];
    if (listed && from_bulk) return false;
    const double b = thin * (listed ? bound_[listed - 1] : low_);
    return b * b < square_[a];
  }
  // a's squared speed s = c^2 after a collision: if c reached its bound B(a), a is listed in the
  // class of c. Returns the rise of a's coverage (0 if none), which the caller covers with a's
  // extra events until the envelope takes it over: B_new - B_old for a listed member, B_new for one
  // that left the bulk (bulk events that pick it are now rejected). The open last class raises its
  // bound above c (above 2^23 B_0: not seen).
  double rise(std::uint32_t a, double s) {
    square_[a] = s;
    const int from = static_cast<int>(listed_[a]) - 1;  // -1: the bulk
    const double before = from < 0 ? low_ : bound_[from];
    if (s < before * before) return 0;
    int to = class_of(s);
    if (to <= from) to = from;  // the last class, beyond its bound
    if (from >= 0) {
      auto& l = list_[from];
      const std::uint32_t other = l.back();
      l[pos_[a]] = other;
      pos_[other] = pos_[a];
      l.pop_back();
    }
    pos_[a] = static_cast<std::uint32_t>(list_[to].size());
    list_[to].push_back(a);
    listed_[a] = static_cast<std::uint8_t>(to + 1);
    if (s >= bound_[to] * bound_[to]) {
      // Two ulps above sqrt(s), so that the bound's square is above s despite the roundings.
      bound_[to] = std::nextafter(std::nextafter(std::sqrt(s), INFINITY), INFINITY);
      inverse_[to] = 1.0 / bound_[to];
    }
    sum_envelope();
    return from < 0 ? bound_[to] : bound_[to] - before;
  }

 private:
  // s >= B_0^2 (to round-off): the k with c / B_0 in [2^k, 2^(k+1)), i.e. s / B_0^2 in
  // [4^k, 4^(k+1)), from the exponent's bits (no call per particle); 0 for s / B_0^2 just below 1,
  // kClasses - 1 for any larger s (and infinity).
  int class_of(double s) const {
    const double x = s * inverse_low_square_;
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const int k = (static_cast<int>((bits >> 52) & 0x7ff) - 1023) >> 1;  // floor(exponent / 2)
    return k < 0 ? 0 : k < kClasses ? k : kClasses - 1;
  }
  void reset(std::uint32_t count, const double (&u)[3]);
  void set_bulk(double bulk);
  bool list_fast();  // list the flagged members in their classes, set the bounds and the envelope
  void sum_envelope() {
    bulk_ = static_cast<double>(count_) * low_;
    double total = 0;
    top_ = 0;
    for (int k = 0; k < kClasses; ++k) {
      total += static_cast<double>(list_[k].size()) * bound_[k];
      cumulative_[k] = total;
      if (!list_[k].empty()) top_ = k + 1;
    }
    envelope_ = bulk_ + total;
  }

  std::vector<double> square_;                 // c_a^2 per member, kept current
  std::vector<std::uint8_t> listed_;          // per member: 0 in the bulk, k + 1 listed in class k
  std::vector<std::uint32_t> pos_;            // a listed member's place in its class's list
  std::vector<std::uint32_t> list_[kClasses];  // the listed members of each class (capacity kept)
  double bound_[kClasses] = {}, inverse_[kClasses] = {}, cumulative_[kClasses] = {};
  double u_[3] = {0, 0, 0};
  double low_ = 0, low_square_ = 0, inverse_low_square_ = 0, inverse_low_ = 0, bulk_ = 0, envelope_ = 0;
  std::uint32_t count_ = 0;
  int top_ = 0;  // classes 0 .. top_ - 1 hold listed members
};

// The sides of one weighted pair class in a cell: one (pairs within one list: every member, or one
// species of a mixture) or two (pairs across two species' lists, a particle from each). Side k's
// members are listed in `layer[k]` (built about one velocity u shared by both sides, so that
// |g| <= c_a + c_b holds across them) and are the local indices offset[k] .. offset[k] + count[k] - 1
// of the cell (the batch's set of open particles); a member of side k initiates envelope events at
// the rate per_bound[k] times its bound, its partner drawn uniformly from side k (one side: not
// itself) or from the other side.
struct WeightedSides {
  int n = 1;
  WeightedLayer* layer[2] = {nullptr, nullptr};
  const std::uint32_t* members[2] = {nullptr, nullptr};
  std::uint32_t count[2] = {0, 0};
  std::uint32_t offset[2] = {0, 0};
  double per_bound[2] = {0, 0};
  double rate() const {
    return n == 1 ? per_bound[0] * layer[0]->envelope()
                  : per_bound[0] * layer[0]->envelope() + per_bound[1] * layer[1]->envelope();
  }
  // The side of local index a, and a's index in its layer.
  int side_of(std::uint32_t a) const { return n == 2 && a >= offset[1] ? 1 : 0; }
};

}  // namespace gdsmc::host
