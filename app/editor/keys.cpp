#include "editor/keys.h"

#include <GLFW/glfw3.h>

#include <array>

namespace anisurf::editor {

namespace {

constexpr int kCtrl = GLFW_MOD_CONTROL, kShift = GLFW_MOD_SHIFT;

constexpr std::array kBindings = {
    KeyBinding{GLFW_KEY_1, 0, KeyCommand::ViewIso, "1", "iso view (and fit)"},
    KeyBinding{GLFW_KEY_2, 0, KeyCommand::ViewFront, "2", "front view"},
    KeyBinding{GLFW_KEY_3, 0, KeyCommand::ViewBack, "3", "back view"},
    KeyBinding{GLFW_KEY_4, 0, KeyCommand::ViewLeft, "4", "left view"},
    KeyBinding{GLFW_KEY_5, 0, KeyCommand::ViewRight, "5", "right view"},
    KeyBinding{GLFW_KEY_6, 0, KeyCommand::ViewTop, "6", "top view"},
    KeyBinding{GLFW_KEY_7, 0, KeyCommand::ViewBottom, "7", "bottom view"},
    KeyBinding{GLFW_KEY_F, 0, KeyCommand::Fit, "F", "fit the mesh in the view"},
    KeyBinding{GLFW_KEY_W, 0, KeyCommand::Wireframe, "W", "wireframe on / off"},
    KeyBinding{GLFW_KEY_G, 0, KeyCommand::Glyphs, "G", "metric glyphs on / off"},
    KeyBinding{GLFW_KEY_B, 0, KeyCommand::Brush, "B", "metric brush on / off (left drag paints)"},
    KeyBinding{GLFW_KEY_SPACE, 0, KeyCommand::Step, "Space", "one adaptation pass (Step)"},
    KeyBinding{GLFW_KEY_R, 0, KeyCommand::RunOrPause, "R", "Run, or Pause a run (keeps the passes done)"},
    KeyBinding{GLFW_KEY_Z, kCtrl, KeyCommand::Undo, "Ctrl+Z", "undo a metric edit"},
    KeyBinding{GLFW_KEY_Z, kCtrl | kShift, KeyCommand::Redo, "Ctrl+Shift+Z", "redo"},
    KeyBinding{GLFW_KEY_Y, kCtrl, KeyCommand::Redo, "Ctrl+Y", "redo"},
    KeyBinding{GLFW_KEY_ESCAPE, 0, KeyCommand::Escape, "Esc", "leave the brush, unpin the element info"},
    KeyBinding{GLFW_KEY_F1, 0, KeyCommand::Keys, "F1", "this list of keys"},
    KeyBinding{GLFW_KEY_SLASH, kShift, KeyCommand::Keys, "?", "this list of keys"},
    KeyBinding{GLFW_KEY_Q, kCtrl, KeyCommand::Quit, "Ctrl+Q", "quit (asks first when there is unsaved work)"},
};

constexpr std::array kMouse = {
    MouseBinding{"left drag", "orbit"},
    MouseBinding{"right or middle drag, Shift+left drag", "pan"},
    MouseBinding{"wheel", "zoom"},
    MouseBinding{"left click (no drag)", "pin the element's info (on empty space: unpin)"},
    MouseBinding{"left drag with the brush (B)", "paint the metric"},
    MouseBinding{"drop a file", "open it (a .sol: the metric of the open mesh)"},
};

std::optional<render::NamedView> named_view(KeyCommand c) {
  switch (c) {
    case KeyCommand::ViewIso: return render::NamedView::Iso;
    case KeyCommand::ViewFront: return render::NamedView::Front;
    case KeyCommand::ViewBack: return render::NamedView::Back;
    case KeyCommand::ViewLeft: return render::NamedView::Left;
    case KeyCommand::ViewRight: return render::NamedView::Right;
    case KeyCommand::ViewTop: return render::NamedView::Top;
    case KeyCommand::ViewBottom: return render::NamedView::Bottom;
    default: return std::nullopt;
  }
}

}  // namespace

std::span<const KeyBinding> key_bindings() { return kBindings; }

std::span<const MouseBinding> mouse_bindings() { return kMouse; }

std::optional<KeyCommand> key_command(int key, int mods) {
  const int held = mods & (kCtrl | kShift);
  for (const KeyBinding& b : kBindings)
    if (b.key == key && b.mods == held) return b.command;
  return std::nullopt;
}

bool apply_key_command(KeyCommand command, EditorSession& session, ViewState& view, PanelState& panels) {
  if (const auto v = named_view(command)) {
    view.view_request = *v;
    return true;
  }
  switch (command) {
    case KeyCommand::Fit: view.fit_request = true; break;
    case KeyCommand::Wireframe: view.wireframe = !view.wireframe; break;
    case KeyCommand::Glyphs: view.glyphs = !view.glyphs; break;
    case KeyCommand::Brush: view.paint_tool = !view.paint_tool; break;
    case KeyCommand::Step:
      if (!session.running()) session.step();  // throws without a mesh (the window shows why)
      break;
    case KeyCommand::RunOrPause:
      if (session.running()) session.pause();
      else session.run();
      break;
    case KeyCommand::Undo: session.undo(); break;
    case KeyCommand::Redo: session.redo(); break;
    case KeyCommand::Escape:
      view.paint_tool = false;
      panels.pinned.reset();
      break;
    case KeyCommand::Keys: panels.show_keys = !panels.show_keys; break;
    case KeyCommand::Quit: return false;
    default: break;
  }
  return true;
}

}  // namespace anisurf::editor
