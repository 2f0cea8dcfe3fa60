// Error type of the renderer (kept free of GL headers so that every source,
// including the one that includes <GL/osmesa.h>, can use it).
#pragma once
#include "core/error.h"

namespace anisurf::render {

// A GL failure the user can act on (no OSMesa, no context, shader error ...).
class GlError : public Error {
 public:
  using Error::Error;
};

}  // namespace anisurf::render
