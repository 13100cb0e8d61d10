// The host's particle storage: structure of arrays, plus the extra attributes plugins declare.
#pragma once
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/particles.hpp>

namespace gdsmc::host {

class ParticleStore {
 public:
  // Allocate n particles and the declared attributes (names must be unique). Positions and the
  // layer index only where particles move (a slab); a homogeneous system keeps velocities and
  // identities alone (32 bytes per particle) and its span shows x, y, z and cell as nullptr.
  void allocate(std::size_t n, const std::vector<AttributeSpec>& attributes, bool positions = true) {
    n_ = n;
    for (auto* v : {&vx_, &vy_, &vz_}) v->assign(n, 0.0);
    for (auto* v : {&x_, &y_, &z_}) {
      v->clear();
      if (positions) v->assign(n, 0.0);
    }
    id_.resize(n);
    for (std::size_t i = 0; i < n; ++i) id_[i] = i;  // identities 0..N-1 in the initial order
    cell_.clear();
    if (positions) cell_.assign(n, 0u);
    specs_ = attributes;
    check_attributes(specs_);
    data_.assign(specs_.size(), {});
    pointers_.assign(specs_.size(), nullptr);
    for (std::size_t a = 0; a < specs_.size(); ++a) {
      data_[a].assign(n * static_cast<std::size_t>(specs_[a].components), 0.0);
      pointers_[a] = data_[a].data();
    }
    std::size_t components = 0;
    for (const auto& a : specs_) components += static_cast<std::size_t>(a.components);
    held_attributes_.reserve(components);  // permute() then never allocates
  }
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
    s.attribute_count = specs_.size();
    s.attribute_specs = specs_.data();
    s.attribute_data = pointers_.data();
    return s;
  }
  std::size_t size() const { return n_; }
  // Put the particles in the order `order` (a permutation: new position k holds old order[k]),
  // every array and attribute alike, in place by following the permutation's cycles (no scratch
  // array: the memory of a run is its particles), so pointers plugins took in bind() stay valid.
  // Identities travel with their particles. `order` is used as the record of what has moved and
  // is left as the identity permutation.
  void permute(std::uint32_t* order) {
    for (std::size_t start = 0; start < n_; ++start) {
      if (order[start] == start) continue;
      // The cycle start <- order[start] <- order[order[start]] ... : hold particle `start`, pull
      // each source into its destination, and drop the held particle into the last hole.
      hold(start);
      std::size_t to = start;
      for (;;) {
        const std::size_t from = order[to];
        order[to] = static_cast<std::uint32_t>(to);
        if (from == start) break;
        move(from, to);
        to = from;
      }
      put(to);
    }
  }
  // Exchange particles i and j in every array.
  void swap(std::size_t i, std::size_t j) {
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_})
      if (!v->empty()) std::swap((*v)[i], (*v)[j]);
    std::swap(id_[i], id_[j]);
    if (!cell_.empty()) std::swap(cell_[i], cell_[j]);
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c)
        std::swap(data_[a][c * n_ + i], data_[a][c * n_ + j]);
  }
  // The layer of every particle, written by the mover (the span shows it read-only to plugins).
  std::uint32_t* cells() { return cell_.data(); }
  // The identities, for the host only (the conformance harness restores snapshots in a permuted
  // order, identities travelling with their particles).
  std::uint64_t* ids() { return id_.data(); }
  const std::vector<AttributeSpec>& attribute_specs() const { return specs_; }

 private:
  std::size_t n_ = 0;
  std::vector<std::uint64_t> id_;
  std::vector<std::uint32_t> cell_;
  std::vector<double> x_, y_, z_, vx_, vy_, vz_;
  std::vector<AttributeSpec> specs_;
  std::vector<std::vector<double>> data_;
  std::vector<double*> pointers_;
  // One particle held aside while a permutation cycle is followed.
  double held_[6] = {0, 0, 0, 0, 0, 0};
  std::uint64_t held_id_ = 0;
  std::uint32_t held_cell_ = 0;
  std::vector<double> held_attributes_;
  void hold(std::size_t i) {
    std::vector<double>* arrays[6] = {&x_, &y_, &z_, &vx_, &vy_, &vz_};
    for (int k = 0; k < 6; ++k)
      if (!arrays[k]->empty()) held_[k] = (*arrays[k])[i];
    held_id_ = id_[i];
    if (!cell_.empty()) held_cell_ = cell_[i];
    held_attributes_.clear();
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c) held_attributes_.push_back(data_[a][c * n_ + i]);
  }
  void put(std::size_t i) {
    std::vector<double>* arrays[6] = {&x_, &y_, &z_, &vx_, &vy_, &vz_};
    for (int k = 0; k < 6; ++k)
      if (!arrays[k]->empty()) (*arrays[k])[i] = held_[k];
    id_[i] = held_id_;
    if (!cell_.empty()) cell_[i] = held_cell_;
    std::size_t h = 0;
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c) data_[a][c * n_ + i] = held_attributes_[h++];
  }
  void move(std::size_t from, std::size_t to) {
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_})
      if (!v->empty()) (*v)[to] = (*v)[from];
    id_[to] = id_[from];
    if (!cell_.empty()) cell_[to] = cell_[from];
    for (std::size_t a = 0; a < specs_.size(); ++a)
      for (int c = 0; c < specs_[a].components; ++c) data_[a][c * n_ + to] = data_[a][c * n_ + from];
  }
};

}  // namespace gdsmc::host
