// Giving freed heap memory back to the system.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace anisurf {

// Returns the whole free pages of every malloc arena to the system (glibc's
// malloc_trim: the pages inside the arenas too, not only their tops). A
// region's remesher frees its working arrays when it ends, and the arrays
// its mesh shrank from; without this the thread's arena keeps those pages
// resident while the next regions grow. Elsewhere a no-op.
inline void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace anisurf
