#include "render/viewer.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "render/gl.h"
#include "render/gpu.h"
#include "render/image.h"
#include "render/renderer.h"

namespace anisurf::render {

namespace {

using Clock = std::chrono::steady_clock;

struct GlfwLibrary {
  GlfwLibrary() {
    glfwSetErrorCallback([](int code, const char* msg) { last_error() = msg ? msg : "?"; });
    if (!glfwInit()) {
      const char* display = std::getenv("DISPLAY");
      throw GlError("cannot open a window: " + last_error() +
                    (display && *display ? "" : " (no DISPLAY: use `anisurf shot` for pictures without a display, "
                                                "or run under xvfb-run)"));
    }
  }
  ~GlfwLibrary() { glfwTerminate(); }
  static std::string& last_error() {
    static std::string e;
    return e;
  }
};

// What the callbacks change (reached through the window's user pointer).
struct Input {
  Scene* scene = nullptr;
  UiState* ui = nullptr;
  double last_x = 0, last_y = 0;
  bool rotating = false, panning = false;
  bool screenshot = false;
  Clock::time_point last_event = Clock::now();
  Clock::time_point last_wheel = Clock::time_point();
  bool camera_touched = false;  // by a drag, the wheel or a view key
};

Input& input_of(GLFWwindow* w) { return *static_cast<Input*>(glfwGetWindowUserPointer(w)); }

void on_mouse_button(GLFWwindow* w, int button, int action, int mods) {
  Input& in = input_of(w);
  in.last_event = Clock::now();
  if (action == GLFW_PRESS && ImGui::GetIO().WantCaptureMouse) return;
  glfwGetCursorPos(w, &in.last_x, &in.last_y);
  bool press = action == GLFW_PRESS;
  if (button == GLFW_MOUSE_BUTTON_LEFT && !(mods & GLFW_MOD_SHIFT)) in.rotating = press;
  if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE ||
      (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)))
    in.panning = press;
  if (!press) in.rotating = in.panning = false;
}

void on_cursor(GLFWwindow* w, double x, double y) {
  Input& in = input_of(w);
  in.last_event = Clock::now();
  double dx = x - in.last_x, dy = y - in.last_y;
  in.last_x = x;
  in.last_y = y;
  int ww = 1, wh = 1;
  glfwGetWindowSize(w, &ww, &wh);
  Camera& cam = in.scene->camera;
  in.camera_touched |= in.rotating || in.panning;
  if (in.rotating) cam.orbit(static_cast<float>(-dx / wh * 3.0), static_cast<float>(dy / wh * 3.0));
  if (in.panning) cam.pan(static_cast<float>(dx / wh), static_cast<float>(-dy / wh));
}

void on_scroll(GLFWwindow* w, double, double dy) {
  Input& in = input_of(w);
  in.last_event = Clock::now();
  if (ImGui::GetIO().WantCaptureMouse) return;
  in.last_wheel = in.last_event;
  in.camera_touched = true;
  in.scene->camera.zoom(static_cast<float>(std::pow(0.88, dy)));
}

void on_key(GLFWwindow* w, int key, int, int action, int mods) {
  Input& in = input_of(w);
  in.last_event = Clock::now();
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  Scene& s = *in.scene;
  in.camera_touched = true;
  auto view = [&](NamedView v) {
    s.camera.set_view(v);
    in.ui->fit_requested = true;
  };
  switch (key) {
    case GLFW_KEY_1: view(NamedView::Iso); break;
    case GLFW_KEY_2: view(NamedView::Front); break;
    case GLFW_KEY_3: view(NamedView::Back); break;
    case GLFW_KEY_4: view(NamedView::Left); break;
    case GLFW_KEY_5: view(NamedView::Right); break;
    case GLFW_KEY_6: view(NamedView::Top); break;
    case GLFW_KEY_7: view(NamedView::Bottom); break;
    case GLFW_KEY_F: in.ui->fit_requested = true; break;
    case GLFW_KEY_O:
      s.camera.orthographic = !s.camera.orthographic;
      in.ui->fit_requested = true;
      break;
    case GLFW_KEY_W: s.display.wireframe = !s.display.wireframe; break;
    case GLFW_KEY_S: s.display.flat = !s.display.flat; break;
    case GLFW_KEY_G:
      for (auto& st : s.surfaces)
        for (auto& g : st.glyphs) g.enabled = !g.enabled;
      break;
    case GLFW_KEY_H: in.ui->show_panel = !in.ui->show_panel; break;
    case GLFW_KEY_P: in.screenshot = true; break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
    default: break;
  }
  (void)mods;
}

