// Particle arrays on transparent huge pages (2 MiB) where the kernel grants them on request
// (/sys/kernel/mm/transparent_hugepage/enabled = madvise, Debian's default, or always). A
// collision candidate reads two particles anywhere in the velocities (a homogeneous system's
// sub-populations span all of storage): with 4 KiB pages each of its six cache-line misses
// also misses the TLB once the arrays outgrow its reach (24 MB at N = 1e6), and the page walk
// adds its own memory reads. Allocations below one huge page use operator new as before. The
// pages are a hint: where the kernel refuses them the arrays work alike, only slower.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace gdsmc::host {

inline constexpr std::size_t kHugePage = std::size_t{2} << 20;

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();  // n sizeof(T) would wrap
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) return static_cast<T*>(::operator new(bytes));
    void* p = nullptr;
    if (posix_memalign(&p, kHugePage, bytes) != 0) throw std::bad_alloc();
    // The whole huge pages only: the array's last partial one stays on 4 KiB pages, so that the
    // resident memory is the array's size (a huge page is resident whole once touched). A refusal
    // (EINVAL: THP off) leaves 4 KiB pages everywhere.
    madvise(p, bytes / kHugePage * kHugePage, MADV_HUGEPAGE);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugePage) ::operator delete(p);
    else std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

}  // namespace gdsmc::host
