#include "render/renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "render/gpu.h"

namespace anisurf::render {

using namespace anisurf::gl;

namespace {

// Texture units.
constexpr int kUnitColormap = 0, kUnitTriangleValues = 1, kUnitTriangleColors = 2, kUnitTriangleFlags = 3;

float mapped(float v, bool log_scale) {
  if (!log_scale) return v;
  return v > 0 ? std::log(v) : NAN;
}

// GPU copy of one surface structure.
struct GpuSurface {
  std::uint64_t version = ~0ull;
  std::size_t n_corners = 0;
  Buffer corners;        // per corner: position, normal
  Buffer corner_values;  // per corner: vertex scalar
  VertexArray surface_vao;
  BufferTexture triangle_values, triangle_colors, triangle_flags;
  bool has_flags = false;
  std::string uploaded_quantity = "\x01";  // name + scale of the quantity in the buffers
  struct Instances {
    Buffer buffer;
    VertexArray vao;
    std::size_t count = 0;
  };
  std::vector<Instances> curves, markers, glyphs;
};

std::vector<glm::vec3> smooth_normals(const TriangleSet& g) {
  std::vector<glm::vec3> n(g.positions.size(), glm::vec3(0));
  for (const glm::uvec3& t : g.triangles) {
    glm::vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    glm::vec3 fn = glm::cross(b - a, c - a);  // area weighted
    n[t.x] += fn;
    n[t.y] += fn;
    n[t.z] += fn;
  }
  for (auto& v : n) {
    float l = glm::length(v);
    v = l > 0 ? v / l : glm::vec3(0, 0, 1);
  }
  return n;
}

void upload_geometry(GpuSurface& gpu, const SurfaceStructure& s) {
  const TriangleSet& g = s.geometry;
  const bool corner_normals = g.corner_normals.size() == 3 * g.triangles.size();
  std::vector<glm::vec3> vn;
  if (!corner_normals) vn = smooth_normals(g);
  std::vector<float> data;
  data.reserve(g.triangles.size() * 18);
  for (std::size_t t = 0; t < g.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      unsigned v = g.triangles[t][k];
      const glm::vec3& p = g.positions[v];
      const glm::vec3& n = corner_normals ? g.corner_normals[3 * t + static_cast<std::size_t>(k)] : vn[v];
      data.insert(data.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
    }
  gpu.n_corners = 3 * g.triangles.size();
  gpu.corners.upload(GL_ARRAY_BUFFER, data.data(), data.size() * sizeof(float));
  gpu.surface_vao.attribute(0, gpu.corners, 3, 6 * sizeof(float), 0);
  gpu.surface_vao.attribute(1, gpu.corners, 3, 6 * sizeof(float), 3 * sizeof(float));
  std::vector<float> zeros(gpu.n_corners, 0.0f);
  gpu.corner_values.upload(GL_ARRAY_BUFFER, zeros.data(), zeros.size() * sizeof(float));
  gpu.surface_vao.attribute(2, gpu.corner_values, 1, sizeof(float), 0);

  std::vector<std::uint8_t> flags(g.triangles.size(), 0);
  for (std::uint32_t t : s.highlight_triangles)
    if (t < flags.size()) flags[t] |= 1;
  gpu.has_flags = !s.highlight_triangles.empty();
  gpu.triangle_flags.upload(GL_R8UI, flags.data(), flags.size());
  // Placeholders until a quantity is uploaded (a bound buffer texture needs a store).
  gpu.triangle_values.upload(GL_R32F, nullptr, 0);
  gpu.triangle_colors.upload(GL_RGBA8, nullptr, 0);

  // Curves, markers, glyphs: instance buffers.
  gpu.curves.clear();
  for (const Curves& c : s.curves) {
    auto& inst = gpu.curves.emplace_back();
    inst.count = c.points.size() / 2;
    inst.buffer.upload(GL_ARRAY_BUFFER, c.points.data(), inst.count * 2 * sizeof(glm::vec3));
    inst.vao.attribute(0, inst.buffer, 3, 2 * sizeof(glm::vec3), 0, 1);
    inst.vao.attribute(1, inst.buffer, 3, 2 * sizeof(glm::vec3), sizeof(glm::vec3), 1);
  }
  gpu.markers.clear();
  for (const Markers& m : s.markers) {
    auto& inst = gpu.markers.emplace_back();
    inst.count = m.positions.size();
    inst.buffer.upload(GL_ARRAY_BUFFER, m.positions.data(), inst.count * sizeof(glm::vec3));
    inst.vao.attribute(0, inst.buffer, 3, sizeof(glm::vec3), 0, 1);
  }
  gpu.glyphs.clear();
  for (const EllipseGlyphs& e : s.glyphs) {
    auto& inst = gpu.glyphs.emplace_back();
    inst.count = e.centers.size();
    std::vector<glm::vec3> packed;
    packed.reserve(3 * inst.count);
    for (std::size_t i = 0; i < inst.count; ++i) packed.insert(packed.end(), {e.centers[i], e.axes_u[i], e.axes_v[i]});
    inst.buffer.upload(GL_ARRAY_BUFFER, packed.data(), packed.size() * sizeof(glm::vec3));
    for (GLuint a = 0; a < 3; ++a) inst.vao.attribute(a, inst.buffer, 3, 3 * sizeof(glm::vec3), a * sizeof(glm::vec3), 1);
  }
  gpu.uploaded_quantity.assign(1, '\x01');  // (GCC 12 flags the literal assignment: -Wrestrict false positive)
  gpu.version = s.version;
}

void upload_quantity(GpuSurface& gpu, const SurfaceStructure& s) {
  const ScalarQuantity* q = s.active_scalar();
  const LabelQuantity* l = s.active_label();
  const VertexCategories* vc = s.active_categories();
  std::string key = s.active + (q && q->log_scale ? "/log" : "");
  if (key == gpu.uploaded_quantity) return;
  gpu.uploaded_quantity = key;
  const auto& tris = s.geometry.triangles;
  if (q && q->location == ScalarLocation::Vertex) {
    std::vector<float> v(gpu.n_corners, NAN);
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        unsigned i = tris[t][k];
        if (i < q->values.size()) v[3 * t + static_cast<std::size_t>(k)] = mapped(q->values[i], q->log_scale);
      }
    gpu.corner_values.upload(GL_ARRAY_BUFFER, v.data(), v.size() * sizeof(float));
  } else if (q) {
    std::size_t n = tris.size() * (q->location == ScalarLocation::Edge ? 3 : 1);
    std::vector<float> v(n, NAN);
    for (std::size_t i = 0; i < n && i < q->values.size(); ++i) v[i] = mapped(q->values[i], q->log_scale);
    gpu.triangle_values.upload(GL_R32F, v.data(), v.size() * sizeof(float));
  } else if (l) {
    std::vector<std::uint8_t> rgba(tris.size() * 4, 128);
    for (std::size_t t = 0; t < tris.size() && t < l->triangle_labels.size(); ++t) {
      glm::vec3 c = categorical_color(l->triangle_labels[t]);
      for (int k = 0; k < 3; ++k) rgba[4 * t + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(c[k] * 255));
      rgba[4 * t + 3] = 255;
    }
    gpu.triangle_colors.upload(GL_RGBA8, rgba.data(), rgba.size());
  } else if (vc) {
    // Three colours per triangle: its corners' categories.
    std::vector<std::uint8_t> rgba(tris.size() * 12, 140);
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const unsigned i = tris[t][k];
        const int c = i < vc->values.size() ? vc->values[i] : -1;
        std::uint8_t* px = &rgba[12 * t + 4 * static_cast<std::size_t>(k)];
        if (c >= 0 && c < static_cast<int>(vc->categories.size()))
          for (int j = 0; j < 3; ++j)
            px[j] = static_cast<std::uint8_t>(std::lround(std::clamp(vc->categories[static_cast<std::size_t>(c)].color[j], 0.0f, 1.0f) * 255));
        px[3] = 255;
      }
    gpu.triangle_colors.upload(GL_RGBA8, rgba.data(), rgba.size());
  }
}

}  // namespace

