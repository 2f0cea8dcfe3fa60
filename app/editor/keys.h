// The editor's keys: one table (key, modifiers, what it does) that the
// window's key callback dispatches through, the Keys window lists and the
// README repeats. Key codes and modifier bits are GLFW's (GLFW_KEY_*,
// GLFW_MOD_*), kept as ints so that this header needs no GLFW.
#pragma once
#include <optional>
#include <span>

#include "editor/panels.h"
#include "editor/session.h"
#include "editor/view_state.h"

namespace anisurf::editor {

enum class KeyCommand {
  ViewIso, ViewFront, ViewBack, ViewLeft, ViewRight, ViewTop, ViewBottom,
  Fit, Glyphs, Wireframe, Brush, Undo, Redo, Step, RunOrPause, Escape, Quit, Keys
};

struct KeyBinding {
  int key;            // GLFW_KEY_*
  int mods;           // GLFW_MOD_CONTROL / GLFW_MOD_SHIFT bits that must be held (the others must not)
  KeyCommand command;
  const char* keys;   // as shown to the user: "Ctrl+Shift+Z"
  const char* action; // what it does, one line
};

// What the mouse does in the view (listed after the keys).
struct MouseBinding {
  const char* gesture;
  const char* action;
};
std::span<const MouseBinding> mouse_bindings();

// Every binding, in the order the Keys window lists them.
std::span<const KeyBinding> key_bindings();

// The command of a key press with modifiers `mods` (Alt and the lock keys
// ignored), if the key is bound.
std::optional<KeyCommand> key_command(int key, int mods);

// Carries out a command on the session, the view and the panels. Quit is
// the window's (it asks first when there is unsaved work): returns false for
// it, true otherwise. Throws what the session's action throws.
bool apply_key_command(KeyCommand command, EditorSession& session, ViewState& view, PanelState& panels);

}  // namespace anisurf::editor
