// predvs app — memory of its own cache lines, for state that one thread writes row after row while
// the other thread runs predictors: a cache line shared with a neighbour's state (false sharing)
// passes from core to core on every write (docs/PERFORMANCE.md, "Thirteenth pass: the plot's state
// on lines of its own").
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace predvs {

inline constexpr std::size_t kCacheLineBytes = 64;

/// std::allocator's interface; each allocation starts on a cache line and takes whole lines.
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = (n * sizeof(T) + kCacheLineBytes - 1) / kCacheLineBytes * kCacheLineBytes;
    return static_cast<T*>(::operator new(bytes, std::align_val_t(kCacheLineBytes)));
  }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kCacheLineBytes)); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const CacheLineAllocator<U>&) const noexcept { return false; }
};

template <class T>
using CacheLineVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace predvs