struct Renderer::Impl {
  Program surface{"surface.vert", "surface.frag"};
  Program curves{"curves.vert", "curves.frag"};
  Program markers{"markers.vert", "markers.frag"};
  Program glyphs{"glyphs.vert", "glyphs.frag"};
  std::map<Colormap, Texture2D> colormaps;
  std::map<std::string, GpuSurface> cache;
  RenderTarget target;

  const Texture2D& colormap(Colormap c) {
    auto it = colormaps.find(c);
    if (it != colormaps.end()) return it->second;
    auto px = colormap_rgba8(c, 256);
    Texture2D& tex = colormaps[c];
    tex.upload_rgba8(256, 1, px.data(), true);
    return tex;
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  // Dummy textures so every sampler has a complete texture bound.
  for (auto c : {Colormap::Viridis, Colormap::Coolwarm}) impl_->colormap(c);
  check_gl("Renderer setup");
}

Renderer::~Renderer() = default;

void Renderer::clear_cache() { impl_->cache.clear(); }

void Renderer::draw(const Scene& scene, int width, int height, int samples) {
  Impl& r = *impl_;
  const DisplayOptions& d = scene.display;
  r.target.ensure(width, height, std::max(1, samples > 0 ? samples : d.msaa_samples));
  r.target.bind();
  glViewport(0, 0, width, height);
  glClearColor(d.background.r, d.background.g, d.background.b, 1.0f);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);

  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const Camera& cam = scene.camera;
  const glm::mat4 view = cam.view(), proj = cam.projection(aspect);
  const glm::vec2 viewport(width, height);
  const int ortho = cam.orthographic ? 1 : 0;
  const float lift = cam.scene_radius * 2e-3f;

