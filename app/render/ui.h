// Dear ImGui on top of the rendered scene, the same in the window and in
// headless shots: the control panel (display options, quantity, camera) and
// the legend (colour bar of the active quantity, key of the feature lines).
#pragma once
#include <string>

#include "render/scene.h"

namespace anisurf::render {

struct UiState {
  bool show_panel = true;    // the control panel (the legend follows display.legend)
  std::string title;         // panel title line, e.g. the file name
  std::string info;          // one line under it, e.g. "37375 vertices, 74754 triangles"
  float fps = 0.0f;          // shown when > 0 (the window)
  bool fit_requested = false;  // set by the panel's "fit" button / view changes
  float legend_width = 0.0f;   // pixels with margins, measured by draw_ui (0: no legend)
  float panel_width = 0.0f;    // pixels from the left edge to the panel's right side (0: none)
  float legend_height = 0.0f;  // pixels of the legend with its bottom margin (0: no legend)
  float bottom_margin = 0.0f;  // pixels kept free at the bottom (a status bar): the legend sits above them

  // Fractions of a `width`-pixel view covered by the panel (left) and the
  // legend (right), for Scene::fit_camera.
  float left_reserve(int width) const;
  float right_reserve(int width) const;
};

// Creates the ImGui context for one backend (no imgui.ini, light style, the
// DejaVu Sans font when installed else ImGui's built-in one). Destroyed with
// the object. The platform / renderer backends are set up by the caller.
class ImGuiSession {
 public:
  ImGuiSession();
  ~ImGuiSession();
  ImGuiSession(const ImGuiSession&) = delete;
  ImGuiSession& operator=(const ImGuiSession&) = delete;
};

// Builds the ImGui windows for this frame (between ImGui::NewFrame() and
// ImGui::Render()). `width`, `height`: the framebuffer in pixels.
void draw_ui(Scene& scene, UiState& ui, int width, int height);

// Values at which the legend of a range puts ticks (nice numbers; on a log
// scale, powers of ten and their 2 and 5 multiples), always including both
// ends. Exposed for tests.
std::vector<float> legend_ticks(float lo, float hi, bool log_scale);

}  // namespace anisurf::render
