// The program's global operator new and delete: malloc and free, with the
// large blocks (4 MB and more: the mesh's arrays, the regions' copies, the
// search structures) asked to be backed by transparent huge pages
// (core/huge_pages.h). glibc maps such blocks on their own and unmaps them
// when freed (main.cpp sets the threshold), so every pass that allocates a
// new array faults its pages in again: one fault per 4 KB page, slow on
// virtual machines, where a fault costs microseconds; one per 2 MB with huge
// pages. The memory is the same (a block's partial huge pages at its ends
// stay small pages). The engine library and the tests keep the standard
// functions.
#include <cstdlib>
#include <new>

#include "core/huge_pages.h"

namespace {

constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

void* allocate(std::size_t n) {
  for (;;) {
    if (void* p = std::malloc(n == 0 ? 1 : n)) {
      if (n >= kLargeBlock) anisurf::advise_huge_pages(p, n, kLargeBlock);
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
