// Draws a Scene with OpenGL 3.3 core into the current context: a
// multisampled offscreen target resolved into framebuffer 0. GPU copies of
// the structures are made on first use and refreshed when a structure's
// version changes. A frame whose inputs equal the previous frame's keeps the
// previous picture. While the camera moves, the picture is drawn at half the
// resolution (one sample per pixel, scaled up by present()) and surfaces
// larger than kProxyMinTriangles are drawn through a decimated proxy
// (render/lod.h) built in the background. A still picture can be drawn in
// slices over several frames (DrawOptions::triangle_budget). Needs a current
// context with the GL functions loaded.
#pragma once
#include <cstddef>
#include <memory>

#include "render/scene.h"

namespace anisurf::render {

// How one frame is drawn.
struct DrawOptions {
  int samples = 0;             // multisamples (0: scene.display.msaa_samples); 1 while the camera moves
  bool camera_moving = false;  // level of detail: half resolution, proxies of large surfaces
  // > 0: a still picture draws at most this many triangles a frame; a larger
  // scene is drawn over several frames, the last complete picture shown
  // meanwhile. 0: the whole picture in one frame.
  std::size_t triangle_budget = 0;
};

// A budget for the window's frames on llvmpipe (2 cores shared with the
// adaptation, 1280x800, 4 samples: a slice of 15k falcon triangles takes
// 40-75 ms). With a budget, the GPU copies of new data are also prepared in
// the background.
inline constexpr std::size_t kInteractiveTriangleBudget = 15000;

// What the last draw() drew (the orbit benchmark prints it).
struct FrameInfo {
  bool redrawn = false;        // false: the inputs were those of the frame before, its picture was kept
  int width = 0, height = 0;   // of the drawn picture (half the output's while the camera moves)
  int samples = 0;
  std::size_t triangles = 0;   // surface triangles drawn
  int proxies = 0;             // surfaces drawn through their proxy
  bool complete = true;        // false: a still picture is being drawn over several frames
};

// Surfaces with more triangles are drawn through a proxy of at most
// kProxyMaxTriangles triangles while the camera moves (once it is built).
inline constexpr std::size_t kProxyMinTriangles = 50000;
inline constexpr std::size_t kProxyMaxTriangles = 30000;

class Renderer {
 public:
  Renderer();   // compiles the shaders; throws GlError
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the scene into the offscreen target (width x height pixels) with
  // `samples` multisamples (0: scene.display.msaa_samples).
  void draw(const Scene& scene, int width, int height, int samples = 0) {
    draw(scene, width, height, DrawOptions{samples, false});
  }
  void draw(const Scene& scene, int width, int height, const DrawOptions& options);
  // Copies the last drawn picture into framebuffer 0 (scaled up to the
  // requested size when drawn at a lower resolution) and leaves it bound
  // with blending and depth test off (ready for the ImGui pass).
  void present();
  // draw() then present().
  void render(const Scene& scene, int width, int height, int samples = 0) {
    render(scene, width, height, DrawOptions{samples, false});
  }
  void render(const Scene& scene, int width, int height, const DrawOptions& options) {
    draw(scene, width, height, options);
    present();
  }
  const FrameInfo& last_frame() const;
  // A proxy is being built in the background.
  bool proxies_pending() const;

  // Drops the GPU copies (e.g. after removing structures).
  void clear_cache();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anisurf::render
