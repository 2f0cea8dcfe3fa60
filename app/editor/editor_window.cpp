// The editor window: GLFW + the renderer + the panels; mouse: orbit / pan /
// zoom, a click pins the element under it, or paint with the brush; keys
// (keys.h) queued by the key callback and carried out by the frame, in
// order; drag and drop to open; the script player;
// the autosave (its own file per launch, an earlier one offered at start);
// open, drop and quit ask first when there is unsaved work (panels.h).
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "editor/autosave.h"
#include "editor/editor_app.h"
#include "editor/editor_view.h"
#include "editor/keys.h"
#include "editor/panels.h"
#include "editor/script.h"
#include "render/gl.h"
#include "render/gpu_error.h"
#include "render/image.h"
#include "render/renderer.h"

namespace anisurf::editor {

namespace {

using Clock = std::chrono::steady_clock;

struct App {
  EditorSession session;
  ViewState view;
  PanelState panels;
  render::Scene scene;
  render::UiState ui;
  EditorView ev;
  double mx = 0, my = 0;
  bool rotating = false, panning = false, painting = false;
  bool have_last_dab = false;
  Vec3 last_dab;
  // A left press that may be a click: it pins the element under it on
  // release unless the mouse moved more than kClickSlop pixels meanwhile.
  static constexpr double kClickSlop = 4.0;
  bool click_candidate = false;
  double press_x = 0, press_y = 0;
  // Key commands in the order they were pressed (the key callback queues
  // them; the frame carries them out: no tap is lost at a low frame rate).
  std::vector<KeyCommand> key_commands;
  std::vector<std::string> dropped;
  // Keys that went down since the last frame, and releases held back to the
  // next frame (on_key_event).
  struct KeyRelease {
    int key, scancode, mods;
  };
  std::vector<int> pressed_this_frame;
  std::vector<KeyRelease> held_releases;
  bool close_requested = false;
  Clock::time_point last_event = Clock::now();
};

App& app_of(GLFWwindow* w) { return *static_cast<App*>(glfwGetWindowUserPointer(w)); }

void paint_at(App& a, GLFWwindow* w) {
  int ww = 1, wh = 1, fw = 1, fh = 1;
  glfwGetWindowSize(w, &ww, &wh);
  glfwGetFramebufferSize(w, &fw, &fh);
  const float sx = static_cast<float>(fw) / static_cast<float>(ww), sy = static_cast<float>(fh) / static_cast<float>(wh);
  auto h = a.ev.hover(a.scene, static_cast<float>(a.mx) * sx, static_cast<float>(a.my) * sy, fw, fh);
  if (!h) return;
  const double spacing = 0.25 * a.session.brush().radius;
  if (a.have_last_dab && norm(h->point - a.last_dab) < spacing) return;
  const Vec3 dir = a.have_last_dab ? h->point - a.last_dab : Vec3();
  try {
    a.session.dab(h->point, dir);
  } catch (const std::exception& e) {
    a.panels.message = e.what();
    a.panels.message_is_error = true;
  }
  a.last_dab = h->point;
  a.have_last_dab = true;
}

void on_mouse_button(GLFWwindow* w, int button, int action, int mods) {
  App& a = app_of(w);
  a.last_event = Clock::now();
  const bool press = action == GLFW_PRESS;
  if (press && ImGui::GetIO().WantCaptureMouse) return;
  glfwGetCursorPos(w, &a.mx, &a.my);
  if (button == GLFW_MOUSE_BUTTON_LEFT && a.view.paint_tool && !(mods & GLFW_MOD_SHIFT)) {
    if (press && a.session.has_mesh()) {
      a.session.begin_stroke();
      a.painting = true;
      a.have_last_dab = false;
      paint_at(a, w);
    } else if (!press && a.painting) {
      a.painting = false;
      a.session.end_stroke();
    }
    return;
  }
  if (button == GLFW_MOUSE_BUTTON_LEFT && !(mods & GLFW_MOD_SHIFT)) {
    if (press) {
      a.click_candidate = true;
      a.press_x = a.mx;
      a.press_y = a.my;
    } else if (a.click_candidate && a.rotating) {
      int ww = 1, wh = 1, fw = 1, fh = 1;
      glfwGetWindowSize(w, &ww, &wh);
      glfwGetFramebufferSize(w, &fw, &fh);
      a.panels.click = glm::vec2(static_cast<float>(a.mx * fw / ww), static_cast<float>(a.my * fh / wh));
    }
    a.rotating = press;
  }
  if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE ||
      (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)))
    a.panning = press;
  if (!press) {
    a.rotating = a.panning = false;
    a.click_candidate = false;
  }
}

