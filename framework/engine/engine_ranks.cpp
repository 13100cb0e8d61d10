// A slab run decomposed over ranks (engine/decomposition.hpp): each rank keeps the particles of its
// block of layers in increasing order key, migrates those that stream out of it, renumbers the keys
// at every reordering as the single-process run renumbers its storage, and moves its block
// boundaries by measured cost; rank 0 gathers the particles into key order for the stages that see
// every particle (forcings, diagnostics, checkpoints, the output).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "engine/engine.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {
// What a refusal of --decompose says, after why.
std::string refused(const std::string& why) {
  return "--decompose: " + why + "; run it without --decompose (one process, or an ensemble over the ranks: "
         "docs/cluster.md)";
}
}  // namespace

std::string Engine::why_not_decomposed(const Pipeline& p, int ranks) {
  if (p.geometry != Geometry::slab) return refused("a homogeneous system has one collision cell, nothing to split into layers");
  if (p.layers < static_cast<std::size_t>(ranks))
    return refused(fmt("%d ranks for %zu layers (system.layers): a rank needs at least one layer", ranks, p.layers));
  return "";
}

void Engine::decompose(Decomposition& ranks) {
  if (const std::string why = why_not_decomposed(pipeline_, ranks.size()); !why.empty()) throw std::runtime_error(why);
  if (!store_.attribute_specs().empty())
    throw std::runtime_error(refused("per-particle plugin attributes ('" + store_.attribute_specs().front().name +
                                     "') do not travel between ranks yet"));
  ranks_ = &ranks;
  if (ranks.size() == 1) {
    ranks.set_bounds({0u, static_cast<std::uint32_t>(grid_.count())});
  } else {
    std::vector<double> cost(grid_.count());
    for (std::size_t c = 0; c < cost.size(); ++c) cost[c] = grid_.members_count(c);
    set_bounds(cost);
  }
  outgoing_.assign(static_cast<std::size_t>(ranks.size()), {});
  // Rank 0's gathered store and its grid (the layers as this run's).
  if (ranks.root()) {
    whole_grid_.slab(system_.particles, grid_.count(), system_.box[1], system_.cross_section());
    if (!grid_.uniform()) whole_grid_.set_edges(grid_.edges());
    whole_grid_.set_species(species_mass(), system_.species_count);
    whole_grid_.set_sampling_system(&system_);
  }
  store_.enable_keys();  // the storage order now is the single-process run's
  keep_own_layers();
  grid_.set_exchange(&ranks);
  collisions_.set_exchange(&ranks);
}

// Contiguous blocks of layers of about equal cost, each of at least one layer.
void Engine::set_bounds(const std::vector<double>& cost) {
  const std::size_t layers = cost.size(), n = static_cast<std::size_t>(ranks_->size());
  double total = 0;
  for (double c : cost) total += c;
  std::vector<std::uint32_t> bounds(n + 1, 0);
  bounds[n] = static_cast<std::uint32_t>(layers);
  double below = 0;
  std::size_t c = 0;
  for (std::size_t r = 1; r < n; ++r) {
    const double target = total * static_cast<double>(r) / static_cast<double>(n);
    // At least one layer for this rank and for each after it.
    while (c < layers - (n - r) && (c < bounds[r - 1] + 1 || below + 0.5 * cost[c] < target)) below += cost[c++];
    bounds[r] = static_cast<std::uint32_t>(c);
  }
  ranks_->set_bounds(std::move(bounds));
}

// The particles of this rank's layers only, in the order they are in (a particle leaving nothing
// behind: each rank set up the whole state alike).
void Engine::keep_own_layers() {
  const std::uint32_t* cell = store_.cells();
  store_.remove_if([&](std::size_t i) { return !ranks_->owns(cell[i]); }, [](const Migrant&) {});
  checked_collision_.bind(store_.span());
  grid_.sort(store_.cells(), store_.size(), &pool_);
}

