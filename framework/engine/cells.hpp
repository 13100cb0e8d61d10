// Collision cells: the M layers of a slab along y (000 Eqs. 4.3-4.7), or the single cell of a
// homogeneous system. Particles stay where they are in storage; a stable counting sort lists each
// layer's members in increasing particle index (= identity order), so per-cell work does not
// depend on the order in which cells are processed.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include <gdsmc/context.hpp>
#include <gdsmc/physics/moments.hpp>
#include <gdsmc/particles.hpp>

#include "engine/decomposition.hpp"
#include "engine/work_pool.hpp"

namespace gdsmc::host {

class CellGrid {
 public:
  // A homogeneous system: one cell holding everyone (members() is then nullptr).
  void homogeneous(std::size_t particles, double volume);
  // A slab of `layers` layers of width height/layers along y in [-height/2, height/2].
  void slab(std::size_t particles, std::size_t layers, double height, double cross_section);
  // The slab's layers given by their edges instead (layers + 1 values from -height/2 to
  // +height/2, strictly increasing; the count does not change), or back to equal widths (empty).
  // Builds the lookup table of table_index(). Throws std::invalid_argument on edges that do not fit.
  void set_edges(std::vector<double> edges);
  // The edges set_edges was given (empty: equal widths).
  const std::vector<double>& edges() const { return edges_; }
  bool uniform() const { return edges_.empty(); }

  std::size_t count() const { return layers_; }
  bool is_slab() const { return slab_; }
  // The volume of cell c (A delta y_c in a slab; the same for every layer of equal widths).
  double cell_volume(std::size_t c = 0) const { return volumes_.empty() ? cell_volume_ : volumes_[c]; }
  // The layer of a position y (clamped: y = +height/2 belongs to the top layer); the same
  // arithmetic as SystemInfo::layer_of (or, with edges, the same comparisons), so plugins and
  // the host agree to the last bit.
  std::uint32_t layer_of(double y) const { return uniform() ? layer_index()(y) : table_index()(y); }
  // layer_of as a value a hot loop keeps in registers: with the grid behind a reference, every
  // store to a particle array may alias height_, so the loop re-read it and re-converted the
  // layer count to double per particle (a third of the mover's time at 10^6).
  struct LayerIndex {
    double half, height, layers;
    std::uint32_t last;
    // floor of f = (y + half) / height * M, clamped to [0, last] (NaN: 0). Selections only, the
    // clamp on the double before a 32-bit conversion (M < 2^31), so that the mover's flight
    // computes it for several particles at once.
    std::uint32_t operator()(double y) const {
      const double f = (y + half) / height * layers;
      const double top = static_cast<double>(last);
      const double below = f < top ? f : top;
      const double k = f > 0 ? below : 0.0;
      return static_cast<std::uint32_t>(static_cast<std::int32_t>(k));
    }
  };
  LayerIndex layer_index() const {
    return {0.5 * height_, height_, static_cast<double>(layers_), static_cast<std::uint32_t>(layers_ - 1)};
  }
  // layer_of with edges, in O(1): a uniform fine grid of bins over [-height/2, height/2] (bin b =
  // floor((y + height/2) * scale), clamped), fine enough that no two interior edges share a bin.
  // first[b] is the number of interior edges in bins below b, the lowest layer any y of bin b can
  // be in; the layer is then first[b], plus one if y is at or above the next edge (upper[k] =
  // edges[k + 1], NaN for the top layer, which no y is at or above). Only comparisons with the edges decide, as in
  // SystemInfo::layer_of's search: the same layer for every y, NaN and out-of-range values included.
  struct TableIndex {
    double half, scale, last;  // last: the last bin's number, as a double
    std::uint64_t last_bin;
    const std::uint32_t* first;
    const double* upper;
    // The fine bin of y (monotone in y; NaN and y <= -height/2: 0, y >= height/2: the last).
    std::uint64_t bin(double y) const {
      const double f = (y + half) * scale;
      if (!(f > 0)) return 0;
      return f < last ? static_cast<std::uint64_t>(f) : last_bin;
    }
    std::uint32_t operator()(double y) const {
      const std::uint32_t k = first[bin(y)];
      return k + static_cast<std::uint32_t>(y >= upper[k]);
    }
  };
  TableIndex table_index() const { return table_index(table_scale_, table_first_.size()); }
  // The fine bins of the table (a power of two; 0 with equal widths).
  std::size_t table_bins() const { return table_first_.size(); }
  static constexpr std::size_t kMaxTableBins = std::size_t{1} << 24;

