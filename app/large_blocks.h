// The allocation policy of the program (large_blocks.cpp, main.cpp).
#pragma once
#include <cstddef>

namespace anisurf::app {

// Blocks from this size up are mapped by glibc on their own and given back
// to the system when freed (main.cpp sets M_MMAP_THRESHOLD to it).
inline constexpr std::size_t kMappedBlock = std::size_t{256} << 10;
// Mapped blocks below this size have their pages made resident at once
// (one call instead of a page fault per 4 KB); larger ones often hold room
// reserved for growth that is never written (a region's mesh arrays, a
// vector's doubled capacity), which must stay out of the resident memory.
inline constexpr std::size_t kPopulatedBlock = std::size_t{1} << 20;
// Blocks from this size up are asked to be backed by 2 MB huge pages.
inline constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

}  // namespace anisurf::app