// What the benchmark's frames drew (the LOD that was active).
struct BenchStats {
  int frames = 0, proxy_frames = 0;
  FrameInfo first;

  void add(const FrameInfo& f) {
    if (frames++ == 0) first = f;
    proxy_frames += f.proxies > 0 ? 1 : 0;
  }
  std::string describe(const Scene& scene) const {
    std::size_t full = 0;
    for (const auto& st : scene.surfaces) full += st.enabled ? st.geometry.triangles.size() : 0;
    char text[256];
    std::snprintf(text, sizeof text, "%zu triangles; drawn at %dx%d, %d sample%s per pixel, %zu triangles%s",
                  full, first.width, first.height, first.samples, first.samples == 1 ? "" : "s", first.triangles,
                  proxy_frames == 0 ? ", no proxy" : "");
    std::string out = text;
    if (proxy_frames > 0) out += " through a proxy on " + std::to_string(proxy_frames) + " of " + std::to_string(frames) + " frames";
    return out;
  }
};

}  // namespace

const char* viewer_keys() {
  return "  mouse: left drag orbit, right drag (or shift + left) pan, wheel zoom\n"
         "  keys:  1 iso  2 front  3 back  4 left  5 right  6 top  7 bottom  F fit\n"
         "         O orthographic/perspective  W wireframe  S flat/smooth  G glyphs\n"
         "         H hide/show the panel  P screenshot (anisurf-view.png)  Q/Esc quit\n";
}