// After streaming: the particles whose new layer another rank owns go to it (their places filled
// by the last particles), and those that came here are appended; sort_members_by_key then puts each
// layer's member list in key order. Storage is never shifted: a compaction in order moved every
// particle of a rank whose lower neighbour takes its first layer's leavers, at every step (1 ms a
// step at 5e5 particles). Each block's layer counts are then counted afresh for the sort.
void Engine::migrate(bool count) {
  const auto start = std::chrono::steady_clock::now();
  for (auto& list : outgoing_) list.clear();
  const std::uint32_t* cell = store_.cells();
  store_.remove_if([&](std::size_t i) { return !ranks_->owns(cell[i]); },
                   [&](const Migrant& m) { outgoing_[static_cast<std::size_t>(ranks_->owner(m.cell))].push_back(m); });
  ranks_->exchange(outgoing_, incoming_);
  if (store_.append(incoming_)) checked_collision_.bind(store_.span());
  if (count) {
    std::uint64_t moved = incoming_.size();
    ranks_->sum(&moved, 1);
    migrated_ += moved;
    ++migration_steps_;
  }
  grid_.count_blocks(store_.cells(), store_.size(), &pool_);
  migration_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Each layer's member list in increasing key (the single-process run's order): the sort lists
// members in storage order, which is key order after a reordering; the layers where a migration
// has put a particle out of that order are sorted by key.
void Engine::sort_members_by_key() {
  const std::uint32_t* key = store_.keys();
  const auto by_key = [key](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; };
  for_pieces(&pool_, ranks_->end_layer() - ranks_->first_layer(), [&](std::size_t k) {
    const std::size_t c = ranks_->first_layer() + k;
    std::uint32_t* m = grid_.members(c);
    const std::uint32_t n = grid_.members_count(c);
    if (!std::is_sorted(m, m + n, by_key)) std::sort(m, m + n, by_key);
  });
}

// After the layers' permutation: layer c's particles, at local places offset_c .. offset_c + N_c - 1,
// become keys G_c .. G_c + N_c - 1, G_c the particles of the layers below c on every rank: the
// places the single-process run's reordering gives them.
void Engine::renumber_keys() {
  const std::size_t layers = grid_.count();
  layer_values_.assign(layers, 0.0);
  for (std::size_t c = ranks_->first_layer(); c < ranks_->end_layer(); ++c) layer_values_[c] = grid_.members_count(c);
  ranks_->share(layer_values_.data(), 1);
  std::uint32_t* key = store_.keys();
  std::uint64_t global = 0;
  std::size_t local = 0;
  for (std::size_t c = 0; c < layers; ++c) {
    const auto n = static_cast<std::uint64_t>(layer_values_[c]);
    if (ranks_->owns(static_cast<std::uint32_t>(c)))
      for (std::uint64_t k = 0; k < n; ++k) key[local++] = static_cast<std::uint32_t>(global + k);
    global += n;
  }
}

// Each layer's cost: its particles (flight, sort, moments) and the candidates it tested since the
// last reordering (collisions), weighed by rank 0's measured seconds per particle moved and per
// candidate. The same on every rank (the collision counts are shared by their owners, and the
// particle counts were, by renumber_keys just before, into layer_values_).
std::vector<double> Engine::layer_costs() {
  double weight = 0;  // seconds per candidate over seconds per particle and step
  if (ranks_->root()) {
    const double moves = static_cast<double>(ctx_.step) * static_cast<double>(system_.particles);
    const double flight = stage_seconds(Stage::flight) + stage_seconds(Stage::sort) + stage_seconds(Stage::moments);
    const double candidates = static_cast<double>(ctx_.candidates);
    if (moves > 0 && flight > 0 && candidates > 0) weight = (stage_seconds(Stage::collisions) / candidates) / (flight / moves);
  }
  ranks_->broadcast(&weight, sizeof weight);
  std::vector<double> cost;
  collisions_.take_candidates(cost);
  for (std::size_t c = 0; c < cost.size(); ++c)
    cost[c] = layer_values_[c] * static_cast<double>(kReorderEvery) + weight * cost[c];
  return cost;
}

