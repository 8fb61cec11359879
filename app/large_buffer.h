// predvs app — room for a long column of numbers, backed by huge pages where the kernel offers them.
//
// `predvs predict` on a 2-million-row track fills about 30 columns of 16 MB each (the track's, the
// predictions', the references'). With the kernel's transparent huge pages in `madvise` mode (the
// Debian default), each is faulted in 4 KB at a time: 4,000 page faults and as many TLB entries per
// column. reserveLarge() reserves the column and, before anything touches it, asks the kernel for
// 2 MB pages on the whole 2 MB-aligned part of the block (madvise MADV_HUGEPAGE). Only the speed
// depends on it (docs/PERFORMANCE.md "`predvs predict` throughput"); where the advice is not
// available (not Linux, THP off, a block below kLargeBufferMinBytes) it is a plain reserve().
#pragma once

#include <cstddef>
#include <vector>

namespace predvs {

/// Blocks smaller than this are reserved without the advice (a huge page would be mostly empty).
constexpr size_t kLargeBufferMinBytes = size_t{4} << 20;

/// v.reserve(n), with the new block's whole 2 MB pages advised as huge pages (file comment). The
/// advice is given only when the reserve allocates, right after it (the block then holds only the
/// elements v had, copied in); n <= v.capacity() changes nothing.
void reserveLarge(std::vector<double>& v, size_t n);

}  // namespace predvs
