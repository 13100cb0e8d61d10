// One slab run decomposed over the ranks of an MPI job (`gdsmc run --decompose`, docs/scaling.md):
// the layers are split into contiguous blocks, one per rank; each rank streams, sorts and collides
// the particles of its own layers. What the engine asks of the ranks is this interface; the MPI
// implementation is study/slab_ranks.cpp (the only place with mpi.h besides study/ranks.cpp).
//
// Why the result has the serial bits at any rank count: every particle carries an order key, its
// index in the single-process run's storage (which changes only at the reorderings by layer); each
// rank keeps its particles in increasing key order, so a layer's member list is the serial one and
// its collisions (streams keyed by layer) are the serial ones; per-layer sums are shared by their
// owners and folded in layer order on every rank, as the serial run folds them; the mover's tallies
// are exact integer sums (engine/fixed_point_sum.hpp); the sampled moments (bin sums and fresh cells
// too) are per-layer sums as well, so the diagnostics that read no particle (SDK 6.6) run on rank 0
// without them; those that do, forcings that act on the particles and checkpoints run on rank 0
// with the particles gathered into key order, which is the serial storage.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gdsmc::host {

// A particle on its way between ranks: every column of a store without plugin attributes, and its
// order key. 64 bytes.
struct Migrant {
  double x, y, z, vx, vy, vz;
  std::uint32_t id, species, cell, key;
};
static_assert(sizeof(Migrant) == 64, "a migrant is 64 bytes");

// Per-layer values whose owners share them (CellGrid::cell_moments, CollisionStage::run).
class LayerExchange {
 public:
  virtual ~LayerExchange() = default;
  // values[c * per_layer, (c + 1) * per_layer) for every layer c: on entry each rank holds its own
  // layers' values, on return every rank holds every layer's (from its owner).
  virtual void share(double* values, std::size_t per_layer) const = 0;
};

// The collectives of a decomposed run. Every rank calls each of them in the same order.
class Decomposition : public LayerExchange {
 public:
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  // The first layer of every rank, then the layer count (size() + 1 values, the same on every rank).
  const std::vector<std::uint32_t>& bounds() const { return bounds_; }
  void set_bounds(std::vector<std::uint32_t> bounds) { bounds_ = std::move(bounds); }
  std::uint32_t first_layer() const { return bounds_[static_cast<std::size_t>(rank_)]; }
  std::uint32_t end_layer() const { return bounds_[static_cast<std::size_t>(rank_) + 1]; }
  bool owns(std::uint32_t layer) const { return layer >= first_layer() && layer < end_layer(); }
  int owner(std::uint32_t layer) const {
    return static_cast<int>(std::upper_bound(bounds_.begin() + 1, bounds_.end() - 1, layer) - (bounds_.begin() + 1));
  }

  // Every rank's values added element by element, on every rank (exact: integers).
  virtual void sum(std::uint64_t* values, std::size_t n) const = 0;
  // Every rank's `bytes` bytes at `mine`, in rank order, into all[rank * bytes ..] on every rank.
  virtual void all_blocks(const void* mine, std::size_t bytes, void* all) const = 0;
  // Rank 0's `bytes` bytes at `data`, on every rank.
  virtual void broadcast(void* data, std::size_t bytes) const = 0;
  // outgoing[r] to rank r (size() lists; this rank's own is empty); `incoming` receives what every
  // rank sent here, in rank order.
  virtual void exchange(const std::vector<std::vector<Migrant>>& outgoing, std::vector<Migrant>& incoming) const = 0;
  // Rank 0 receives every rank's `mine`, in rank order, into `all`, and how many each sent into
  // `counts`; the other ranks only send (their `counts` hold their own count, for scatter()).
  virtual void gather(const std::vector<Migrant>& mine, std::vector<Migrant>& all, std::vector<std::size_t>& counts) const = 0;
  // The reverse of gather: rank 0 sends each rank its `counts[r]` migrants of `all` (in rank
  // order) into `mine`.
  virtual void scatter(const std::vector<Migrant>& all, const std::vector<std::size_t>& counts,
                       std::vector<Migrant>& mine) const = 0;

 protected:
  int rank_ = 0, size_ = 1;

 private:
  std::vector<std::uint32_t> bounds_;
};

}  // namespace gdsmc::host