// At a reordering: new block boundaries when the costliest rank would gain more than 10 %; the
// layers that change rank move whole, and their member lists are put back in key order.
void Engine::rebalance() {
  const std::vector<double> cost = layer_costs();
  const std::vector<std::uint32_t> before = ranks_->bounds();
  const auto largest = [&](const std::vector<std::uint32_t>& b) {
    double most = 0;
    for (std::size_t r = 0; r + 1 < b.size(); ++r) {
      double sum = 0;
      for (std::uint32_t c = b[r]; c < b[r + 1]; ++c) sum += cost[c];
      most = std::max(most, sum);
    }
    return most;
  };
  set_bounds(cost);
  if (ranks_->bounds() == before || largest(ranks_->bounds()) > 0.9 * largest(before)) {
    ranks_->set_bounds(before);
    return;
  }
  ++rebalanced_;
  migrate(false);
  grid_.sort(store_.cells(), store_.size(), &pool_);
  sort_members_by_key();
}

// The mover's tallies of every rank, added exactly (fixed point: integers), on every rank; then
// their values, which are those of the single-process run (its blocks add the same integers).
void Engine::merge_tally(StreamingTally& tally) const {
  constexpr std::size_t kWords = 3, kPerSide = 1 + 4 * kWords;
  // The two sides, a mixture's sides per species, then the body force's work.
  const std::size_t species = species_mass() ? system_.species_count : 0, sides = 2 + 2 * species;
  const std::size_t per_rank = sides * kPerSide + kWords;
  const auto side = [&](ExactStreamingTally& t, std::size_t k) -> ExactBoundaryTally& {
    return k < 2 ? t.sides[k] : t.species_sides[(k - 2) / species * StreamingTally::kMaxSpecies + (k - 2) % species];
  };
  std::vector<std::uint64_t>& all = merged_words_;
  all.resize(per_rank * (1 + static_cast<std::size_t>(ranks_->size())));
  std::uint64_t* mine = all.data() + per_rank * static_cast<std::size_t>(ranks_->size());
  const auto put = [](std::uint64_t* at, const FixedPointSum& sum) {
    const FixedPointSum::Words w = sum.words();
    std::copy(w.begin(), w.end(), at);
  };
  for (std::size_t k = 0; k < sides; ++k) {
    const ExactBoundaryTally& t = side(tally.exact, k);
    std::uint64_t* at = mine + k * kPerSide;
    at[0] = t.hits;
    for (std::size_t a = 0; a < 3; ++a) put(at + 1 + a * kWords, t.momentum[a]);
    put(at + 1 + 3 * kWords, t.energy);
  }
  put(mine + sides * kPerSide, tally.exact.acceleration_energy);
  ranks_->all_blocks(mine, per_rank * sizeof(std::uint64_t), all.data());
  const auto get = [](const std::uint64_t* at) { return FixedPointSum::from_words({at[0], at[1], at[2]}); };
  ExactStreamingTally sum;
  for (int r = 0; r < ranks_->size(); ++r) {
    const std::uint64_t* v = all.data() + per_rank * static_cast<std::size_t>(r);
    ExactStreamingTally part;
    for (std::size_t k = 0; k < sides; ++k) {
      const std::uint64_t* at = v + k * kPerSide;
      ExactBoundaryTally& t = side(part, k);
      t.hits = at[0];
      for (std::size_t a = 0; a < 3; ++a) t.momentum[a] = get(at + 1 + a * kWords);
      t.energy = get(at + 1 + 3 * kWords);
    }
    part.acceleration_energy = get(v + sides * kPerSide);
    sum += part;
  }
  tally.exact = sum;
  tally.to_values(mover_->tally_units(), species);
}

