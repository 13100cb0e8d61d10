// What the collision stage's candidate loops share (collision_stage.cpp, collision_weighted.cpp):
// a strided group's particle by a Barrett reduction, the prefetch of a candidate's velocities, and
// the scratch of one batch of candidate pairs. Internal to the engine.
#pragma once
#include <cstdint>
#include <cstring>

#include <gdsmc/collision.hpp>

namespace gdsmc::host::candidates {

// Particle a of a group without a member list: (first + a * stride) mod n, by a Barrett reduction
// (barrett = floor((2^64 - 1) / n), computed once per group), so no division per candidate.
inline std::uint32_t strided_particle(std::uint64_t first, std::uint64_t stride, std::uint32_t a, std::uint64_t n,
                                      std::uint64_t barrett) {
  const std::uint64_t x = first + static_cast<std::uint64_t>(a) * stride;
  const auto q = static_cast<std::uint64_t>((static_cast<unsigned __int128>(x) * barrett) >> 64);
  std::uint64_t r = x - q * n;
  while (r >= n) r -= n;
  return static_cast<std::uint32_t>(r);
}

// Particle a of a group: a member list (slab layers), a contiguous range, or a strided one (the
// sub-populations of a homogeneous system) of the n particles in storage.
struct GroupParticles {
  const std::uint32_t* members;
  std::uint64_t first, stride, n, barrett;
  GroupParticles(const std::uint32_t* members_, std::uint64_t first_, std::uint64_t stride_, std::uint64_t n_)
      : members(members_), first(first_), stride(stride_), n(n_), barrett(n_ ? ~std::uint64_t{0} / n_ : 0) {}
  std::uint32_t operator()(std::uint32_t a) const {
    if (members) return members[a];
    if (stride == 1) return static_cast<std::uint32_t>(first + a);
    return strided_particle(first, stride, a, n, barrett);
  }
};

template <class T>
inline void prefetch(const T* a) {
#if defined(__GNUC__)
  __builtin_prefetch(a, 1, 3);  // written if the pair collides
#else
  (void)a;
#endif
}

// One batch of candidates being drawn: at most kPairBatch pairs with no particle twice (a set of
// the cell's local indices, hashed into kSeenBits bits: a clash, real or of the hash, closes the
// batch early). Since the rule draws from its own stream and takes the pairs in order on the
// current velocities, where a batch ends changes only the speed, never a result.
constexpr std::uint32_t kPairBatch = 32;
// A uniform draw of this many candidates (three numbers each) or more takes its numbers from a
// BulkRng (64 at a time); fewer, from the stream itself.
constexpr std::uint64_t kBulkCandidates = 32;
constexpr std::uint32_t kSeenBits = 4096;
struct BatchScratch {
  std::uint32_t i[kPairBatch], j[kPairBatch];
  Vec3 v1[kPairBatch], v2[kPairBatch];
  double u[kPairBatch], w[kPairBatch];
  // Weighted pairs: each pair's time in the step and its particles' local indices.
  double t[kPairBatch];
  std::uint32_t la[kPairBatch], lb[kPairBatch];
  std::uint8_t accepted[kPairBatch];
  std::uint64_t seen[kSeenBits / 64];
  bool dirty = true;  // seen may hold bits of pairs no longer open (a batch left by an exception)
  bool holds(std::uint32_t a) const { return (seen[(a & (kSeenBits - 1)) >> 6] >> (a & 63)) & 1; }
  // An empty batch whose arrays the rule sees through `b`. The scratch is kept per thread (a layer
  // step holds a few candidates: clearing 512 bytes per layer cost more than drawing them).
  void open(PairBatch& b) {
    if (dirty) std::memset(seen, 0, sizeof seen);
    dirty = false;
    b.i = i, b.j = j, b.v1 = v1, b.v2 = v2, b.u = u, b.accepted = accepted;
  }
  // The set emptied after the first m pairs (local indices la, lb) were closed: their words only.
  void forget(std::uint32_t m) {
    for (std::uint32_t q = 0; q < m; ++q) seen[(la[q] & (kSeenBits - 1)) >> 6] = seen[(lb[q] & (kSeenBits - 1)) >> 6] = 0;
  }
  // The set emptied after the first m pairs were closed, its words now those of no open pair.
  void close(std::uint32_t m) {
    forget(m);
    dirty = false;
  }
  // The first m pairs' velocities from storage (prefetched as the pairs were drawn).
  void load_velocities(std::uint32_t m, const double* vx, const double* vy, const double* vz) {
    for (std::uint32_t q = 0; q < m; ++q) {
      v1[q] = Vec3{vx[i[q]], vy[i[q]], vz[i[q]]};
      v2[q] = Vec3{vx[j[q]], vy[j[q]], vz[j[q]]};
    }
  }
  // The accepted ones of the first m pairs back to storage.
  void store_accepted(std::uint32_t m, double* vx, double* vy, double* vz) const {
    for (std::uint32_t q = 0; q < m; ++q) {
      if (!accepted[q]) continue;
      vx[i[q]] = v1[q].x, vy[i[q]] = v1[q].y, vz[i[q]] = v1[q].z;
      vx[j[q]] = v2[q].x, vy[j[q]] = v2[q].y, vz[j[q]] = v2[q].z;
    }
  }
  // Pair m of the batch: particles i_, j_ (the group's a, b) with acceptance number u_, its
  // particles marked open and their velocities prefetched.
  void put(std::uint32_t m, std::uint32_t a, std::uint32_t b, std::uint32_t i_, std::uint32_t j_, double u_,
           const double* vx, const double* vy, const double* vz) {
    add(a);
    add(b);
    i[m] = i_;
    j[m] = j_;
    la[m] = a;
    lb[m] = b;
    u[m] = u_;
    prefetch(vx + i_), prefetch(vy + i_), prefetch(vz + i_);
    prefetch(vx + j_), prefetch(vy + j_), prefetch(vz + j_);
  }
  void add(std::uint32_t a) {
    seen[(a & (kSeenBits - 1)) >> 6] |= std::uint64_t{1} << (a & 63);
    dirty = true;
  }
};

}  // namespace gdsmc::host::candidates
