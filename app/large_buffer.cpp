// predvs app — reserveLarge() (large_buffer.h).
#include "large_buffer.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace predvs {

void reserveLarge(std::vector<double>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const size_t bytes = n * sizeof(double);
  if (bytes < kLargeBufferMinBytes) return;
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<uintptr_t>(v.data());
  const uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  // Advice only: a kernel without THP answers EINVAL, and the block works the same.
  if (last > first) (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#endif
}

}  // namespace predvs
