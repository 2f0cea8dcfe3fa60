// Headless pictures: an OSMesa context, the renderer and Dear ImGui's OpenGL3
// backend, reused across shots of the same session (tests take several).
#pragma once
#include <functional>
#include <memory>

#include "render/image.h"
#include "render/scene.h"
#include "render/ui.h"

namespace anisurf::render {

// One at a time per process: it owns the current Dear ImGui context.
class HeadlessRenderer {
 public:
  // Creates the context (throws GlError when OSMesa is missing).
  HeadlessRenderer(int width, int height);
  ~HeadlessRenderer();
  HeadlessRenderer(const HeadlessRenderer&) = delete;
  HeadlessRenderer& operator=(const HeadlessRenderer&) = delete;

  // Renders the scene (with the ImGui legend / panel as `ui` and
  // scene.display say) at width x height and returns the picture, rows
  // top-down. ImGui runs `ui_frames` frames so auto-sized windows settle; the
  // output depends only on the inputs (same pixels every time).
  Image render(Scene& scene, UiState& ui, int width, int height, int ui_frames = 3);

  // The same with the caller's ImGui windows: `ui(width, height)` is called
  // between ImGui::NewFrame() and ImGui::Render() of each frame.
  Image render(Scene& scene, const std::function<void(int, int)>& ui, int width, int height, int ui_frames = 3);

  // Runs the ImGui frames alone (no drawing) so that ui.legend_width is
  // known before the camera is fitted (Scene::fit_camera's reserve).
  void layout_ui(Scene& scene, UiState& ui, int width, int height, int ui_frames = 3);

  // "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe ..."
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anisurf::render