void on_cursor(GLFWwindow* w, double x, double y) {
  App& a = app_of(w);
  a.last_event = Clock::now();
  const double dx = x - a.mx, dy = y - a.my;
  a.mx = x;
  a.my = y;
  if (a.click_candidate && std::hypot(x - a.press_x, y - a.press_y) > App::kClickSlop) a.click_candidate = false;
  int ww = 1, wh = 1;
  glfwGetWindowSize(w, &ww, &wh);
  if (a.painting) paint_at(a, w);
  if (a.rotating) a.scene.camera.orbit(static_cast<float>(-dx / wh * 3.0), static_cast<float>(dy / wh * 3.0));
  if (a.panning) a.scene.camera.pan(static_cast<float>(dx / wh), static_cast<float>(-dy / wh));
}

void on_scroll(GLFWwindow* w, double, double dy) {
  App& a = app_of(w);
  a.last_event = Clock::now();
  if (ImGui::GetIO().WantCaptureMouse) return;
  a.scene.camera.zoom(static_cast<float>(std::pow(0.88, dy)));
}

void on_close(GLFWwindow* w);

// A key press outside text fields: its command is queued for the frame.
void on_key(GLFWwindow* w, int key, int, int action, int mods) {
  App& a = app_of(w);
  a.last_event = Clock::now();
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  if (const auto c = key_command(key, mods)) a.key_commands.push_back(*c);
}

// The queued key commands, in order; Quit as the window's close button
// (confirmation when there is unsaved work).
void apply_key_commands(GLFWwindow* w, App& a) {
  const auto commands = std::move(a.key_commands);
  a.key_commands.clear();
  for (KeyCommand c : commands) {
    try {
      if (!apply_key_command(c, a.session, a.view, a.panels)) {
        glfwSetWindowShouldClose(w, GLFW_TRUE);
        on_close(w);
      }
    } catch (const std::exception& e) {
      a.panels.message = e.what();
      a.panels.message_is_error = true;
    }
  }
}

// Every key event, to the window's keys and to Dear ImGui. ImGui (1.86)
// reads the key states once per frame: a press released within the same
// frame (a quick tap at a low frame rate: Tab out of a field, Enter) would
// never be seen, so such a release is passed on at the next frame
// (release_held_keys()).
void on_key_event(GLFWwindow* w, int key, int scancode, int action, int mods) {
  App& a = app_of(w);
  if (action == GLFW_RELEASE &&
      std::find(a.pressed_this_frame.begin(), a.pressed_this_frame.end(), key) != a.pressed_this_frame.end()) {
    a.held_releases.push_back({key, scancode, mods});
    return;
  }
  if (action == GLFW_PRESS) a.pressed_this_frame.push_back(key);
  on_key(w, key, scancode, action, mods);
  ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
}

// Before the events of a new frame: the releases held back by on_key_event.
void release_held_keys(GLFWwindow* w, App& a) {
  const auto held = std::move(a.held_releases);
  a.held_releases.clear();
  a.pressed_this_frame.clear();
  for (const auto& r : held) ImGui_ImplGlfw_KeyCallback(w, r.key, r.scancode, GLFW_RELEASE, r.mods);
}

void on_drop(GLFWwindow* w, int count, const char** paths) {
  App& a = app_of(w);
  for (int i = 0; i < count; ++i) a.dropped.emplace_back(paths[i]);
}

void on_close(GLFWwindow* w) {
  App& a = app_of(w);
  if (a.panels.quit_confirmed) return;
  if (a.session.has_mesh() && a.session.dirty()) {
    glfwSetWindowShouldClose(w, GLFW_FALSE);
    request(a.session, a.view, a.panels, {PanelState::Action::Quit, {}, {}});
  }
}

// Opens dropped files (asking first when there is unsaved work): a .sol
// goes with the open mesh (or the mesh dropped with it), anything else is
// opened as a mesh.
void open_dropped(App& a) {
  if (a.dropped.empty()) return;
  std::string mesh, sol;
  for (const auto& p : a.dropped) {
    std::string ext = std::filesystem::path(p).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    (ext == ".sol" ? sol : mesh) = p;
  }
  a.dropped.clear();
  if (mesh.empty()) mesh = a.session.has_mesh() ? a.session.mesh_path() : "";
  if (mesh.empty()) return;
  request(a.session, a.view, a.panels, {PanelState::Action::Open, mesh, sol});
}

