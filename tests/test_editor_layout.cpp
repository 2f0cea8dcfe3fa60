// The editor's layout, states and findable elements: the adaptation's
// states (idle, running, pausing, paused, converged, cancelled); the keys'
// table (dispatch, the Keys window, the README); "frame worst" facing the
// worst triangle of the bunny's q < 0.1 bin and filling the view, nothing
// in front of it; the outlines' projection; a click pinning the element
// under it; the status bar at the bottom, the panels inside the window
// after a resize, errors wrapped; the touched vertices' markers capped and
// spread; and, in the window under Xvfb, a quick key tap at 1 fps not lost
// and a click (not a drag) pinning the element under it.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "editor/editor_view.h"
#include "editor/keys.h"
#include "editor/panels.h"
#include "editor/session.h"
#include "io/mesh_io.h"
#include "render/headless.h"
#include "render/image.h"
#include "render/outline.h"
#include "render/pick.h"
#include "render/point_sampling.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;
namespace fs = std::filesystem;

namespace {

// Updates the view until the displayed state is shown and the camera
// requests are carried out (the structure is built in the background).
void settle(EditorSession& s, ViewState& v, EditorView& ev, render::Scene& scene, float aspect) {
  for (int i = 0; i < 4000 && (!ev.settled(s, v) || v.fit_request || v.view_request || v.frame_selection || v.frame_element);
       ++i) {
    ev.update(s, v, scene, aspect, 0, 0);
    if (!ev.settled(s, v)) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

glm::vec3 to_glm(const Vec3& p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }

// Runs `frames` ImGui frames of the editor's panels at width x height.
void draw_frames(render::HeadlessRenderer& r, EditorSession& s, ViewState& v, PanelState& p, render::Scene& scene,
                 render::UiState& ui, int width, int height, int frames = 3) {
  r.render(scene, [&](int w, int h) { draw_panels(s, v, p, scene, ui, w, h); }, width, height, frames);
}

}  // namespace

TEST_CASE("editor state: idle, running, paused after a step or a pause, converged, cancelled, each explained") {
  EditorSession s;
  s.open(test::asset_file("demo.mesh"), test::asset_file("demo.sol"));
  CHECK(s.run_state() == RunState::Idle);
  s.step();
  CHECK((s.run_state() == RunState::Running || s.run_state() == RunState::Paused));
  s.wait();
  CHECK(s.run_state() == RunState::Paused);  // one pass, the schedule goes on
  s.run();
  CHECK(s.run_state() == RunState::Running);
  s.pause();
  CHECK((s.run_state() == RunState::Pausing || s.run_state() == RunState::Paused));
  s.wait();
  CHECK(s.run_state() == RunState::Paused);
  s.run();
  s.wait();
  REQUIRE(s.timeline().back()->schedule.phase == Schedule::Phase::Done);
  CHECK(s.run_state() == RunState::Converged);
  // A cancelled run: the timeline back where it started, the state says so
  // until the next run.
  s.reset();
  CHECK(s.run_state() == RunState::Idle);
  s.run(2);
  s.wait();
  const std::size_t before = s.timeline().size();
  s.run();
  s.cancel();
  CHECK((s.run_state() == RunState::Cancelling || s.run_state() == RunState::Cancelled));
  s.wait();
  CHECK(s.timeline().size() == before);
  CHECK(s.run_state() == RunState::Cancelled);
  s.step();
  s.wait();
  CHECK(s.run_state() == RunState::Paused);
  // Every state has its own name and its own explanation.
  const RunState all[] = {RunState::Idle,   RunState::Running,   RunState::Pausing,   RunState::Cancelling,
                          RunState::Paused, RunState::Converged, RunState::Cancelled, RunState::Failed};
  for (RunState a : all)
    for (RunState b : all)
      if (a != b) {
        CHECK(std::string(run_state_name(a)) != run_state_name(b));
        CHECK(run_state_tooltip(a, "x") != run_state_tooltip(b, "x"));
      }
  CHECK(run_state_tooltip(RunState::Failed, "the metric is not finite").find("the metric is not finite") !=
        std::string::npos);
  CHECK(run_state_tooltip(RunState::Running, "").find("Cancel") != std::string::npos);
}

TEST_CASE("editor keys: one table dispatches, lists and documents every key") {
  CHECK(key_command(GLFW_KEY_F, 0) == KeyCommand::Fit);
  CHECK(key_command(GLFW_KEY_B, 0) == KeyCommand::Brush);
  CHECK(key_command(GLFW_KEY_ESCAPE, 0) == KeyCommand::Escape);
  CHECK(key_command(GLFW_KEY_Q, GLFW_MOD_CONTROL) == KeyCommand::Quit);
  CHECK(key_command(GLFW_KEY_Q, 0) == std::nullopt);
  CHECK(key_command(GLFW_KEY_Z, GLFW_MOD_CONTROL) == KeyCommand::Undo);
  CHECK(key_command(GLFW_KEY_Z, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT) == KeyCommand::Redo);
  CHECK(key_command(GLFW_KEY_Z, GLFW_MOD_CONTROL | GLFW_MOD_ALT) == KeyCommand::Undo);  // Alt ignored
  CHECK(key_command(GLFW_KEY_F1, 0) == KeyCommand::Keys);
  for (int k = GLFW_KEY_1; k <= GLFW_KEY_7; ++k) CHECK(key_command(k, 0).has_value());
  // Each key bound once (same key and modifiers).
  const auto table = key_bindings();
  for (std::size_t i = 0; i < table.size(); ++i)
    for (std::size_t j = i + 1; j < table.size(); ++j)
      CHECK_FALSE((table[i].key == table[j].key && table[i].mods == table[j].mods));

  // The commands act on the view, the panels and the session.
  EditorSession s;
  s.open(test::asset_file("demo.mesh"));
  ViewState v;
  PanelState p;
  const bool wire = v.wireframe, glyphs = v.glyphs;
  CHECK(apply_key_command(KeyCommand::Wireframe, s, v, p));
  CHECK(v.wireframe != wire);
  CHECK(apply_key_command(KeyCommand::Glyphs, s, v, p));
  CHECK(v.glyphs != glyphs);
  CHECK(apply_key_command(KeyCommand::ViewTop, s, v, p));
  CHECK(v.view_request == render::NamedView::Top);
  CHECK(apply_key_command(KeyCommand::Brush, s, v, p));
  CHECK(v.paint_tool);
  p.pinned = PanelState::Pinned{HoverInfo{0, 0, {}}, s.display().snapshot};
  CHECK(apply_key_command(KeyCommand::Escape, s, v, p));
  CHECK_FALSE(v.paint_tool);
  CHECK_FALSE(p.pinned);
  CHECK(apply_key_command(KeyCommand::Keys, s, v, p));
  CHECK(p.show_keys);
  CHECK(apply_key_command(KeyCommand::Step, s, v, p));
  s.wait();
  CHECK(s.timeline().size() == 2);
  CHECK_FALSE(apply_key_command(KeyCommand::Quit, s, v, p));  // the window's

  // The README lists every key and mouse gesture of the table.
  const std::string readme = test::file_bytes(fs::path(ANISURF_TEST_DATA_DIR) / ".." / ".." / "README.md");
  REQUIRE_FALSE(readme.empty());
  const auto keys_at = readme.find("### Keys");
  REQUIRE(keys_at != std::string::npos);
  const std::string section = readme.substr(keys_at, readme.find("\n## ", keys_at) - keys_at);
  for (const KeyBinding& b : table) {
    INFO(b.keys);
    CHECK(section.find(std::string("`") + b.keys + "`") != std::string::npos);
  }
  for (const MouseBinding& m : mouse_bindings()) {
    INFO(m.gesture);
    CHECK(section.find(m.gesture) != std::string::npos);
  }
}

TEST_CASE("editor frame worst: the camera faces the bunny's worst q < 0.1 triangle, which fills the view in front") {
  const std::string bunny = test::shared_file("meshes/bunny.off");
  if (bunny.empty()) {
    MESSAGE("skipped: ../shared/meshes/bunny.off not found");
    return;
  }
  EditorSession s;
  s.open(bunny);
  s.select_bin(BinKind::Quality, 0);  // q < 0.1
  const Selection& sel = s.selection();
  REQUIRE_FALSE(sel.triangles.empty());
  const int W = 1600, H = 900;
  const float aspect = static_cast<float>(W) / H;
  ViewState v;
  EditorView ev;
  ev.set_synchronous(true);
  render::Scene scene;
  settle(s, v, ev, scene, aspect);
  for (int named = 0; named < 7; ++named) {  // from every named view
    v.view_request = static_cast<render::NamedView>(named);
    settle(s, v, ev, scene, aspect);
    v.frame_selection = true;
    settle(s, v, ev, scene, aspect);
    const SurfaceMesh& m = s.display().snapshot->mesh;
    const Triangle t(sel.worst_triangle);
    const Vec3 a = m.position(m.vertex(t, 0)), b = m.position(m.vertex(t, 1)), c = m.position(m.vertex(t, 2));
    const Vec3 n = cross(b - a, c - a) / norm(cross(b - a, c - a));
    // Looking along the normal, at the front.
    const double facing = dot(to_glm(n) * -1.0f, scene.camera.forward());
    CHECK(facing > std::cos(5.0 * M_PI / 180));
    // The centroid at the centre of the view; the triangle spans a good part of it.
    const glm::vec3 centroid = to_glm((a + b + c) / 3.0);
    const auto px = render::project_to_pixel(scene.camera, centroid, W, H);
    REQUIRE(px);
    CHECK(std::abs(px->x - W / 2.0f) < 0.05f * W);
    CHECK(std::abs(px->y - H / 2.0f) < 0.05f * H);
    const render::WorldTriangle world = {to_glm(a), to_glm(b), to_glm(c)};
    const auto screen = render::project_triangles(scene.camera, std::span(&world, 1), W, H);
    REQUIRE(screen.size() == 1);
    CHECK(screen[0].extent() > 0.25f * H);
    for (const glm::vec2& q : screen[0].corner) CHECK((q.x >= 0 && q.y >= 0 && q.x < W && q.y < H));
    // Nothing in front of it: the ray through its centroid hits it first.
    const auto hit = ev.hover(scene, px->x, px->y, W, H);
    REQUIRE(hit);
    CHECK(hit->triangle == sel.worst_triangle);
  }
}

TEST_CASE("editor outlines: projected corners, triangles behind the eye left out, at most N spread evenly") {
  render::Camera cam;
  cam.target = {0, 0, 0};
  cam.distance = 5;
  const std::vector<render::WorldTriangle> tris = {
      {glm::vec3(-1, -1, 0), glm::vec3(1, -1, 0), glm::vec3(0, 1, 0)},     // in front of the eye (at z = 5)
      {glm::vec3(-1, -1, 9), glm::vec3(1, -1, 9), glm::vec3(0, 1, 9)}};  // behind it
  const auto s = render::project_triangles(cam, tris, 800, 600);
  REQUIRE(s.size() == 1);
  CHECK(std::abs(s[0].centroid().x - 400) < 1.0f);
  CHECK(s[0].corner[2].y < s[0].corner[0].y);  // y up in the world, down on the screen
  CHECK(s[0].extent() > 50);
  const auto keep = render::evenly_spaced(10000, 4000);
  CHECK(keep.size() == 4000);
  CHECK(keep.front() == 0);
  CHECK(keep.back() >= 9997);
  for (std::size_t i = 1; i < keep.size(); ++i) CHECK((keep[i] - keep[i - 1] == 2 || keep[i] - keep[i - 1] == 3));
  CHECK(render::evenly_spaced(5, 4000).size() == 5);
}

TEST_CASE("editor layout: a status bar at the bottom, panels inside the window after a resize, errors wrapped, a click pins") {
  EditorSession s;
  s.open(test::asset_file("demo.mesh"), test::asset_file("demo.sol"));
  s.analysis();  // the Analysis panel is shown once there is one
  ViewState v;
  PanelState p;
  EditorView ev;
  ev.set_synchronous(true);
  p.view = &ev;
  render::Scene scene;
  render::UiState ui;
  render::HeadlessRenderer r(1600, 900);
  for (const auto& [W, H] : {std::pair{1600, 900}, std::pair{1024, 768}, std::pair{1600, 900}}) {
    CAPTURE(W);
    v.fit_request = true;
    settle(s, v, ev, scene, static_cast<float>(W) / H);
    draw_frames(r, s, v, p, scene, ui, W, H);
    // The status bar spans the bottom; the main panel ends above it; the
    // Analysis panel is anchored at the right edge, inside the window.
    CHECK(p.status_rect.w == doctest::Approx(W));
    CHECK(p.status_rect.y + p.status_rect.h == doctest::Approx(H));
    CHECK(p.main_rect.inside(W, H));
    CHECK(p.main_rect.y + p.main_rect.h <= p.status_rect.y + 0.5f);
    CHECK(p.main_rect.y + p.main_rect.h > p.status_rect.y - 20);  // down to the bar
    REQUIRE(p.analysis_rect.w > 0);
    CHECK(p.analysis_rect.inside(W, H));
    CHECK(p.analysis_rect.x + p.analysis_rect.w == doctest::Approx(W - 8.0f).epsilon(0.01));
  }
  // A message does not move the panel; a long error wraps in the status bar
  // (several lines, the bar no wider than the window).
  const auto main_before = p.main_rect;
  const float bar_before = p.status_rect.h;
  // The panel's content (Step and the headers) stays where it was: its height does not change.
  const float content_before = ImGui::FindWindowByName("anisurf editor")->ContentSize.y;
  p.message = "error: " + std::string(60, 'x') + " " + std::string(400, 'y') + " " + std::string(30, 'z') +
              " and the end of the message";
  for (std::size_t i = 9; i < p.message.size(); i += 12) p.message[i] = ' ';
  p.message_is_error = true;
  draw_frames(r, s, v, p, scene, ui, 1600, 900);
  CHECK(p.main_rect.y == main_before.y);
  CHECK(p.main_rect.x == main_before.x);
  CHECK(ImGui::FindWindowByName("anisurf editor")->ContentSize.y == content_before);
  CHECK(p.status_rect.w == doctest::Approx(1600));
  CHECK(p.status_rect.h > bar_before + 1.5f * ImGui::GetTextLineHeight());  // 3 lines instead of 1
  CHECK(p.main_rect.y + p.main_rect.h <= p.status_rect.y + 0.5f);

  // A click on the mesh pins the triangle under it; on empty space unpins.
  const int W = 1600, H = 900;
  std::optional<glm::vec2> on_mesh, off_mesh;
  for (int y = 20; y < H - 60 && !(on_mesh && off_mesh); y += 20)
    for (int x = 420; x < 1100 && !(on_mesh && off_mesh); x += 20)
      (ev.hover(scene, x, y, W, H) ? on_mesh : off_mesh) = glm::vec2(x, y);
  REQUIRE(on_mesh);
  REQUIRE(off_mesh);
  p.click = *on_mesh;
  draw_frames(r, s, v, p, scene, ui, W, H, 1);
  REQUIRE(p.pinned);
  CHECK(p.pinned->element.triangle == ev.hover(scene, on_mesh->x, on_mesh->y, W, H)->triangle);
  CHECK(p.pinned->of == s.display().snapshot);
  CHECK_FALSE(p.click);
  draw_frames(r, s, v, p, scene, ui, W, H, 2);
  CHECK(p.pinned);  // stays without a click
  // Its window's "Frame it" puts it at the centre of the view.
  v.frame_element = p.pinned->element.triangle;
  settle(s, v, ev, scene, static_cast<float>(W) / H);
  {
    const SurfaceMesh& m = s.display().snapshot->mesh;
    const Triangle t(p.pinned->element.triangle);
    const Vec3 c = (m.position(m.vertex(t, 0)) + m.position(m.vertex(t, 1)) + m.position(m.vertex(t, 2))) / 3.0;
    const auto px = render::project_to_pixel(scene.camera, to_glm(c), W, H);
    REQUIRE(px);
    CHECK(std::abs(px->x - W / 2.0f) < 0.05f * W);
    CHECK(std::abs(px->y - H / 2.0f) < 0.05f * H);
    CHECK(ev.hover(scene, px->x, px->y, W, H)->triangle == p.pinned->element.triangle);
  }
  v.fit_request = true;
  settle(s, v, ev, scene, static_cast<float>(W) / H);
  p.click = *off_mesh;
  draw_frames(r, s, v, p, scene, ui, W, H, 1);
  CHECK_FALSE(p.pinned);
}

TEST_CASE("editor markers: spread_sample keeps at most the cap, spread over the points") {
  std::vector<glm::vec3> grid;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) grid.push_back({i / 199.0f, j / 199.0f, 0.0f});
  const auto keep = render::spread_sample(grid, 3000);
  CHECK(keep.size() <= 3000);
  CHECK(keep.size() >= 1000);
  CHECK(std::is_sorted(keep.begin(), keep.end()));
  // Every point has a kept one nearby (cells of about 1/sqrt(3000) of the side).
  float farthest = 0;
  for (std::size_t i = 0; i < grid.size(); i += 37) {
    float nearest = INFINITY;
    for (std::size_t k : keep) nearest = std::min(nearest, glm::length(grid[i] - grid[k]));
    farthest = std::max(farthest, nearest);
  }
  CHECK(farthest < 0.06f);
  CHECK(render::spread_sample(grid, 50000).size() == grid.size());
}

TEST_CASE("editor markers: the falcon's touched vertices are capped and sized to the view") {
  const std::string falcon = test::shared_file("meshes/falcon.mesh");
  if (falcon.empty()) {
    MESSAGE("skipped: ../shared/meshes/falcon.mesh not found");
    return;
  }
  EditorSession s;
  s.open(falcon);
  // The passes until one touches more vertices than are marked (a split or a smoothing pass).
  for (int pass = 0; pass < 8; ++pass) {
    s.step();
    s.wait();
    if (s.timeline().back()->report.touched.size() > 2 * EditorView::kMaxTouchedMarkers) break;
  }
  ViewState v;
  EditorView ev;
  ev.set_synchronous(true);
  render::Scene scene;
  settle(s, v, ev, scene, 1.6f);
  const EditorView::MarkerCounts mc = ev.touched_markers();
  MESSAGE("falcon, pass " << s.timeline().back()->label << ": " << mc.total << " vertices touched, " << mc.shown << " marked");
  REQUIRE(mc.total > static_cast<int>(EditorView::kMaxTouchedMarkers));
  CHECK(mc.shown <= static_cast<int>(EditorView::kMaxTouchedMarkers));
  CHECK(mc.shown >= static_cast<int>(EditorView::kMaxTouchedMarkers) / 3);
  const render::Markers* mk = nullptr;
  for (const auto& st : scene.surfaces)
    for (const auto& m : st.markers)
      if (m.name == EditorView::kTouchedName) mk = &m;
  REQUIRE(mk);
  CHECK(static_cast<int>(mk->positions.size()) == mc.shown);
  // The whole model in view: small discs; zoomed in on a part: fewer in
  // view, larger discs (at most 4.5 px).
  ev.size_markers(scene, 1280, 800);
  const float whole = mk->radius_px;
  scene.camera.zoom(0.1f);
  ev.size_markers(scene, 1280, 800);
  const float zoomed = mk->radius_px;
  MESSAGE("marker radius: " << whole << " px for the whole model, " << zoomed << " px zoomed in");
  CHECK(whole >= 1.5f);
  CHECK(zoomed > whole);
  CHECK(zoomed <= 4.5f);
}

TEST_CASE("editor window: a quick key tap at 1 frame per second is not lost (Ctrl+Q quits, under Xvfb)") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0 || std::system("command -v xdotool >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run or xdotool not installed");
    return;
  }
  const auto dir = test::temp_dir("editor_key_tap");
  const std::string cube = (dir / "cube.mesh").string();
  write_mesh_data(cube, test::cube());
  // Press and release within a few milliseconds, between two frames a second apart.
  std::ostringstream cmd;
  cmd << "XDG_STATE_HOME='" << (dir / "state").string() << "' xvfb-run -a -s '-screen 0 1280x800x24' sh -c '\""
      << ANISURF_BINARY << "\" \"" << cube << "\" --max-fps 1 & pid=$!; "
      << "timeout 30 xdotool search --sync --onlyvisible --name \"anisurf editor\" >/dev/null; sleep 3; "
      << "xdotool mousemove 800 450 key --delay 1 ctrl+q; sleep 5; "
      << "if kill -0 $pid 2>/dev/null; then echo alive; kill $pid; else echo exited; fi; wait $pid' >'"
      << (dir / "stdout.txt").string() << "' 2>'" << (dir / "stderr.txt").string() << "'";
  std::system(cmd.str().c_str());
  CHECK(test::file_bytes(dir / "stdout.txt").find("exited") != std::string::npos);
}