  for (const SurfaceStructure& s : scene.surfaces) {
    if (!s.enabled || s.geometry.triangles.empty()) continue;
    GpuSurface& gpu = r.cache[s.name];
    if (gpu.version != s.version) upload_geometry(gpu, s);
    upload_quantity(gpu, s);

    // Surface.
    Program& p = r.surface;
    p.use();
    p.set("u_view", view);
    p.set("u_projection", proj);
    p.set("u_base_color", s.color);
    p.set("u_flat", d.flat ? 1 : 0);
    p.set("u_wireframe", d.wireframe ? 1 : 0);
    p.set("u_wire_width", d.wire_width_px);
    p.set("u_wire_color", d.wire_color);
    p.set("u_highlight_color", d.highlight_color);
    p.set("u_orthographic", ortho);
    p.set("u_has_flags", gpu.has_flags ? 1 : 0);
    p.set("u_colormap", kUnitColormap);
    p.set("u_triangle_values", kUnitTriangleValues);
    p.set("u_triangle_colors", kUnitTriangleColors);
    p.set("u_triangle_flags", kUnitTriangleFlags);
    int mode = 0;
    r.colormap(Colormap::Viridis).bind(kUnitColormap);
    if (const ScalarQuantity* q = s.active_scalar()) {
      mode = q->location == ScalarLocation::Vertex ? 1 : q->location == ScalarLocation::Triangle ? 2 : 3;
      p.set("u_range", glm::vec2(mapped(q->range_min, q->log_scale), mapped(q->range_max, q->log_scale)));
      r.colormap(q->colormap).bind(kUnitColormap);
    } else if (s.active_label()) {
      mode = 4;
    } else if (s.active_categories()) {
      mode = 5;
    }
    p.set("u_color_mode", mode);
    gpu.triangle_values.bind(kUnitTriangleValues);
    gpu.triangle_colors.bind(kUnitTriangleColors);
    gpu.triangle_flags.bind(kUnitTriangleFlags);
    // Push the surface back a little so lines on it win the depth test.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    gpu.surface_vao.bind();
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(gpu.n_corners));
    glDisable(GL_POLYGON_OFFSET_FILL);

    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);

    // Glyphs (translucent fill: no depth writes).
    glDepthMask(GL_FALSE);
    for (std::size_t i = 0; i < s.glyphs.size() && i < gpu.glyphs.size(); ++i) {
      const EllipseGlyphs& e = s.glyphs[i];
      std::size_t n = std::min(e.drawn_count(), gpu.glyphs[i].count);
      if (!e.enabled || n == 0) continue;
      Program& g = r.glyphs;
      g.use();
      g.set("u_view", view);
      g.set("u_projection", proj);
      g.set("u_scale", e.scale);
      g.set("u_lift", 0.2f);
      g.set("u_orthographic", ortho);
      // Over a colour quantity: light glyphs with dark outlines.
      g.set("u_color", s.active.empty() ? e.color : glm::vec3(0.97f));
      gpu.glyphs[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(n));
    }
    glDepthMask(GL_TRUE);

    // Curves, then markers on top of them.
    for (std::size_t i = 0; i < s.curves.size() && i < gpu.curves.size(); ++i) {
      const Curves& c = s.curves[i];
      if (!c.enabled || gpu.curves[i].count == 0) continue;
      Program& g = r.curves;
      g.use();
      g.set("u_view", view);
      g.set("u_projection", proj);
      g.set("u_viewport", viewport);
      g.set("u_width", c.width_px);
      g.set("u_lift", lift);
      g.set("u_orthographic", ortho);
      g.set("u_color", c.color);
      gpu.curves[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(gpu.curves[i].count));
    }
    for (std::size_t i = 0; i < s.markers.size() && i < gpu.markers.size(); ++i) {
      const Markers& m = s.markers[i];
      if (!m.enabled || gpu.markers[i].count == 0) continue;
      Program& g = r.markers;
      g.use();
      g.set("u_view", view);
      g.set("u_projection", proj);
      g.set("u_viewport", viewport);
      g.set("u_radius", m.radius_px);
      g.set("u_lift", 2.0f * lift);
      g.set("u_orthographic", ortho);
      g.set("u_color", m.color);
      gpu.markers[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(gpu.markers[i].count));
    }
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  check_gl("Renderer::draw");
}

void Renderer::present() {
  impl_->target.resolve(0);
  glViewport(0, 0, impl_->target.width(), impl_->target.height());
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  check_gl("Renderer::present");
}

}  // namespace anisurf::render
