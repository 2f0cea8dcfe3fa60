#include "editor/editor_app.h"

#include <malloc.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "cli/cli.h"
#include "core/error.h"
#include "editor/script.h"
#include "render/gpu_error.h"

namespace anisurf::editor {

namespace {

const char* kEditorHelp =
    "usage: anisurf [MESH [SOL]]                    open the editor window (default: the demo)\n"
    "       anisurf --script FILE [--headless] [--size WxH] [--max-fps F]\n"
    "                                               run an editor script: headless pictures\n"
    "                                               through OSMesa, or drive the window\n"
    "       anisurf [MESH [SOL]] --frame-stats      the window prints its frame times at exit\n"
    "                                               (the slowest frame, and what ran then)\n"
    "       anisurf --help-script                   the script language\n\n"
    "Window: left drag orbit (paints with the brush tool, B), right drag pan, wheel zoom;\n"
    "keys 1-7 views, F fit, G glyphs, W wireframe, space step, R run/pause,\n"
    "Ctrl+Z / Ctrl+Y undo / redo, Esc leaves the brush and unpins, F1 lists the keys;\n"
    "a click (no drag) pins the element's info; drop a mesh (and its .sol) to open it.\n"
    "Ctrl+Q quits; open, drop and quit ask first when there are unsaved changes.\n"
    "Each launch autosaves its session as a script of its own in $XDG_STATE_HOME/anisurf\n"
    "(else ~/.local/state/anisurf): File > autosaved sessions restores one (its edits,\n"
    "not its saves); replay one with --script.\n\n"
    "example:\n"
    "  anisurf --script assets/demo.anisurf --headless\n";

std::string find_demo(const std::string& name) {
  for (const std::filesystem::path& dir : {std::filesystem::path("assets"), std::filesystem::path(ANISURF_ASSETS_DIR)}) {
    std::error_code ec;
    if (std::filesystem::exists(dir / name, ec)) return (dir / name).string();
  }
  return {};
}

// llvmpipe allocates and frees frame-sized buffers (megabytes) every frame.
// With glibc's adaptive mmap threshold they end up at the top of the heap
// and each free trims it, so the next frame faults every page in again: on
// the Falcon that tripled the time of a frame (and most of it in the
// kernel). A fixed mmap threshold and a high trim threshold keep them.
void keep_frame_buffers_allocated() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

std::pair<int, int> parse_size(const std::string& t) {
  const auto x = t.find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument(t);
    const int w = std::stoi(t.substr(0, x)), h = std::stoi(t.substr(x + 1));
    if (w < 320 || h < 240 || w > 8192 || h > 8192) throw std::invalid_argument(t);
    return {w, h};
  } catch (const std::exception&) {
    throw cli::UsageError{"--size expects WIDTHxHEIGHT (at least 320x240), got '" + t + "'"};
  }
}

}  // namespace

const char* editor_help() { return kEditorHelp; }

std::optional<int> editor_main(const std::vector<std::string>& args, const std::vector<std::string>& command_names) {
  const bool script_mode = !args.empty() && args[0] == "--script";
  if (!args.empty() && args[0] == "--help-script") {
    std::cout << script_help();
    return 0;
  }
  if (!args.empty() && (args[0] == "--help-editor")) {
    std::cout << kEditorHelp;
    return 0;
  }
  if (!args.empty() && !script_mode) {
    // A subcommand, an option of the regular command line, or not a file: not ours.
    if (args[0].rfind("-", 0) == 0) return std::nullopt;
    if (std::find(command_names.begin(), command_names.end(), args[0]) != command_names.end()) return std::nullopt;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(args[0], ec)) {
      // A mesh file name that does not exist: say so (not "unknown command").
      std::string ext = std::filesystem::path(args[0]).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
      for (const char* e : {".mesh", ".meshb", ".off", ".obj", ".ply", ".stl", ".gltf", ".glb", ".vtk", ".msh", ".vtu", ".vtp"})
        if (ext == e) {
          std::cerr << "anisurf: " << args[0] << ": no such file\n";
          return 1;
        }
      return std::nullopt;
    }
  }
  try {
    cli::ArgParser p(args);
    ScriptOptions o;
    if (script_mode) {
      o.script = p.option("--script");
      if (o.script.empty()) throw cli::UsageError{"--script needs a FILE"};
    }
    o.headless = p.flag("--headless");
    if (o.headless && !script_mode) throw cli::UsageError{"--headless goes with --script FILE"};
    if (const std::string s = p.option("--size"); !s.empty()) std::tie(o.width, o.height) = parse_size(s);
    o.max_fps = p.option_double("--max-fps", 60);
    o.frame_stats = p.flag("--frame-stats");
    if (o.frame_stats && o.headless) throw cli::UsageError{"--frame-stats measures the window: not with --headless"};
    if (!(o.max_fps >= 1)) throw cli::UsageError{"--max-fps expects a frame rate >= 1"};
    const auto pos = p.positionals();
    if (pos.size() > 2) throw cli::UsageError{"expected [MESH [SOL]]"};
    if (script_mode && !pos.empty()) throw cli::UsageError{"--script takes the mesh from the script (open MESH [SOL])"};
    keep_frame_buffers_allocated();
    if (o.headless) return run_script_headless(o);
    std::string mesh = pos.empty() ? "" : pos[0], sol = pos.size() > 1 ? pos[1] : "";
    if (mesh.empty() && !script_mode) {
      mesh = find_demo("demo.mesh");
      sol = find_demo("demo.sol");
      if (mesh.empty()) throw Error("no MESH given and assets/demo.mesh not found");
    }
    return run_editor_window(mesh, sol, o);
  } catch (const cli::UsageError& e) {
    std::cerr << "anisurf: " << e.message << "\n\n" << kEditorHelp;
    return 2;
  } catch (const render::GlError& e) {
    std::cerr << "anisurf: " << e.what() << "\n";
    return 1;
  } catch (const Error& e) {
    std::cerr << "anisurf: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "anisurf: internal error: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace anisurf::editor