TEST_CASE("editor window: a click pins the element under it, a drag does not (under Xvfb)") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0 || std::system("command -v xdotool >/dev/null 2>&1") != 0 ||
      std::system("command -v import >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run, xdotool or import (ImageMagick) not installed");
    return;
  }
  const auto dir = test::temp_dir("editor_click_pin");
  const std::string cube = (dir / "cube.mesh").string();
  write_mesh_data(cube, test::cube());
  // The pinned triangle's outline is cyan (0.1, 0.85, 1): its pixels in a grab of the screen.
  auto cyan_pixels = [](const fs::path& png) {
    const render::Image img = render::read_png(png.string());
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const auto* p = img.pixel(x, y);
        n += p[0] < 70 && p[1] > 180 && p[1] < 245 && p[2] > 225;
      }
    return n;
  };
  // A drag from the mesh's middle (orbits, pins nothing), then a click there.
  std::ostringstream cmd;
  cmd << "XDG_STATE_HOME='" << (dir / "state").string() << "' xvfb-run -a -s '-screen 0 1280x800x24' sh -c '\""
      << ANISURF_BINARY << "\" \"" << cube << "\" & pid=$!; "
      << "timeout 30 xdotool search --sync --onlyvisible --name \"anisurf editor\" >/dev/null; sleep 3; "
      << "xdotool mousemove 720 400 mousedown 1 mousemove 760 420 mousemove 800 440 mouseup 1; sleep 2; "
      << "import -window root \"" << (dir / "dragged.png").string() << "\"; "
      << "xdotool mousemove 720 400 click 1; sleep 2; xdotool mousemove 1270 790; sleep 2; "
      << "import -window root \"" << (dir / "clicked.png").string() << "\"; "
      << "kill $pid; wait $pid' >'" << (dir / "stdout.txt").string() << "' 2>'" << (dir / "stderr.txt").string() << "'";
  std::system(cmd.str().c_str());
  REQUIRE(fs::exists(dir / "dragged.png"));
  REQUIRE(fs::exists(dir / "clicked.png"));
  const int dragged = cyan_pixels(dir / "dragged.png"), clicked = cyan_pixels(dir / "clicked.png");
  MESSAGE("cyan outline pixels: " << dragged << " after a drag, " << clicked << " after a click");
  CHECK(dragged < 20);
  CHECK(clicked > 200);
}

#endif