void run_viewer(Scene& scene, UiState& ui, const ViewerOptions& options) {
  GlfwLibrary glfw;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (!window) throw GlError("cannot create an OpenGL 3.3 core window: " + GlfwLibrary::last_error());
  struct WindowGuard {
    GLFWwindow* w;
    ~WindowGuard() { glfwDestroyWindow(w); }
  } guard{window};
  glfwMakeContextCurrent(window);
  auto missing = gl::load_gl(reinterpret_cast<gl::GetProcAddress>(&glfwGetProcAddress));
  if (!missing.empty()) throw GlError("the window's OpenGL lacks " + missing.front() + ": OpenGL 3.3 core is required");
  glfwSwapInterval(options.bench_orbit_frames > 0 ? 0 : 1);

  Input input;
  input.scene = &scene;
  input.ui = &ui;
  glfwSetWindowUserPointer(window, &input);
  glfwSetMouseButtonCallback(window, on_mouse_button);
  glfwSetCursorPosCallback(window, on_cursor);
  glfwSetScrollCallback(window, on_scroll);
  glfwSetKeyCallback(window, on_key);

  Renderer renderer;
  ImGuiSession imgui;
  // ImGui's GLFW backend chains to the callbacks installed above.
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  struct BackendGuard {
    ~BackendGuard() {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
    }
  } backends;

  int fbw = 0, fbh = 0;
  glfwGetFramebufferSize(window, &fbw, &fbh);
  scene.fit_camera(static_cast<float>(fbw) / std::max(fbh, 1));

  const bool bench = options.bench_orbit_frames > 0;
  const float start_yaw = scene.camera.yaw;
  const auto frame_budget = std::chrono::duration<double>(1.0 / std::max(options.max_fps, 1.0));
  auto bench_start = Clock::now();
  auto fps_start = Clock::now();
  int fps_frames = 0;
  BenchStats bench_stats;
  for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
    auto frame_start = Clock::now();
    // Idle (nothing happened for a second): wait for events instead of
    // redrawing the same picture.
    const bool idle = !bench && frame_start - input.last_event > std::chrono::seconds(1) && renderer.last_frame().complete;
    if (idle)
      glfwWaitEventsTimeout(0.5);
    else
      glfwPollEvents();
    // The widths of the legend and the panel are known after the first
    // frames: fit again to keep their strips free, unless the user moved the
    // camera already.
    if (frame == 3 && !bench && (ui.legend_width > 0 || ui.panel_width > 0) && !input.camera_touched)
      ui.fit_requested = true;
    glfwGetFramebufferSize(window, &fbw, &fbh);
    if (fbw <= 0 || fbh <= 0) continue;  // minimised
    if (ui.fit_requested) {
      scene.fit_camera(static_cast<float>(fbw) / static_cast<float>(fbh), ui.left_reserve(fbw), ui.right_reserve(fbw));
      ui.fit_requested = false;
    }
    if (bench) {
      // Frame 0 uploads the buffers and starts the proxies; it is repeated
      // until they are built (the warm-up), then the timing starts.
      if (frame == 1 && renderer.proxies_pending() && Clock::now() - bench_start < std::chrono::seconds(120)) {
        frame = 0;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      if (frame == 1) bench_start = Clock::now();
      if (frame == options.bench_orbit_frames + 1) break;
      scene.camera.yaw = start_yaw + 6.2831853f * static_cast<float>(frame) / options.bench_orbit_frames;
    }
    // While the camera moves: half resolution, one sample per pixel, proxies
    // of large surfaces; the still picture is redrawn in full detail.
    const bool moving = (bench && !options.bench_full_detail) || input.rotating || input.panning ||
                        Clock::now() - input.last_wheel < std::chrono::milliseconds(300);
    // Still pictures larger than the budget are drawn over several frames
    // (the benchmark's full-detail frames in one each).
    const std::size_t budget = bench ? 0 : kInteractiveTriangleBudget;
    renderer.render(scene, fbw, fbh, DrawOptions{scene.display.msaa_samples, moving, budget});
    if (bench && frame > 0) bench_stats.add(renderer.last_frame());
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    draw_ui(scene, ui, fbw, fbh);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (input.screenshot) {
      input.screenshot = false;
      Image img(fbw, fbh);
      gl::glPixelStorei(GL_PACK_ALIGNMENT, 1);
      gl::glReadPixels(0, 0, fbw, fbh, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
      img.flip_rows();
      for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
      write_png("anisurf-view.png", img);
      std::fprintf(stderr, "view: wrote anisurf-view.png (%dx%d)\n", fbw, fbh);
    }
    glfwSwapBuffers(window);

    ++fps_frames;
    double since = std::chrono::duration<double>(Clock::now() - fps_start).count();
    if (idle) {  // waiting for events: the rate says nothing; keep the last one
      fps_frames = 0;
      fps_start = Clock::now();
    } else if (since >= 0.5) {
      ui.fps = static_cast<float>(fps_frames / since);
      fps_frames = 0;
      fps_start = Clock::now();
    }
    if (!bench) std::this_thread::sleep_until(frame_start + std::chrono::duration_cast<Clock::duration>(frame_budget));
  }
  if (bench) {
    gl::glFinish();
    double s = std::chrono::duration<double>(Clock::now() - bench_start).count();
    std::printf("orbit: %d frames in %.2f s = %.1f fps (%dx%d window, %s; %s)\n", options.bench_orbit_frames, s,
                options.bench_orbit_frames / s, fbw, fbh, bench_stats.describe(scene).c_str(),
                gl::gl_description().c_str());
  }
}

}  // namespace anisurf::render