// Writes the launch's autosave when the journal changed; an error stays
// shown at the top of the panel until a write works again.
void write_autosave(App& a, Autosave& autosave) {
  try {
    if (autosave.write(a.session.journal())) {
      a.panels.autosave_path = autosave.path();
      a.panels.autosave_error.clear();
    }
  } catch (const std::exception& e) {
    if (a.panels.autosave_error != e.what()) std::fprintf(stderr, "anisurf: %s\n", e.what());
    a.panels.autosave_error = e.what();  // shown in red at the top of the panel
  }
}

// Recent files, kept next to the autosave (one per line).
std::string recent_path() { return (std::filesystem::path(autosave_dir()) / "recent.txt").string(); }

void load_recent(PanelState& p) {
  std::ifstream in(recent_path());
  for (std::string line; std::getline(in, line) && p.recent.size() < 8;)
    if (!line.empty()) p.recent.push_back(line);
}

// At exit (no window left to show an error in): a failure goes to stderr.
void save_recent(const PanelState& p) {
  try {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(recent_path()).parent_path(), ec);
    AtomicFile out(recent_path());
    for (const auto& r : p.recent) out.stream() << r << "\n";
    out.commit();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "anisurf: the recent files were not saved: %s\n", e.what());
  }
}

// Frame times, the responsiveness measure: the work of each frame from its
// events to the swap (the sleep of the frame cap excluded), overall and
// while each kind of background work goes on, with the slowest frame and
// what went on then.
struct FrameStats {
  enum Activity { Metric, Pass, Bezier, kActivities };
  // Where a frame's time went: events and the script's line, the view's
  // update (structures collected, the scene composed), drawing the scene,
  // the panels, the swap.
  enum Part { Events, Update, Draw, Panels, Swap, kParts };
  static constexpr const char* kPartNames[kParts] = {"events and script", "view update", "scene drawing", "panels (and a screenshot)",
                                                     "swap"};
  double slowest_parts[kParts] = {};
  static constexpr const char* kNames[kActivities] = {"a metric is built", "a pass runs", "the G1 surface is built"};
  int frames = 0;
  double total = 0, slowest = 0;
  std::string slowest_during;
  int active_frames[kActivities] = {};
  double active_slowest[kActivities] = {};
  bool skip_current = false;  // a reset during this frame: it is not counted

  void add(double dt, const bool (&active)[kActivities], const double (&parts)[kParts]) {
    if (skip_current) {
      skip_current = false;
      return;
    }
    ++frames;
    total += dt;
    std::string during;
    for (int i = 0; i < kActivities; ++i)
      if (active[i]) {
        ++active_frames[i];
        active_slowest[i] = std::max(active_slowest[i], dt);
        during += (during.empty() ? "" : ", ") + std::string(kNames[i]);
      }
    if (dt > slowest) {
      slowest = dt;
      slowest_during = during.empty() ? "nothing in the background" : during;
      std::copy(std::begin(parts), std::end(parts), std::begin(slowest_parts));
    }
  }
  void reset() {
    *this = FrameStats{};
    skip_current = true;
  }
  void print() const {
    std::fprintf(stderr, "frame stats: %d frames, mean %.1f ms, slowest %.1f ms (while %s)\n", frames,
                 frames ? 1000 * total / frames : 0.0, 1000 * slowest, slowest_during.c_str());
    if (frames > 0) {
      std::string parts;
      for (int i = 0; i < kParts; ++i) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%s %.0f ms", i ? ", " : "", kPartNames[i], 1000 * slowest_parts[i]);
        parts += buf;
      }
      std::fprintf(stderr, "frame stats: the slowest frame: %s\n", parts.c_str());
    }
    for (int i = 0; i < kActivities; ++i)
      if (active_frames[i] > 0)
        std::fprintf(stderr, "frame stats: while %s: %d frames, slowest %.1f ms\n", kNames[i], active_frames[i],
                     1000 * active_slowest[i]);
  }
};

struct GlfwLib {
  GlfwLib() {
    if (!glfwInit()) {
      const char* d = std::getenv("DISPLAY");
      throw render::GlError(std::string("cannot open a window") +
                            (d && *d ? "" : " (no DISPLAY: use anisurf --script FILE --headless, or xvfb-run)"));
    }
  }
  ~GlfwLib() { glfwTerminate(); }
};

}  // namespace