  // Counting sort of the particles by the layer index already stored in cell[] (the mover writes
  // it); fills the member lists, on the pool's threads. No allocation after the first call.
  void sort(const std::uint32_t* cell, std::size_t n, WorkPool* pool = nullptr);
  // The same sort when the layers of each block of kSortBlock particles were counted already (by
  // the mover, while it wrote cell[]): block b's counts at block_counts(n) + b * count(), one
  // count() row per block, each row wholly written by its block.
  std::uint32_t* block_counts(std::size_t n);
  void sort_counted(const std::uint32_t* cell, std::size_t n, WorkPool* pool = nullptr);
  // sort_counted in two parts, for a caller that interleaves the blocks' scatter with other work
  // (CollisionStage::run: a layer collides once the blocks holding its members have placed them).
  // place_blocks: every layer's range and every block's places in it (serial, from the counts);
  // then scatter_block(b) for every block b, in any order, on any thread (or scatter_blocks: all
  // of them on the pool's threads).
  void place_blocks(std::size_t n);
  void scatter_block(const std::uint32_t* cell, std::size_t b, std::size_t n);
  void scatter_blocks(const std::uint32_t* cell, std::size_t n, WorkPool* pool = nullptr);
  // After place_blocks: the last block holding a member of layer c (kNoBlock when c is empty).
  std::size_t last_block(std::size_t c) const { return last_block_[c]; }
  static constexpr std::size_t kNoBlock = static_cast<std::size_t>(-1);
  static constexpr std::size_t kSortBlock = 16384;  // the counts: 4 * layers / kSortBlock bytes a particle
  static std::size_t sort_blocks(std::size_t n) { return (n + kSortBlock - 1) / kSortBlock; }
  // Recompute cell[] from y, then sort (after the initial state, or in tests); nothing in a
  // homogeneous system.
  void assign_and_sort(const double* y, std::uint32_t* cell, std::size_t n);

  // After storage was permuted into the order of all_members(): the layer of every position
  // written into cell[] (layer c holds positions offsets[c] .. offsets[c+1] - 1) and each layer's
  // members listed as those positions; what sort() would find, without its passes.
  void set_layer_order(std::uint32_t* cell, WorkPool* pool = nullptr);
  // Every particle, layer after layer (members of layer 0, then layer 1, ...): the order that makes
  // each layer a contiguous range of storage (ParticleStore::permute), after which assign_and_sort
  // lists each layer as 0..N_0-1, N_0.., and so on.
  const std::uint32_t* all_members() const { return members_.data(); }
  const std::uint32_t* members(std::size_t c) const { return slab_ ? members_.data() + offsets_[c] : nullptr; }
  std::uint32_t* members(std::size_t c) { return slab_ ? members_.data() + offsets_[c] : nullptr; }
  std::uint32_t members_count(std::size_t c) const { return slab_ ? offsets_[c + 1] - offsets_[c] : total_; }

  // Moments of every cell (000 Eqs. 4.4-4.6) and of the whole system; in a slab the global
  // temperature is T-bar = sum_I N_I T_I / N (Eq. 4.8) and the global mean the mean of all.
  // The sums run over fixed pieces (the layers of a slab, blocks of kMomentBlock particles of a
  // homogeneous system) on the pool's threads and are added in piece order: the same bits for
  // any thread count.
  void cell_moments(const ParticleSpan& p, double mean_density, std::vector<CellMoments>& cells,
                    CellMoments& global, WorkPool* pool = nullptr) const;
  // A decomposed slab (engine/decomposition.hpp): the span holds this rank's layers only; each
  // layer's moments are shared by its owner before the global fold, which then has the serial
  // bits on every rank. Null: one process.
  void set_exchange(const LayerExchange* exchange) { exchange_ = exchange; }
  // Each block's layer counts (block_counts(n)) from cell[], for place_blocks: after the particles
  // the mover counted have changed (a decomposed slab's migration).
  void count_blocks(const std::uint32_t* cell, std::size_t n, WorkPool* pool = nullptr);
  // Slab: the largest |v - u_I| in every layer at the last cell_moments (0 below 2 particles).
  const double* peculiar_speed_max() const { return speed_max_.data(); }

