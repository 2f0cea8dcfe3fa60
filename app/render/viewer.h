// The interactive window (GLFW + OpenGL 3.3 core + Dear ImGui): orbit with
// the left mouse button, pan with the right one (or shift + left), zoom with
// the wheel; keys for the views and display toggles (see viewer_keys()).
#pragma once
#include <string>

#include "render/scene.h"
#include "render/ui.h"

namespace anisurf::render {

struct ViewerOptions {
  int width = 1280, height = 800;
  std::string title = "anisurf";
  double max_fps = 60.0;   // frame cap (Xvfb ignores the swap interval)
  // > 0: benchmark instead of interacting: orbit the camera 360 degrees in
  // this many frames without the cap, print the frame rate, close.
  int bench_orbit_frames = 0;
  // The benchmark's frames drawn as still ones (full resolution, the
  // multisampling of the options, no proxy) instead of as a moving camera.
  bool bench_full_detail = false;
};

// Opens the window and runs until it is closed (or the benchmark ends).
// Throws GlError when no window can be opened (no display ...).
void run_viewer(Scene& scene, UiState& ui, const ViewerOptions& options);

// The keyboard help shown by `anisurf view --help`.
const char* viewer_keys();

}  // namespace anisurf::render
