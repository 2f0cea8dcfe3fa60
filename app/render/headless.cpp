#include "render/headless.h"

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include "render/gl.h"
#include "render/gpu.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"

namespace anisurf::render {

using namespace anisurf::gl;

struct HeadlessRenderer::Impl {
  OffscreenContext context;
  Renderer renderer;
  ImGuiSession imgui;
  bool backend = false;
  Impl(int w, int h) : context(w, h) {
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) throw GlError("Dear ImGui's OpenGL3 backend failed to start");
    backend = true;
  }
  ~Impl() {
    if (backend) ImGui_ImplOpenGL3_Shutdown();
  }
};

HeadlessRenderer::HeadlessRenderer(int width, int height) : impl_(std::make_unique<Impl>(width, height)) {}

HeadlessRenderer::~HeadlessRenderer() = default;

std::string HeadlessRenderer::description() const { return gl::gl_description(); }

void HeadlessRenderer::layout_ui(Scene& scene, UiState& ui, int width, int height, int ui_frames) {
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
  io.DeltaTime = 1.0f / 60.0f;
  io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
  for (int f = 0; f < std::max(ui_frames, 1); ++f) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    draw_ui(scene, ui, width, height);
    ImGui::Render();
  }
}

Image HeadlessRenderer::render(Scene& scene, UiState& ui, int width, int height, int ui_frames) {
  return render(scene, [&](int w, int h) { draw_ui(scene, ui, w, h); }, width, height, ui_frames);
}

Image HeadlessRenderer::render(Scene& scene, const std::function<void(int, int)>& ui, int width, int height,
                               int ui_frames) {
  if (impl_->context.width() != width || impl_->context.height() != height) impl_->context.resize(width, height);
  impl_->renderer.draw(scene, width, height);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
  io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
  io.DeltaTime = 1.0f / 60.0f;  // fixed: no time dependence in the output
  io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
  for (int f = 0; f < std::max(ui_frames, 1); ++f) {
    impl_->renderer.present();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    ui(width, height);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
  glFinish();
  Image img(width, height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  check_gl("reading the picture back");
  img.flip_rows();
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;  // opaque PNG
  return img;
}

}  // namespace anisurf::render