  // A mixture (engine/mixture_moments.cpp): the mass of each of `count` species (the store's
  // species column then weighs every moment: barycentric means, T = sum m_i V_i^2 / 3N, SDK
  // context.hpp); nullptr: one species of unit mass, the arithmetic above unchanged.
  void set_species(const double* mass, std::size_t count) {
    species_mass_ = mass;
    species_count_ = mass ? count : 1;
  }
  std::size_t species_count() const { return species_count_; }
  // At the last cell_moments of a mixture, for cell c and species s (index c * species_count() + s):
  // N_{c,s}, T_{c,s} = m_s sum (v - u_c)^2 / (3 N_{c,s}) (0 below 2 particles) and the largest
  // |v - u_c| of species s in the cell (0 when empty), u_c the cell's barycentric velocity.
  struct SpeciesCellMoments {
    double count = 0, temperature = 0, speed_max = 0;
  };
  const SpeciesCellMoments* species_cell_moments() const { return species_cells_.data(); }
  // Checkpoints: those moments as 3 values per cell and species, and back (their size checked).
  std::vector<double> species_cell_values() const {
    std::vector<double> v;
    for (const SpeciesCellMoments& m : species_cells_) v.insert(v.end(), {m.count, m.temperature, m.speed_max});
    return v;
  }
  bool set_species_cell_values(const std::vector<double>& v) {
    if (v.size() != 3 * layers_ * species_count_) return false;
    species_cells_.resize(layers_ * species_count_);
    for (std::size_t k = 0; k < species_cells_.size(); ++k) species_cells_[k] = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
    return true;
  }
  // The shared moments of a sampled step: peculiar velocities relative to each particle's cell
  // mean (computed fresh here), cumulants, pressure tensor, kinetic energy. Two passes (the means,
  // then the peculiar sums), or, in a homogeneous system given `conserved_mean` (a mean velocity
  // the caller knows has not moved since it was measured), one pass around it, checked below.
  // Only the MomentsPart `parts` asked for are kept, the others NaN (cell_mean_velocity nullptr):
  // without moments_peculiar the second pass is not made, without any part neither is.
  void sampled_moments(const ParticleSpan& p, double mean_density, SampledMoments& out, WorkPool* pool = nullptr,
                       const double* conserved_mean = nullptr, std::uint32_t parts = moments_all) const;
  // The sampling bins of SampledMoments::bin_sums (moments_bins): the system's bin count and its
  // layers' edges, read at each sampled_moments (nullptr: no bin sums).
  void set_sampling_system(const SystemInfo* system) { system_ = system; }
  // How far the mean may have moved from `conserved_mean`, as |u - u'|^2 / (3 T), before the one
  // pass is discarded for two: the fourth and sixth moments around u' differ from those around u
  // by a relative O(|u - u'| / sqrt(T)), here at most ~1e-10.
  static constexpr double kConservedMeanTolerance = 1e-20;
  static constexpr std::size_t kMomentBlock = 1u << 16;

