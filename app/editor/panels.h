// The editor's Dear ImGui panels (the UI layer): File, Metric, Brush,
// Adaptation, Analysis, G1 surface, Display, the hover tooltip and the quit
// confirmation. They read the session and call its actions; they own only
// UI state (text fields, recent files, messages).
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "editor/editor_view.h"
#include "editor/session.h"
#include "editor/view_state.h"
#include "render/scene.h"
#include "render/ui.h"

namespace anisurf::editor {

struct PanelState {
  std::string open_path, open_sol, save_mesh = "out/adapted.mesh", save_sol = "out/adapted.sol",
                                    shot_path = "out/editor.png";
  std::vector<std::string> recent;  // most recent first
  std::string message;              // last action's result or error
  bool message_is_error = false;
  std::optional<HoverInfo> hover;   // set by the window each frame
  float fps = 0;
  bool quit_requested = false;      // the window asked to close with unsaved work
  bool quit_confirmed = false;      // the user confirmed: close
  // Metric panel: the settings being edited (applied on release / Enter).
  MetricSettings edit;
  bool edit_valid = false;
  double preview_vertices = 0;
  std::string preview_error;
  std::function<void(const std::string&)> screenshot;  // writes a PNG of the window
};

// Recent files: path added in front (kept unique, at most 8).
void remember_recent(PanelState& p, const std::string& path);

// Builds this frame's panels (between ImGui::NewFrame and ImGui::Render).
void draw_panels(EditorSession& session, ViewState& view, PanelState& panels, render::Scene& scene,
                 render::UiState& ui, int width, int height);

}  // namespace anisurf::editor
