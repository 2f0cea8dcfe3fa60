// The editor's entry points: `anisurf [MESH [SOL]]` opens the window (no
// argument: the demo), `anisurf --script FILE [--headless] [--size WxH]`
// runs a script (headless: OSMesa pictures; else it drives the window).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace anisurf::editor {

// Handles the command lines above; nullopt when `args` (argv[1..]) is a
// subcommand line for the regular command line. Returns the exit code.
std::optional<int> editor_main(const std::vector<std::string>& args, const std::vector<std::string>& command_names);

// The usage text of the editor's command lines.
const char* editor_help();

struct ScriptOptions {
  std::string script;
  bool headless = true;
  int width = 1280, height = 800;
  // The window's frame cap and, for the measures, a report of frame times
  // while the adaptation runs (printed on stderr after each run).
  double max_fps = 60;
  // --frame-stats: the window prints its frame times at exit (frames, mean,
  // slowest, and the slowest while a metric is built, a pass runs or the G1
  // surface is built); a script's `frame-stats` line prints them too.
  bool frame_stats = false;
};

// Runs a script headless (OSMesa); returns 0, or prints "FILE:LINE: ..." on
// stderr and returns 1.
int run_script_headless(const ScriptOptions& options);

// Opens the window on a session (mesh / sol optional) and, if
// options.script is set, plays the script in it (one line per frame, waiting
// for the adaptation). Throws render::GlError without a display.
int run_editor_window(const std::string& mesh, const std::string& sol, const ScriptOptions& options);

}  // namespace anisurf::editor
