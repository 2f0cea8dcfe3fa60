// What the editor shows, as data (the panels and the script change it, the
// view (editor_view.h) draws it): colour mode, glyphs, wireframe, the G1
// surface, pending camera requests, and the hover / brush state.
#pragma once
#include <optional>
#include <string>

#include "render/camera.h"

namespace anisurf::editor {

// Colour modes of `color MODE` and the panel.
// "deviation": the mesh to its G1 surface (drawn on the G1 surface);
// "distance": the mesh to the input surface T_G (drawn on the mesh);
// "fallback": how each vertex was placed: on the G1 surface, pulled to the
// input (where the G1 surface strayed beyond the input bound), off the
// surface (drawn on the mesh).
inline constexpr const char* kColorModes[] = {"size",      "aniso",    "length",   "quality", "ref",
                                              "deviation", "distance", "fallback", "none"};
bool is_color_mode(const std::string& mode);
// The modes that colour the mesh itself, which the G1 surface hides.
inline bool colors_mesh_only(const std::string& mode) { return mode == "distance" || mode == "fallback"; }

struct ViewState {
  std::string color = "size";
  bool glyphs = false;
  bool wireframe = true;
  bool features = true;
  bool show_touched = true;      // markers on the vertices the displayed pass touched
  int bezier = 0;                // > 0: the G1 surface sampled k x k is shown
  bool control_net = false;
  std::optional<render::NamedView> view_request;  // applied (with a fit) on the next frame
  bool fit_request = true;
  bool frame_selection = false;  // frame the worst element of the selection
  std::optional<int> frame_element;  // frame this triangle (a slot of the state shown) the same way
  // The brush is active in the window (left drag paints instead of orbiting).
  bool paint_tool = false;
};

}  // namespace anisurf::editor
