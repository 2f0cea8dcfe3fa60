// Draws a Scene with OpenGL 3.3 core into the current context: a
// multisampled offscreen target resolved into framebuffer 0. GPU copies of
// the structures are made on first use and refreshed when a structure's
// version changes. Needs a current context with the GL functions loaded.
#pragma once
#include <memory>

#include "render/scene.h"

namespace anisurf::render {

class Renderer {
 public:
  Renderer();   // compiles the shaders; throws GlError
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the scene into the offscreen target (width x height pixels) with
  // `samples` multisamples (0: scene.display.msaa_samples).
  void draw(const Scene& scene, int width, int height, int samples = 0);
  // Copies the last drawn picture into framebuffer 0 and leaves it bound
  // with blending and depth test off (ready for the ImGui pass).
  void present();
  // draw() then present().
  void render(const Scene& scene, int width, int height, int samples = 0) {
    draw(scene, width, height, samples);
    present();
  }

  // Drops the GPU copies (e.g. after removing structures).
  void clear_cache();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anisurf::render
