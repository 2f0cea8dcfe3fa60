// Headless OpenGL: an OSMesa (Mesa llvmpipe, software) context rendering into
// a buffer in memory. Needs no display and no GPU. Creating one makes it
// current and loads the GL functions (render/gl.h) from OSMesaGetProcAddress.
#pragma once
#include <memory>
#include <string>

namespace anisurf::render {

class OffscreenContext {
 public:
  // Throws GlError if libOSMesa cannot be loaded or no 3.3 core context can
  // be created (the message says which package to install).
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  // Makes the context current on a (re)allocated w x h buffer.
  void resize(int width, int height);
  int width() const;
  int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anisurf::render
