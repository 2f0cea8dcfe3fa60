// `anisurf --script FILE --headless`: the script's screenshots through OSMesa,
// with the same panels as the window.
#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/error.h"
#include "editor/editor_app.h"
#include "editor/editor_view.h"
#include "editor/panels.h"
#include "editor/script.h"
#include "render/gpu_error.h"
#include "render/headless.h"
#include "render/image.h"

namespace anisurf::editor {

int run_script_headless(const ScriptOptions& o) {
  std::vector<ScriptLine> lines;
  try {
    lines = read_script(o.script);
  } catch (const Error& e) {
    std::cerr << "anisurf: " << e.what() << "\n";
    return 1;
  }
  EditorSession session;
  ViewState view;
  PanelState panels;
  render::Scene scene;
  render::UiState ui;
  EditorView ev;
  ev.set_synchronous(true);  // every picture shows the G1 surface it asks for
  panels.view = &ev;
  std::unique_ptr<render::HeadlessRenderer> renderer;
  const int W = o.width, H = o.height;
  const float aspect = static_cast<float>(W) / static_cast<float>(H);
  auto ui_cb = [&](int w, int h) { draw_panels(session, view, panels, scene, ui, w, h); };
  bool quit = false;
  ScriptHost host;
  host.quit = [&] { quit = true; };
  host.click = [&](float x, float y) { panels.click = glm::vec2(x, y); };
  host.show_keys = [&](bool on) { panels.show_keys = on; };
  host.screenshot = [&](const std::string& png) {
    const auto t0 = std::chrono::steady_clock::now();
    session.wait();
    session.analysis();  // the Analysis panel shows the displayed state's
    if (view.color == "distance") session.distance();  // the colours of the state shown, measured
    if (!renderer) renderer = std::make_unique<render::HeadlessRenderer>(W, H);
    const bool fit = view.fit_request || view.frame_selection || view.frame_element || view.view_request.has_value();
    ViewState before = view;
    ev.update(session, view, scene, aspect, ui.left_reserve(W), ui.right_reserve(W));
    if (fit) {
      // Measure the panel and the legend, then fit again to keep them free.
      renderer->render(scene, ui_cb, W, H, 2);
      view.fit_request = before.fit_request || before.view_request.has_value();
      view.frame_selection = before.frame_selection;
      view.frame_element = before.frame_element;
      ev.update(session, view, scene, aspect, ui.left_reserve(W), ui.right_reserve(W));
    }
    // What waits for the camera's fit (the G1 surface's control net is built
    // around the view's centre) is built now.
    if (!ev.settled(session, view)) ev.update(session, view, scene, aspect, ui.left_reserve(W), ui.right_reserve(W));
    ev.size_markers(scene, W, H);
    render::Image img = renderer->render(scene, ui_cb, W, H, 3);
    render::write_png(png, img);
    std::fprintf(stderr, "screenshot %s (%dx%d, %.2f s)\n", png.c_str(), W, H,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  try {
    for (const auto& line : lines) {
      if (quit) break;
      const auto t0 = std::chrono::steady_clock::now();
      execute(line, session, view, host);
      session.wait();
      if (const std::string err = session.adaptation_error(); !err.empty())
        throw Error(line.where() + ": " + line.words[0] + ": " + err);
      const std::string& c = line.words[0];
      if (c == "step" || c == "run") {
        const auto tl = session.timeline();
        const auto& last = tl.back();
        std::fprintf(stderr, "%s: %zu passes, %d vertices, %d triangles, in band %.1f%% (%.2f s)\n",
                     line.where().c_str(), tl.size() - 1 + session.dropped_passes(), last->mesh.n_vertices(),
                     last->mesh.n_triangles(),
                     last->has_report ? 100 * last->report.in_band_share : 0.0,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
    }
  } catch (const render::GlError& e) {
    std::cerr << "anisurf: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "anisurf: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace anisurf::editor
