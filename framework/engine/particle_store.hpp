// The host's particle storage: structure of arrays, plus the extra attributes plugins declare.
#pragma once
#include <algorithm>
#include <cstring>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <gdsmc/particles.hpp>
#include <gdsmc/state.hpp>

#include "engine/decomposition.hpp"
#include "engine/huge_page_allocator.hpp"
#include "engine/work_pool.hpp"

namespace gdsmc::host {

// An array of one particle quantity (huge pages: see huge_page_allocator.hpp).
template <class T>
using ParticleArray = std::vector<T, HugePageAllocator<T>>;

class ParticleStore {
 public:
  // Allocate n particles and the declared attributes (names must be unique). Positions and the
  // layer index only where particles move (a slab); a homogeneous system keeps velocities and
  // identities alone (28 bytes per particle) and its span shows x, y, z and cell as nullptr.
  void allocate(std::size_t n, const std::vector<AttributeSpec>& attributes, bool positions = true) {
    n_ = n;
    for (auto* v : {&vx_, &vy_, &vz_}) v->assign(n, 0.0);
    for (auto* v : {&x_, &y_, &z_}) {
      v->clear();
      if (positions) v->assign(n, 0.0);
    }
    id_.resize(n);
    for (std::size_t i = 0; i < n; ++i) id_[i] = static_cast<std::uint32_t>(i);  // identities 0..N-1 in the initial order
    cell_.clear();
    if (positions) cell_.assign(n, 0u);
    species_.clear();
    mixture_ = false;
    specs_ = attributes;
    check_attributes(specs_);
    data_.assign(specs_.size(), {});
    pointers_.assign(specs_.size(), nullptr);
    for (std::size_t a = 0; a < specs_.size(); ++a) {
      data_[a].assign(n * static_cast<std::size_t>(specs_[a].components), 0.0);
      pointers_[a] = data_[a].data();
    }
  }
  // A mixture: particles with identity [0, counts[0]) are species 0, the next counts[1] species 1,
  // ... (counts sum to the particle count); called right after allocate(), in identity order.
  void set_species(const std::vector<std::size_t>& counts) {
    species_.assign(n_, 0u);
    mixture_ = true;
    std::size_t i = 0;
    for (std::size_t s = 0; s < counts.size(); ++s)
      for (std::size_t k = 0; k < counts[s] && i < n_; ++k) species_[i++] = static_cast<std::uint32_t>(s);
  }
  bool has_species() const { return mixture_; }
  // Throws unless every attribute has components and the names are unique.
  static void check_attributes(const std::vector<AttributeSpec>& specs) {
    for (std::size_t a = 0; a < specs.size(); ++a) {
      if (specs[a].components < 1) throw std::runtime_error("attribute '" + specs[a].name + "' declares no components");
      for (std::size_t b = 0; b < a; ++b)
        if (specs[a].name == specs[b].name)
          throw std::runtime_error("two plugins declare the per-particle attribute '" + specs[a].name + "'");
    }
  }
  ParticleSpan span() {
    ParticleSpan s;
    s.count = n_;
    s.id = id_.data();
    s.cell = cell_.empty() ? nullptr : cell_.data();
    s.x = x_.empty() ? nullptr : x_.data();
    s.y = y_.empty() ? nullptr : y_.data();
    s.z = z_.empty() ? nullptr : z_.data();
    s.vx = vx_.data(); s.vy = vy_.data(); s.vz = vz_.data();
    s.species = !mixture_ ? nullptr : species_.data();
    s.attribute_count = specs_.size();
    s.attribute_specs = specs_.data();
    s.attribute_data = pointers_.data();
    return s;
  }
  std::size_t size() const { return n_; }
  // Put the particles in the order `order` (a permutation: new position k holds old order[k]),
  // every array and attribute alike, in place, so pointers plugins took in bind() stay valid.
  // Identities travel with their particles. The layer index cell[] does not: it serves as scratch
  // and the caller writes it afresh (CellGrid::set_layer_order: after a reordering by layer, the
  // layer of every position is known). A slab store only. Scratch: 4 bytes per particle of our
  // own (allocated at the first reordering) plus cell[]'s 4, so an 8-byte value is gathered as its
  // two halves in one pass (low into the scratch, high into cell[]) and rebuilt in a second, and a
  // 4-byte array is gathered into the scratch and copied back. Every pass is a gather in blocks
  // on the pool's threads (independent reads, which the memory system overlaps). Following the
  // permutation's cycles in place instead (no scratch) costs 158 ms per reordering of 1e6 slab
  // particles after 15 steps of flight, against a few ms here: each step of a cycle waits for the
  // previous one.
  void permute(const std::uint32_t* order, WorkPool* pool = nullptr) {
    if (cell_.size() != n_) throw std::logic_error("ParticleStore::permute: a slab store (with cell[]) only");
    scratch_.resize(n_);
    constexpr std::size_t kBlock = 1u << 16;
    const std::size_t blocks = (n_ + kBlock - 1) / kBlock;
    std::uint32_t* low = scratch_.data();
    std::uint32_t* high = cell_.data();
    auto gather = [&](auto&& pass) {
      for_pieces(pool, blocks, [&](std::size_t b) {
        for (std::size_t k = b * kBlock, e = std::min(n_, k + kBlock); k < e; ++k) pass(k);
      });
    };
    auto apply32 = [&](std::uint32_t* data) {
      gather([&](std::size_t k) { low[k] = data[order[k]]; });
      gather([&](std::size_t k) { data[k] = low[k]; });
    };
    auto apply64 = [&](double* values) {
      gather([&](std::size_t k) {
        std::uint64_t w;
        std::memcpy(&w, values + order[k], 8);
        low[k] = static_cast<std::uint32_t>(w);
        high[k] = static_cast<std::uint32_t>(w >> 32);
      });
      gather([&](std::size_t k) {
        const std::uint64_t w = static_cast<std::uint64_t>(high[k]) << 32 | low[k];
        std::memcpy(values + k, &w, 8);
      });
    };
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_})
      if (!v->empty()) apply64(v->data());
    apply32(id_.data());
    if (mixture_) apply32(species_.data());
    if (!key_.empty()) apply32(key_.data());
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c) apply64(data_[a].data() + c * n_);
  }
  // Exchange particles i and j in every array.
  void swap(std::size_t i, std::size_t j) {
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_})
      if (!v->empty()) std::swap((*v)[i], (*v)[j]);
    std::swap(id_[i], id_[j]);
    if (mixture_) std::swap(species_[i], species_[j]);
    if (!key_.empty()) std::swap(key_[i], key_[j]);
    if (!cell_.empty()) std::swap(cell_[i], cell_[j]);
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c)
        std::swap(data_[a][c * n_ + i], data_[a][c * n_ + j]);
  }
  // Checkpoints: every array of the allocated store (identities, layers, positions where they
  // exist, velocities, attributes by name), read back into a store allocated alike.
  void save(StateWriter& out) const {
    const auto write = [&](const std::string& name, const auto& v) { out.write(name, v.data(), v.size()); };
    write("particles.id", id_);
    write("particles.cell", cell_);
    write("particles.x", x_);
    write("particles.y", y_);
    write("particles.z", z_);
    write("particles.vx", vx_);
    write("particles.vy", vy_);
    write("particles.vz", vz_);
    for (std::size_t a = 0; a < specs_.size(); ++a) write("particles.attribute." + specs_[a].name, data_[a]);
    if (mixture_) write("particles.species", species_);  // a mixture's only
  }
  void load(StateReader& in) {
    in.read("particles.id", id_.data(), id_.size());
    in.read("particles.cell", cell_.data(), cell_.size());
    for (auto [name, v] : {std::pair{"particles.x", &x_}, std::pair{"particles.y", &y_}, std::pair{"particles.z", &z_},
                           std::pair{"particles.vx", &vx_}, std::pair{"particles.vy", &vy_}, std::pair{"particles.vz", &vz_}})
      in.read(name, v->data(), v->size());
    for (std::size_t a = 0; a < specs_.size(); ++a)
      in.read("particles.attribute." + specs_[a].name, data_[a].data(), data_[a].size());
    if (mixture_) in.read("particles.species", species_.data(), species_.size());
  }
  // The layer of every particle, written by the mover (the span shows it read-only to plugins).
  std::uint32_t* cells() { return cell_.data(); }
  // The identities, for the host only (the conformance harness restores snapshots in a permuted
  // order, identities travelling with their particles).
  std::uint32_t* ids() { return id_.data(); }
  const std::vector<AttributeSpec>& attribute_specs() const { return specs_; }

  // A decomposed slab (engine/decomposition.hpp): every particle's order key, its index in the
  // single-process run's storage; keys() is nullptr until enable_keys() numbers them 0, 1, ...
  // The key travels with its particle (permute, swap, the migrants below); no plugin sees it.
  void enable_keys() {
    key_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) key_[i] = static_cast<std::uint32_t>(i);
  }
  std::uint32_t* keys() { return key_.empty() ? nullptr : key_.data(); }
  // Particle i as a migrant (a store with keys and without attributes), and back into place i.
  Migrant migrant(std::size_t i) const {
    return {x_[i], y_[i], z_[i], vx_[i], vy_[i], vz_[i], id_[i], !mixture_ ? 0u : species_[i], cell_[i], key_[i]};
  }
  void set(std::size_t i, const Migrant& m) {
    x_[i] = m.x, y_[i] = m.y, z_[i] = m.z, vx_[i] = m.vx, vy_[i] = m.vy, vz_[i] = m.vz;
    id_[i] = m.id, cell_[i] = m.cell, key_[i] = m.key;
    if (mixture_) species_[i] = m.species;
  }
  // Removes every particle for which leaves(i) is true, handing it to send(migrant) first; the
  // last particles fill the places left (so the order of the others is not kept: a decomposed
  // slab puts its layers' member lists in key order afterwards). Returns how many left.
  template <class Leaves, class Send>
  std::size_t remove_if(Leaves&& leaves, Send&& send) {
    std::size_t n = n_;
    for (std::size_t i = 0; i < n;) {
      if (!leaves(i)) {
        ++i;
        continue;
      }
      send(migrant(i));
      if (i != --n) move(n, i);  // the last into the place; place i is looked at again
    }
    const std::size_t left = n_ - n;
    resize(n);
    return left;
  }
  // Appends `in` after the last particle. Returns whether the arrays moved in memory (their
  // pointers changed).
  bool append(const std::vector<Migrant>& in) {
    if (in.empty()) return false;
    const double* before = vx_.data();
    const std::size_t n = n_;
    resize(n_ + in.size());
    for (std::size_t k = 0; k < in.size(); ++k) set(n + k, in[k]);
    return vx_.data() != before;
  }
  // n particles: the first min(n, size()) kept, the others zero (a store without attributes).
  void resize(std::size_t n) {
    if (!specs_.empty()) throw std::logic_error("ParticleStore::resize: a store with plugin attributes cannot be resized");
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_})
      if (!v->empty() || n_ == 0) v->resize(n);
    id_.resize(n);
    cell_.resize(n);
    if (mixture_) species_.resize(n);
    if (!key_.empty() || n_ == 0) key_.resize(n);
    n_ = n;
  }
  // Every column of a store with keys, resized to n (a rank's store before its particles arrive).
  void reserve_like(std::size_t n, bool species) {
    n_ = 0;
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_}) v->clear();
    id_.clear(), cell_.clear(), key_.clear(), species_.clear();
    mixture_ = species;
    resize(n);
  }

 private:
  // Particle `from` into place `to` (every column but the attributes).
  void move(std::size_t from, std::size_t to) {
    x_[to] = x_[from], y_[to] = y_[from], z_[to] = z_[from];
    vx_[to] = vx_[from], vy_[to] = vy_[from], vz_[to] = vz_[from];
    id_[to] = id_[from], cell_[to] = cell_[from], key_[to] = key_[from];
    if (mixture_) species_[to] = species_[from];
  }
  std::size_t n_ = 0;
  ParticleArray<std::uint32_t> id_;
  ParticleArray<std::uint32_t> cell_;
  ParticleArray<std::uint32_t> species_;  // a mixture's species per particle; empty with one species
  bool mixture_ = false;                  // species_ is kept (set_species): a store of 0 particles may hold none
  ParticleArray<double> x_, y_, z_, vx_, vy_, vz_;
  std::vector<AttributeSpec> specs_;
  std::vector<ParticleArray<double>> data_;
  std::vector<double*> pointers_;
  ParticleArray<std::uint32_t> key_;      // a decomposed slab's order keys; empty otherwise
  ParticleArray<std::uint32_t> scratch_;  // permute(): 4 bytes per particle, allocated at the first reordering (a slab only)
};

}  // namespace gdsmc::host
