// The editor's script language: one command per line, the same actions as
// the panels ('#' starts a comment). Documented in script_help().
//   open MESH [SOL]
//   metric iso H | metric size EXPR | metric hessian EXPR ERR
//   metric curvature HAUSD | metric sol FILE
//   hgrad R | hmin A | hmax B | max-aniso K
//   brush set|smooth|erase [STRENGTH] | brush direction stroke|max-curvature|min-curvature
//   paint X Y Z RADIUS SIZE [STRETCH DIRX DIRY DIRZ] | stroke begin|end
//   undo | redo
//   step | run [MAXPASSES] | reset | timeline I | lmin L | lmax L
//   select-bin length|quality I | clear-selection
//   view NAME | color MODE | glyphs on|off | wire on|off
//   bezier K|off | control-net on|off
//   click X Y | keys on|off
//   screenshot PNG | save MESH [SOL] | quit
//   frame-stats [reset]   (the window only: the slowest frame so far)
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "editor/session.h"
#include "editor/view_state.h"

namespace anisurf::editor {

struct ScriptLine {
  std::string file;
  int number = 0;
  std::string text;
  std::vector<std::string> words;
  // "demo.anisurf:12"
  std::string where() const { return file + ":" + std::to_string(number); }
};

// Reads a script (skips blank and comment lines). Throws Error if unreadable.
std::vector<ScriptLine> read_script(const std::string& path);
// Splits a line into words ('#' to the end is dropped).
std::vector<std::string> split_words(const std::string& text);

// What a line asks of the front end beyond the session and the view state.
struct ScriptHost {
  std::function<void(const std::string& png)> screenshot;
  std::function<void()> quit;
  // `frame-stats`: prints the frame times since the start or the last
  // `frame-stats reset` (reset: true clears them). Null: no frames (headless).
  std::function<void(bool reset)> frame_stats;
  // Metric settings from `metric ...`, `hgrad` ... lines: null applies them at
  // once (EditorSession::set_settings); the window builds them in the
  // background as its panel does (EditorSession::request_metric) and plays
  // the next line once the metric is installed.
  std::function<void(const MetricSettings&)> set_settings;
  // `click X Y`: a click without drag at pixel (X, Y) of the window (pins
  // the element under it); `keys on|off`: the Keys window.
  std::function<void(float x, float y)> click;
  std::function<void(bool)> show_keys;
};

// Runs one line; throws Error("FILE:LINE: message") on a bad line or a
// failed action. Adaptation commands start the worker and return: the caller
// waits (session.wait()) or keeps drawing frames until it is idle.
void execute(const ScriptLine& line, EditorSession& session, ViewState& view, const ScriptHost& host);

// The language, for `anisurf --help-script` and the README.
const char* script_help();

}  // namespace anisurf::editor