void Engine::gather_whole() {
  const auto start = std::chrono::steady_clock::now();
  ++gathers_;
  const std::size_t n = store_.size();
  if (packed_.capacity() < n) packed_.reserve(n + n / 8);  // headroom: the count moves with migration
  packed_.resize(n);
  for (std::size_t i = 0; i < n; ++i) packed_[i] = store_.migrant(i);
  ranks_->gather(packed_, gathered_, gathered_counts_);
  const auto done = [&] {
    gather_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (!ranks_->root()) return done();
  if (whole_.size() != system_.particles) whole_.reserve_like(system_.particles, store_.has_species());
  for (const Migrant& m : gathered_) {
    if (m.key >= whole_.size()) throw std::logic_error("gather: a key beyond the particle count");
    whole_.set(m.key, m);
  }
  whole_grid_.sort(whole_.cells(), whole_.size(), &pool_);
  done();
}

void Engine::return_whole() {
  if (ranks_->root())
    for (Migrant& m : gathered_) m = whole_.migrant(m.key);
  ranks_->scatter(gathered_, gathered_counts_, packed_);
  for (std::size_t i = 0; i < packed_.size(); ++i) store_.set(i, packed_[i]);
}

void Engine::set_layers_decomposed() {
  const std::size_t layers = grid_.count();
  std::vector<double> edges(layers + 1), counts(layers);
  gather_whole();
  if (ranks_->root()) {
    on_whole_serial([&] { set_layers_from_profile(); });
    edges = whole_grid_.edges();
    for (std::size_t c = 0; c < layers; ++c) counts[c] = whole_grid_.members_count(c);
    whole_.enable_keys();  // the reordered storage is the single-process run's
  }
  ranks_->broadcast(edges.data(), edges.size() * sizeof(double));
  ranks_->broadcast(counts.data(), counts.size() * sizeof(double));
  grid_.set_edges(edges);
  if (!ranks_->root()) layers_.adopt(edges, ctx_.time_in_tau0());
  set_bounds(counts);
  // Each rank's layers are a contiguous range of the reordered particles.
  const auto& bounds = ranks_->bounds();
  gathered_counts_.assign(static_cast<std::size_t>(ranks_->size()), 0);
  for (std::size_t r = 0; r + 1 < bounds.size(); ++r)
    for (std::uint32_t c = bounds[r]; c < bounds[r + 1]; ++c) gathered_counts_[r] += static_cast<std::size_t>(counts[c]);
  if (ranks_->root()) {
    gathered_.resize(whole_.size());
    for (std::size_t i = 0; i < whole_.size(); ++i) gathered_[i] = whole_.migrant(i);
  }
  ranks_->scatter(gathered_, gathered_counts_, packed_);
  store_.resize(0);
  store_.append(packed_);
  checked_collision_.bind(store_.span());
  grid_.sort(store_.cells(), store_.size(), &pool_);
  grid_.cell_moments(store_.span(), system_.number_density, cells_, global_, &pool_);
  set_layer_majorants();
  sampled_step_ = static_cast<std::uint64_t>(-1);
}

bool Engine::any_rank(bool flag) const {
  std::uint64_t v = flag ? 1 : 0;
  ranks_->sum(&v, 1);
  return v != 0;
}

bool Engine::root_says(bool value) const {
  std::uint8_t v = value ? 1 : 0;
  ranks_->broadcast(&v, 1);
  return v != 0;
}

Engine::DecompositionStats Engine::decomposition_stats() const {
  DecompositionStats s;
  s.migrated = migrated_;
  s.steps = migration_steps_;
  s.rebalanced = rebalanced_;
  s.migration_seconds = migration_seconds_;
  s.gather_seconds = gather_seconds_;
  s.gathers = gathers_;
  if (ranks_) s.bounds = ranks_->bounds();
  return s;
}

}  // namespace gdsmc::host
