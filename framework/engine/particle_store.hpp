// The host's particle storage: structure of arrays, plus the extra attributes plugins declare.
#pragma once
#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdsmc/particles.hpp>

namespace gdsmc::host {

class ParticleStore {
 public:
  // Allocate n particles and the declared attributes (names must be unique).
  void allocate(std::size_t n, const std::vector<AttributeSpec>& attributes) {
    n_ = n;
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_}) v->assign(n, 0.0);
    id_.resize(n);
    for (std::size_t i = 0; i < n; ++i) id_[i] = i;  // identities 0..N-1 in the initial order
    cell_.assign(n, 0u);
    specs_ = attributes;
    check_attributes(specs_);
    data_.assign(specs_.size(), {});
    pointers_.assign(specs_.size(), nullptr);
    for (std::size_t a = 0; a < specs_.size(); ++a) {
      data_[a].assign(n * static_cast<std::size_t>(specs_[a].components), 0.0);
      pointers_[a] = data_[a].data();
    }
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
    s.cell = cell_.data();
    s.x = x_.data(); s.y = y_.data(); s.z = z_.data();
    s.vx = vx_.data(); s.vy = vy_.data(); s.vz = vz_.data();
    s.attribute_count = specs_.size();
    s.attribute_specs = specs_.data();
    s.attribute_data = pointers_.data();
    return s;
  }
  std::size_t size() const { return n_; }
  // Put the particles in the order `order` (a permutation: new position k holds old order[k]),
  // every array and attribute alike, through a scratch buffer and back into the same storage, so
  // pointers plugins took in bind() stay valid. Identities travel with their particles.
  void permute(const std::uint32_t* order) {
    auto apply = [&](auto& v, std::size_t components) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      std::vector<T>& scratch = scratch_for<T>();
      scratch.resize(n_);
      for (std::size_t c = 0; c < components; ++c) {
        T* data = v.data() + c * n_;
        for (std::size_t k = 0; k < n_; ++k) scratch[k] = data[order[k]];
        std::copy(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(n_), data);
      }
    };
    for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_}) apply(*v, 1);
    apply(id_, 1);
    apply(cell_, 1);
    for (std::size_t a = 0; a < specs_.size(); ++a) apply(data_[a], static_cast<std::size_t>(specs_[a].components));
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
  std::vector<double> scratch_d_;
  std::vector<std::uint64_t> scratch_u64_;
  std::vector<std::uint32_t> scratch_u32_;
  template <class T>
  std::vector<T>& scratch_for() {
    if constexpr (std::is_same_v<T, double>) return scratch_d_;
    else if constexpr (std::is_same_v<T, std::uint64_t>) return scratch_u64_;
    else return scratch_u32_;
  }
};

}  // namespace gdsmc::host
