// Transparent huge pages for the large arrays of a mesh.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace anisurf {

#if defined(__linux__)
namespace detail {
// madvise(advice) over the whole pages of `page` bytes inside [data, data + bytes).
inline void advise_whole_pages(const void* data, std::size_t bytes, std::uintptr_t page, int advice) {
  if (data == nullptr) return;
  const auto first = reinterpret_cast<std::uintptr_t>(data);
  const auto begin = (first + page - 1) & ~(page - 1);
  const auto end = (first + bytes) & ~(page - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}
}  // namespace detail
#endif

// Asks the kernel to back the whole 2 MB pages inside [data, data + bytes)
// with transparent huge pages (Linux madvise MADV_HUGEPAGE; in the usual
// "madvise" mode the kernel uses them only where asked). Filling a fresh
// array then takes one page fault per 2 MB instead of one per 4 KB (page
// faults are slow on virtual machines), and random accesses miss the TLB
// less.
// Arrays under min_bytes (16 MB unless given) are left alone; elsewhere a no-op.
inline void advise_huge_pages(const void* data, std::size_t bytes, std::size_t min_bytes = std::size_t{16} << 20) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (bytes >= min_bytes) detail::advise_whole_pages(data, bytes, kHuge, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
  (void)min_bytes;
#endif
}

// Makes the whole pages inside [data, data + bytes) resident and writable
// at once (Linux 5.14+ madvise MADV_POPULATE_WRITE: one call instead of a
// page fault per 4 KB page as a fresh array is first written). For memory
// about to be written: the pages count as used from then on, written or not
// (the program's operator new populates only blocks under 1 MB for that).
// Elsewhere, and on older kernels, a no-op.
inline void populate_pages(const void* data, std::size_t bytes) {
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
  constexpr int MADV_POPULATE_WRITE = 23;  // Linux's value (older headers lack it)
#endif
  detail::advise_whole_pages(data, bytes, 4096, MADV_POPULATE_WRITE);
#else
  (void)data;
  (void)bytes;
#endif
}

// Gives the whole pages inside [data, data + bytes) back to the system
// (Linux madvise MADV_DONTNEED; they read as zeros if touched again): for
// the part of a large array already consumed, while the rest is read.
// Elsewhere a no-op.
inline void release_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  detail::advise_whole_pages(data, bytes, 4096, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

// Reserves room for n elements in v, huge pages asked for.
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace anisurf