int run_editor_window(const std::string& mesh, const std::string& sol, const ScriptOptions& o) {
  std::vector<ScriptLine> script;
  if (!o.script.empty()) script = read_script(o.script);
  GlfwLib glfw;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "anisurf editor", nullptr, nullptr);
  if (!window) throw render::GlError("cannot create an OpenGL 3.3 core window");
  struct WindowGuard {
    GLFWwindow* w;
    ~WindowGuard() { glfwDestroyWindow(w); }
  } guard{window};
  glfwMakeContextCurrent(window);
  auto missing = gl::load_gl(reinterpret_cast<gl::GetProcAddress>(&glfwGetProcAddress));
  if (!missing.empty()) throw render::GlError("the window's OpenGL lacks " + missing.front());
  glfwSwapInterval(1);

  App a;
  a.panels.view = &a.ev;
  glfwSetWindowUserPointer(window, &a);
  glfwSetMouseButtonCallback(window, on_mouse_button);
  glfwSetCursorPosCallback(window, on_cursor);
  glfwSetScrollCallback(window, on_scroll);
  glfwSetDropCallback(window, on_drop);
  glfwSetWindowCloseCallback(window, on_close);

  render::Renderer renderer;
  render::ImGuiSession imgui;
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  glfwSetKeyCallback(window, on_key_event);  // after ImGui's: it passes keys on itself
  struct BackendGuard {
    ~BackendGuard() {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
    }
  } backends;

  // The autosave: this launch's own file; the others' are listed (the
  // oldest beyond 20 pruned) and the newest is offered.
  const std::string autosave_directory = autosave_dir();
  Autosave autosave(autosave_directory, std::time(nullptr), static_cast<long>(::getpid()));
  std::error_code dir_ec;
  std::filesystem::file_time_type listed_at{};
  auto list_others = [&] {
    a.panels.autosaves = list_autosaves(autosave_directory, autosave.path());
    listed_at = std::filesystem::last_write_time(autosave_directory, dir_ec);
  };
  if (script.empty()) {
    load_recent(a.panels);
    prune_autosaves(autosave_directory, 20);
    list_others();
    // The newest, when it holds unsaved work (a session that ended saved
    // is only listed).
    if (!a.panels.autosaves.empty() && a.panels.autosaves.front().unsaved > 0) {
      const AutosaveEntry& e = a.panels.autosaves.front();
      a.panels.offer = e;
      std::fprintf(stderr, "anisurf: offering the autosave of an earlier session: %s (%s)\n", e.path.c_str(),
                   e.describe().c_str());
    }
  }
  if (!mesh.empty()) {
    a.session.open(mesh, sol);
    a.panels.open_path = mesh;
    a.panels.open_sol = sol;
    remember_recent(a.panels, mesh + (sol.empty() ? "" : "|" + sol));
  }
  std::size_t next_line = 0;
  std::string pending_shot;
  int exit_code = 0;
  bool quit = false;
  ScriptHost host;
  host.screenshot = [&](const std::string& p) { pending_shot = p; };
  host.quit = [&] { quit = true; };
  FrameStats frame_stats;
  host.frame_stats = [&](bool reset) { reset ? frame_stats.reset() : frame_stats.print(); };
  // As the Metric panel: built in the background, the next line played once installed.
  host.set_settings = [&](const MetricSettings& m) { a.session.request_metric(m, true); };
  const ScriptLine* metric_line = nullptr;  // the line whose metric is being built
  a.panels.screenshot = [&](const std::string& p) { pending_shot = p; };
  host.click = [&](float x, float y) { a.panels.click = glm::vec2(x, y); };
  host.show_keys = [&](bool on) { a.panels.show_keys = on; };
  auto last_autosave = Clock::now();

  // Frame statistics while the adaptation runs (the responsiveness measure).
  int run_frames = 0;
  double run_seconds = 0, run_worst = 0;
  Clock::time_point run_start;
  bool was_running = false;
  std::size_t runs_seen = 0;
  const Snapshot* shown_at_start = nullptr;
  double first_shown = -1;  // seconds from the start of a run to the first frame showing a pass
  bool awaiting_first = false;
  float fps_frames = 0;
  auto fps_start = Clock::now();
  const auto budget = std::chrono::duration<double>(1.0 / std::max(o.max_fps, 1.0));
  int shots_waiting_frames = 0;

  for (int frame = 0; !glfwWindowShouldClose(window) && !quit; ++frame) {
    const auto frame_start = Clock::now();
    const bool busy = a.session.running() || a.session.measuring() || a.session.metric_building() ||
                      a.ev.bezier_building() || !a.ev.settled(a.session, a.view) || next_line < script.size() ||
                      !pending_shot.empty() || !renderer.last_frame().complete;
    release_held_keys(window, a);
    // Measured frames never wait for events (the wait would count as work).
    if (!busy && !o.frame_stats && frame_start - a.last_event > std::chrono::seconds(1))
      glfwWaitEventsTimeout(0.25);
    else
      glfwPollEvents();
    apply_key_commands(window, a);
    open_dropped(a);
    a.session.poll();
    if (a.panels.quit_confirmed) glfwSetWindowShouldClose(window, GLFW_TRUE);

    // The script: the next line once the adaptation is idle, the metric of
    // the last metric line installed, the G1 surface asked for built and the
    // last screenshot written.
    if (metric_line && !a.session.metric_building()) {
      if (const std::string err = a.session.apply_error(); !err.empty()) {
        std::cerr << "anisurf: " << metric_line->where() << ": " << metric_line->words[0] << ": " << err << "\n";
        exit_code = 1;
        break;
      }
      metric_line = nullptr;
    }
    const bool shown_latest = a.ev.shown() == a.session.display().snapshot.get();
    const bool background_done = !metric_line && (a.view.bezier == 0 || a.ev.bezier_current(a.view));
    if (next_line < script.size() && !a.session.running() && pending_shot.empty() && shown_latest && background_done) {
      const ScriptLine& line = script[next_line++];
      try {
        if (const std::string err = a.session.adaptation_error(); !err.empty()) throw Error(err);
        execute(line, a.session, a.view, host);
        if (a.session.metric_building()) metric_line = &line;
        if (line.words[0] == "open") {
          a.panels.open_path = line.words[1];
          a.panels.draft.valid = false;
        }
      } catch (const std::exception& e) {
        std::cerr << "anisurf: " << e.what() << "\n";
        exit_code = 1;
        break;
      }
      if (!pending_shot.empty()) shots_waiting_frames = 3;  // let panels settle first
    }

    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window, &fbw, &fbh);
    if (fbw <= 0 || fbh <= 0) continue;
    const float aspect = static_cast<float>(fbw) / static_cast<float>(fbh);
    if (frame == 3 && !a.view.frame_selection) a.view.fit_request = true;  // panel widths known now
    const auto t_events = Clock::now();
    a.ev.update(a.session, a.view, a.scene, aspect, a.ui.left_reserve(fbw), a.ui.right_reserve(fbw));
    a.ev.size_markers(a.scene, fbw, fbh);
    const auto t_update = Clock::now();
    // Hover: the element under the mouse (not while dragging, nor while a
    // script plays: its screenshots show no tooltip).
    a.panels.hover.reset();
    if (next_line >= script.size() && !a.rotating && !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId | ImGuiPopupFlags_AnyPopupLevel) && frame_start - a.last_event < std::chrono::seconds(2)) {
      int ww = 1, wh = 1;
      glfwGetWindowSize(window, &ww, &wh);
      a.panels.hover = a.ev.hover(a.scene, static_cast<float>(a.mx * fbw / ww), static_cast<float>(a.my * fbh / wh), fbw, fbh);
    }
    // One sample per pixel while the adaptation runs; the renderer's level of
    // detail while the camera moves.
    const bool camera_moving = a.rotating || a.panning;
    renderer.render(a.scene, fbw, fbh,
                    render::DrawOptions{a.session.running() ? 1 : a.scene.display.msaa_samples, camera_moving,
                                        render::kInteractiveTriangleBudget});
    const auto t_draw = Clock::now();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    draw_panels(a.session, a.view, a.panels, a.scene, a.ui, fbw, fbh);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    // A screenshot waits for the distance colours of the state shown.
    if (!pending_shot.empty() && renderer.last_frame().complete && a.ev.settled(a.session, a.view) && (!a.session.has_mesh() || a.session.analysis_current()) &&
        --shots_waiting_frames <= 0) {
      render::Image img(fbw, fbh);
      gl::glPixelStorei(GL_PACK_ALIGNMENT, 1);
      gl::glReadPixels(0, 0, fbw, fbh, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
      img.flip_rows();
      for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
      try {
        render::write_png(pending_shot, img);
        std::fprintf(stderr, "screenshot %s (%dx%d)\n", pending_shot.c_str(), fbw, fbh);
        a.panels.message = "wrote " + pending_shot;
        a.panels.message_is_error = false;
      } catch (const std::exception& e) {
        a.panels.message = e.what();
        a.panels.message_is_error = true;
      }
      pending_shot.clear();
    }
    const auto t_panels = Clock::now();
    glfwSwapBuffers(window);

    // Statistics and autosave.
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - frame_start).count();
    const bool running = a.session.running();
    if (running && !was_running) {
      run_frames = 0;
      run_seconds = run_worst = 0;
      run_start = frame_start;
      shown_at_start = a.ev.shown();
      first_shown = -1;
      awaiting_first = true;
    }
    if (awaiting_first && a.ev.shown() != shown_at_start) {
      first_shown = std::chrono::duration<double>(now - run_start).count();
      awaiting_first = false;
      std::fprintf(stderr,
                   "adaptation: first pass on screen %.3f s after the start (the remesher's setup %.3f s, its pass %.3f s, "
                   "its snapshot %.3f s, the view's structure %.3f s)\n",
                   first_shown, a.session.last_setup_seconds(),
                   a.ev.shown() && a.ev.shown()->has_report ? a.ev.shown()->report.seconds : 0.0,
                   a.session.last_snapshot_seconds(), a.ev.last_build_seconds());
    }
    if (running) {
      ++run_frames;
      run_worst = std::max(run_worst, dt);
    }
    const bool active[FrameStats::kActivities] = {a.session.metric_building(), running, a.ev.bezier_building()};
    using Seconds = std::chrono::duration<double>;
    const double parts[FrameStats::kParts] = {Seconds(t_events - frame_start).count(), Seconds(t_update - t_events).count(),
                                              Seconds(t_draw - t_update).count(), Seconds(t_panels - t_draw).count(),
                                              Seconds(now - t_panels).count()};
    frame_stats.add(dt, active, parts);
    if (!running && was_running) {
      if (const auto asked = a.session.stop_requested())
        std::fprintf(stderr, "adaptation: stopped %.3f s after the pause or cancel was asked\n",
                     std::chrono::duration<double>(now - *asked).count());
      run_seconds = std::chrono::duration<double>(now - run_start).count();
      const auto tl = a.session.timeline();
      std::fprintf(stderr,
                   "adaptation: done after %.2f s (%zu passes, %zu in the timeline); the window drew %d frames (%.1f fps, slowest frame %.0f ms); "
                   "last pass %.3f s\n",
                   run_seconds, tl.size() - 1 + a.session.dropped_passes(), tl.size() - 1, run_frames, run_frames / std::max(run_seconds, 1e-9), 1000 * run_worst,
                   tl.back()->has_report ? tl.back()->report.seconds : 0.0);
    }
    if (a.session.runs_started() != runs_seen && !running && !was_running) {
      // Started and done between two frames: no frame was drawn while it ran.
      const auto tl = a.session.timeline();
      std::fprintf(stderr, "adaptation: started and done within one frame of %.0f ms (%zu passes in the timeline); its pass %.3f s\n",
                   1000 * dt, tl.size() - 1, tl.back()->has_report ? tl.back()->report.seconds : 0.0);
    }
    runs_seen = a.session.runs_started();
    was_running = running;
    ++fps_frames;
    const double since = std::chrono::duration<double>(now - fps_start).count();
    if (since >= 0.5) {
      a.panels.fps = static_cast<float>(fps_frames / since);
      fps_frames = 0;
      fps_start = now;
    }
    if (now - last_autosave > std::chrono::seconds(5) && script.empty()) {
      write_autosave(a, autosave);
      last_autosave = now;
      // Another launch added or removed an autosave: list them again.
      if (std::filesystem::last_write_time(autosave_directory, dir_ec) != listed_at) list_others();
    }
    // While the adaptation runs the frame rate is capped lower (15 fps keeps
    // the window responsive and leaves the worker most of the machine).
    const auto cap = running ? std::max(budget, std::chrono::duration<double>(1.0 / 15.0)) : budget;
    std::this_thread::sleep_until(frame_start + std::chrono::duration_cast<Clock::duration>(cap));
  }
  if (script.empty()) {
    write_autosave(a, autosave);
    save_recent(a.panels);
  }
  if (o.frame_stats) frame_stats.print();
  a.session.pause();
  a.session.wait();
  return exit_code;
}

}  // namespace anisurf::editor
