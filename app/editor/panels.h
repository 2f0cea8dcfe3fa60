// The editor's Dear ImGui panels (the UI layer): File, Metric, Brush,
// Adaptation, Analysis, G1 surface, Display, the hover tooltip, the pinned
// element, the Keys window, the status bar at the bottom (the adaptation's
// state, the last message, timings), the outlines of the selected, hovered
// and pinned triangles, and the dialogs that protect work (unsaved changes,
// overwrite, save as, the autosave offered at start). They read the session and call its actions; they own only
// UI state (text fields, recent files, messages).
#pragma once
#include <glm/glm.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/autosave.h"
#include "editor/editor_view.h"
#include "editor/session.h"
#include "editor/view_state.h"
#include "render/scene.h"
#include "render/ui.h"

namespace anisurf::editor {

// The Metric panel's fields: the settings being typed. They follow the
// session's settings when those change (undo, a script, a commit) and are
// kept otherwise, so that a value typed into a field is committed when the
// field is left by Enter, Tab or a click elsewhere alike.
struct SettingsDraft {
  MetricSettings edit;  // what the fields show
  MetricSettings base;  // the session's settings the draft started from
  bool valid = false;
  // Takes the session's settings when they are not `base` any more (or on
  // the first call); returns true when it did (the draft was replaced).
  bool follow(const MetricSettings& session);
  // The fields differ from the session's settings.
  bool pending() const { return valid && !(edit == base); }
};

struct PanelState {
  // Open: the paths typed; save: where Save writes (beside the opened file,
  // with its name, unless the user changed them; save_sol empty: the mesh
  // only); the screenshot.
  std::string open_path, open_sol, save_mesh, save_sol, shot_path = "out/editor.png";
  int opened_seen = 0;  // session.opened() the save paths were set for
  std::vector<std::string> recent;  // most recent first
  std::string message;              // last action's result or error
  bool message_is_error = false;
  std::optional<HoverInfo> hover;   // set by the window each frame
  // A click without drag (pixels of the view, top-left origin): the next
  // frame pins the element under it, or unpins on empty space. Set by the
  // window and by a script's `click X Y`.
  std::optional<glm::vec2> click;
  // The pinned element and the state it belongs to (shown in its window
  // until closed, Esc, or another click).
  struct Pinned {
    HoverInfo element;
    std::shared_ptr<const Snapshot> of;
  };
  std::optional<Pinned> pinned;
  bool show_keys = false;  // the Keys window (F1, ?)
  float fps = 0;
  // Where the windows were drawn in the last frame (pixels, top-left
  // origin): the layout follows the view's size each frame.
  struct Rect {
    float x = 0, y = 0, w = 0, h = 0;
    // The rect lies within a width x height view.
    bool inside(int width, int height) const {
      return x >= 0 && y >= 0 && x + w <= static_cast<float>(width) && y + h <= static_cast<float>(height);
    }
  };
  Rect main_rect, analysis_rect, status_rect;
  bool quit_confirmed = false;      // close the window (nothing unsaved, or the user said so)
  // Actions that would drop unsaved work wait for the user's answer in the
  // "Unsaved changes" dialog (Save / Discard / Cancel).
  enum class Action { None, Open, Restore, Quit };
  struct Pending {
    Action action = Action::None;
    std::string mesh, sol;  // Open: the files; Restore: mesh = the autosave
  };
  Pending pending;
  bool ask_unsaved = false;        // open the dialog on the next frame
  // A save onto files that exist (and that this session did not write)
  // waits for the "Overwrite?" dialog; continue_pending: the pending action
  // follows a successful save.
  std::vector<std::string> overwrite;
  bool ask_overwrite = false;
  bool continue_pending = false;
  bool ask_save_as = false;
  std::string save_as_mesh, save_as_sol;
  // Autosave: this launch's file ("" before its first write), the last
  // write's error ("" when it worked), the other launches' autosaves (newest
  // first) and the one offered at start until it is answered.
  std::string autosave_path, autosave_error;
  std::vector<AutosaveEntry> autosaves;
  std::optional<AutosaveEntry> offer;
  // Metric panel: the settings being edited. An edit asks for their
  // predicted vertex count once the fields have been still for
  // kPreviewDelay (the metric is built in the background:
  // EditorSession::request_metric); a commit asks for the metric itself.
  SettingsDraft draft;
  static constexpr std::chrono::milliseconds kPreviewDelay{250};
  std::optional<std::chrono::steady_clock::time_point> preview_due;
  // The view (for the G1 surface's state: built in the background, the
  // patches its control net shows); null: not shown.
  EditorView* view = nullptr;
  std::function<void(const std::string&)> screenshot;  // writes a PNG of the window
};

// Runs `action` now when the session has no unsaved changes, else asks
// first (the "Unsaved changes" dialog of the next frame).
void request(EditorSession& session, ViewState& view, PanelState& panels, PanelState::Pending action);

// Recent files: path added in front (kept unique, at most 8).
void remember_recent(PanelState& p, const std::string& path);

// The status bar's words for the adaptation's state, and what they mean (its tooltip).
std::string run_state_tooltip(RunState state, const std::string& error);

// Builds this frame's panels (between ImGui::NewFrame and ImGui::Render).
void draw_panels(EditorSession& session, ViewState& view, PanelState& panels, render::Scene& scene,
                 render::UiState& ui, int width, int height);

}  // namespace anisurf::editor