 private:
  bool slab_ = false;
  std::size_t layers_ = 1;
  std::uint32_t total_ = 0;
  double height_ = 1, cell_volume_ = 0, cross_section_ = 0;
  std::vector<double> edges_;                 // layers + 1, or empty: equal widths
  std::vector<double> volumes_;               // layers, or empty: all cell_volume_
  double table_scale_ = 0;                    // fine bins per unit of y
  std::vector<std::uint32_t> table_first_;    // fine bins (TableIndex::first)
  std::vector<double> table_upper_;           // layers (TableIndex::upper)
  TableIndex table_index(double scale, std::size_t bins) const {
    return {0.5 * height_, scale, static_cast<double>(bins - 1), static_cast<std::uint64_t>(bins - 1),
            table_first_.data(), table_upper_.data()};
  }
  std::vector<std::uint32_t> offsets_;        // layers + 1
  std::vector<std::uint32_t> fill_;           // blocks x layers: counts, then next places (sort)
  std::vector<std::uint32_t> next_;           // layers: the next block's start in each (sort)
  std::vector<std::size_t> last_block_;       // layers: the last block holding a member (place_blocks)
  std::vector<std::uint32_t> members_;        // particles
  mutable std::vector<double> scratch_mean_;  // 3 * layers (sampled_moments)
  mutable std::vector<double> speed_max_;     // layers (cell_moments, slab)
  // One piece of the moment sums: a layer (slab) or a block of particles (homogeneous).
  struct PieceSums {
    double s[3] = {0, 0, 0};
    double v2 = 0, c2 = 0;
    PeculiarSums peculiar;
  };
  mutable std::vector<PieceSums> pieces_;
  // sampled_moments' parts of SDK 6.6 and a decomposed slab's shares of them (sampled_sums.cpp).
  const SystemInfo* system_ = nullptr;
  mutable std::vector<double> layer_counts_;           // decomposed: every layer's count, from its owner
  mutable std::vector<CellMoments> sampled_cells_;     // moments_cells
  mutable std::vector<double> bin_pieces_, bin_sums_;  // each piece's sums in its bins; their fold
  double layer_count(std::size_t c) const { return exchange_ ? layer_counts_[c] : members_count(c); }
  // After the first pass: every layer's count, sums of v and of v^2 (pieces_) from its owner.
  void share_sampled_means() const;
  // Every rank's particles (each layer's count from its owner), without a pass over them.
  std::size_t shared_count() const;
  // After the second: every layer's peculiar sums from its owner.
  void share_peculiar_sums() const;
  // out.cells from the layers' counts, means and peculiar sums of the passes just made.
  void fresh_cells(SampledMoments& out, double mean_density) const;
  // out.bin_sums: each piece's particles summed in its bins (a layer's few), in storage order,
  // then the pieces' sums added in piece order.
  void bin_sums(const ParticleSpan& p, SampledMoments& out, WorkPool* pool, bool heat) const;
  const LayerExchange* exchange_ = nullptr;
  mutable std::vector<double> shared_;  // a decomposed slab's layers' moments, 10 per layer
  // Every layer's cell moments, sums and largest peculiar speed from its owner (exchange_).
  void share_layers(std::vector<CellMoments>& cells) const;
  void share_mixture_layers(std::vector<CellMoments>& cells) const;  // mixture_moments.cpp
  // A mixture's (mixture_moments.cpp): the masses, and per piece and species the sums of its passes.
  const double* species_mass_ = nullptr;
  std::size_t species_count_ = 1;
  struct SpeciesSums {
    double n = 0, s[3] = {0, 0, 0}, v2 = 0, c2 = 0, c2_max = 0;
    PeculiarSums peculiar;  // mass-weighted: m V_a V_b, (m V^2)^2, (m V^2)^3
  };
  mutable std::vector<SpeciesSums> species_sums_;  // [piece * species_count_ + s]
  mutable std::vector<SpeciesCellMoments> species_cells_;  // [cell * species_count_ + s]
  mutable std::vector<double> mixture_mass_, mixture_energy_;  // per cell (mixture_sums, mixture_cell_moments)
  // Both passes of a mixture's moments over every piece: the barycentric mean of every cell
  // (into scratch_mean_), then the peculiar sums around it.
  void mixture_sums(const ParticleSpan& p, WorkPool* pool, bool peculiar) const;
  void mixture_cell_moments(const ParticleSpan& p, double mean_density, std::vector<CellMoments>& cells,
                            CellMoments& global, WorkPool* pool) const;
  void mixture_sampled_moments(const ParticleSpan& p, SampledMoments& out, WorkPool* pool, std::uint32_t parts) const;
  std::size_t piece_count() const;
  template <class Run>
  void homogeneous_moments(const ParticleSpan& p, double mean_density, CellMoments& cell, CellMoments& global,
                           Run&& run) const;
  template <class Run>
  bool one_pass_moments(const ParticleSpan& p, const double* conserved_mean, SampledMoments& out, Run&& run) const;
  // sampled_moments' passes: every part with moments_peculiar, the means and energy without it.
  void measure_moments(const ParticleSpan& p, SampledMoments& out, WorkPool* pool, const double* conserved_mean,
                       std::uint32_t parts) const;
  // The particles of piece k: [begin, end) of members(cell) (or of every particle), and its cell.
  void piece_range(std::size_t k, std::size_t& cell, std::size_t& begin, std::size_t& end) const;
  // Sums over two pieces side by side, each in its own order (cells.cpp).
  template <class Sums, class Add>
  void side_by_side(const std::size_t (&pair)[2], std::size_t count, Sums (&sums)[2], Add&& add) const;
  // piece_range, and the piece's sums set to zero for a pass to fill.
  PieceSums& open_piece(std::size_t k, std::size_t& cell, std::size_t& begin, std::size_t& end) const;
};

}  // namespace gdsmc::host
