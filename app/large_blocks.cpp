// The program's global operator new and delete: malloc and free, with the
// pages of fresh blocks faulted in cheaply. glibc maps each block of
// kMappedBlock and more on its own and unmaps it when freed, so every pass
// that allocates a new array faults its pages in again, one fault per 4 KB
// page: slow on virtual machines, where a fault costs microseconds. Blocks
// up to kPopulatedBlock are made resident in one call (MADV_POPULATE_WRITE);
// blocks of kLargeBlock and more are asked to be backed by transparent huge
// pages, one fault per 2 MB (core/huge_pages.h). The engine library and the
// tests keep the standard functions.
#include "large_blocks.h"

#include <cstdlib>
#include <new>

#include "core/huge_pages.h"

namespace {

using anisurf::app::kLargeBlock;
using anisurf::app::kMappedBlock;
using anisurf::app::kPopulatedBlock;

void* allocate(std::size_t n) {
  for (;;) {
    if (void* p = std::malloc(n == 0 ? 1 : n)) {
      if (n >= kLargeBlock) {
        anisurf::advise_huge_pages(p, n, kLargeBlock);
      } else if (n >= kMappedBlock && n < kPopulatedBlock) {
        anisurf::populate_pages(p, n);
      }
      return p;
    }
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void* allocate_nothrow(std::size_t n) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
