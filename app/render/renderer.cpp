#include "render/renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <optional>
#include <type_traits>

#include "render/gpu.h"
#include "render/lod.h"

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

// A proxy of one surface for the frames drawn while the camera moves, built
// by a background job from a copy of the surface's triangles.
struct SurfaceLod {
  std::future<ProxyMesh> job;
  std::uint64_t job_version = 0;       // the surface's version the job works on
  std::uint64_t version = ~0ull;       // the surface's version `structure` stands for
  std::optional<SurfaceStructure> structure;
  GpuSurface gpu;
};

// Starts the proxy's job for the surface's current version, unless one runs.
void start_proxy_job(SurfaceLod& lod, const SurfaceStructure& s) {
  if (lod.job.valid()) return;
  TriangleSet copy{s.geometry.positions, s.geometry.triangles, {}};
  lod.job_version = s.version;
  lod.job = std::async(std::launch::async,
                       [g = std::move(copy)] { return make_proxy(g, kProxyMaxTriangles); });
}

// The proxy structure for the surface's current version, once its job is
// done (nullptr before); starts or restarts the job as needed.
const SurfaceStructure* ready_proxy(SurfaceLod& lod, const SurfaceStructure& s) {
  using namespace std::chrono_literals;
  if (lod.job.valid() && lod.job.wait_for(0s) == std::future_status::ready) {
    ProxyMesh proxy = lod.job.get();
    if (lod.job_version == s.version) {
      lod.structure = proxy_structure(s, proxy);
      lod.version = s.version;
      upload_geometry(lod.gpu, *lod.structure);
    }
  }
  if (lod.version != s.version) {
    start_proxy_job(lod, s);
    return nullptr;
  }
  // Toggles that change without a new version follow the full structure.
  lod.structure->active = s.active;
  for (std::size_t i = 0; i < s.scalars.size() && i < lod.structure->scalars.size(); ++i)
    lod.structure->scalars[i].log_scale = s.scalars[i].log_scale;
  return &*lod.structure;
}

// The bytes of everything a frame's picture depends on besides the data a
// structure's version covers: equal bytes, equal pictures.
class FrameKey {
 public:
  template <class T>
  void add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const unsigned char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void add(const std::string& text) {
    add(text.size());
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

void add_surface(FrameKey& key, const SurfaceStructure& s, bool through_proxy) {
  key.add(s.name);
  key.add(s.enabled);
  key.add(s.version);
  key.add(s.geometry.triangles.size());
  key.add(through_proxy);
  key.add(s.active);
  key.add(s.color);
  if (const ScalarQuantity* q = s.active_scalar()) {
    key.add(q->range_min);
    key.add(q->range_max);
    key.add(q->log_scale);
    key.add(q->colormap);
  }
  for (const EllipseGlyphs& e : s.glyphs) {
    key.add(e.enabled);
    key.add(e.density);
    key.add(e.scale);
    key.add(e.color);
  }
  for (const Curves& c : s.curves) {
    key.add(c.enabled);
    key.add(c.width_px);
    key.add(c.color);
  }
  for (const Markers& m : s.markers) {
    key.add(m.enabled);
    key.add(m.radius_px);
    key.add(m.color);
  }
}

std::vector<unsigned char> frame_key(const Scene& scene, int width, int height, int samples, bool moving,
                                     const std::vector<bool>& through_proxy) {
  FrameKey key;
  key.add(width);
  key.add(height);
  key.add(samples);
  key.add(moving);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  key.add(scene.camera.view());
  key.add(scene.camera.projection(aspect));
  key.add(scene.camera.orthographic);
  key.add(scene.camera.scene_radius);
  const DisplayOptions& d = scene.display;
  key.add(d.flat);
  key.add(d.wireframe);
  key.add(d.wire_width_px);
  key.add(d.wire_color);
  key.add(d.highlight_color);
  key.add(d.background);
  key.add(scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) add_surface(key, scene.surfaces[i], through_proxy[i]);
  return key.bytes();
}

// Picture size while the camera moves: this fraction of the output's.
constexpr float kMovingScale = 0.5f;

}  // namespace

struct Renderer::Impl {
  Program surface{"surface.vert", "surface.frag"};
  Program curves{"curves.vert", "curves.frag"};
  Program markers{"markers.vert", "markers.frag"};
  Program glyphs{"glyphs.vert", "glyphs.frag"};
  std::map<Colormap, Texture2D> colormaps;
  std::map<std::string, GpuSurface> cache;
  std::map<std::string, SurfaceLod> lods;
  RenderTarget target;
  int output_width = 0, output_height = 0;
  std::vector<unsigned char> drawn_key;  // frame_key() of the picture in `target`
  FrameInfo last;

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

void Renderer::clear_cache() {
  impl_->cache.clear();
  impl_->lods.clear();
  impl_->drawn_key.clear();
}

const FrameInfo& Renderer::last_frame() const { return impl_->last; }

bool Renderer::proxies_pending() const {
  for (const auto& [name, lod] : impl_->lods)
    if (lod.job.valid()) return true;
  return false;
}

void Renderer::draw(const Scene& scene, int width, int height, const DrawOptions& options) {
  Impl& r = *impl_;
  const DisplayOptions& d = scene.display;
  const bool moving = options.camera_moving;
  const float pixel_scale = moving ? kMovingScale : 1.0f;
  const int samples = moving ? 1 : std::max(1, options.samples > 0 ? options.samples : d.msaa_samples);
  const int target_width = std::max(1, static_cast<int>(std::lround(static_cast<float>(width) * pixel_scale)));
  const int target_height = std::max(1, static_cast<int>(std::lround(static_cast<float>(height) * pixel_scale)));
  r.output_width = width;
  r.output_height = height;

  // Proxies first: whether one is ready is part of what the picture shows.
  std::vector<const SurfaceStructure*> proxies(scene.surfaces.size(), nullptr);
  std::vector<bool> through_proxy(scene.surfaces.size(), false);
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const SurfaceStructure& s = scene.surfaces[i];
    if (!moving || !s.enabled || s.geometry.triangles.size() <= kProxyMinTriangles) continue;
    proxies[i] = ready_proxy(r.lods[s.name], s);
    through_proxy[i] = proxies[i] != nullptr;
  }
  std::vector<unsigned char> key = frame_key(scene, width, height, samples, moving, through_proxy);
  if (key == r.drawn_key && r.target.width() == target_width && r.target.height() == target_height) {
    r.last.redrawn = false;
    return;
  }
  r.drawn_key = std::move(key);
  r.last = FrameInfo{true, target_width, target_height, samples, 0, 0};

  r.target.ensure(target_width, target_height, samples);
  r.target.bind();
  glViewport(0, 0, target_width, target_height);
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
  const glm::vec2 viewport(target_width, target_height);
  const int ortho = cam.orthographic ? 1 : 0;
  const float lift = cam.scene_radius * 2e-3f;

  for (std::size_t si = 0; si < scene.surfaces.size(); ++si) {
    const SurfaceStructure& s = scene.surfaces[si];
    if (!s.enabled || s.geometry.triangles.empty()) continue;
    GpuSurface& full = r.cache[s.name];
    if (full.version != s.version) upload_geometry(full, s);
    // The surface pass reads the proxy's buffers when one stands in.
    const SurfaceStructure& shaded = proxies[si] ? *proxies[si] : s;
    GpuSurface& gpu = proxies[si] ? r.lods[s.name].gpu : full;
    upload_quantity(gpu, shaded);
    r.last.triangles += shaded.geometry.triangles.size();
    r.last.proxies += proxies[si] ? 1 : 0;

    // Surface.
    Program& p = r.surface;
    p.use();
    p.set("u_view", view);
    p.set("u_projection", proj);
    p.set("u_base_color", s.color);
    p.set("u_flat", d.flat ? 1 : 0);
    p.set("u_wireframe", d.wireframe ? 1 : 0);
    p.set("u_wire_width", std::max(1.0f, d.wire_width_px * pixel_scale));
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
    for (std::size_t i = 0; i < s.glyphs.size() && i < full.glyphs.size(); ++i) {
      const EllipseGlyphs& e = s.glyphs[i];
      std::size_t n = std::min(e.drawn_count(), full.glyphs[i].count);
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
      full.glyphs[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(n));
    }
    glDepthMask(GL_TRUE);

    // Curves, then markers on top of them.
    for (std::size_t i = 0; i < s.curves.size() && i < full.curves.size(); ++i) {
      const Curves& c = s.curves[i];
      if (!c.enabled || full.curves[i].count == 0) continue;
      Program& g = r.curves;
      g.use();
      g.set("u_view", view);
      g.set("u_projection", proj);
      g.set("u_viewport", viewport);
      g.set("u_width", c.width_px * pixel_scale);
      g.set("u_lift", lift);
      g.set("u_orthographic", ortho);
      g.set("u_color", c.color);
      full.curves[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(full.curves[i].count));
    }
    for (std::size_t i = 0; i < s.markers.size() && i < full.markers.size(); ++i) {
      const Markers& m = s.markers[i];
      if (!m.enabled || full.markers[i].count == 0) continue;
      Program& g = r.markers;
      g.use();
      g.set("u_view", view);
      g.set("u_projection", proj);
      g.set("u_viewport", viewport);
      g.set("u_radius", m.radius_px * pixel_scale);
      g.set("u_lift", 2.0f * lift);
      g.set("u_orthographic", ortho);
      g.set("u_color", m.color);
      full.markers[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(full.markers[i].count));
    }
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  check_gl("Renderer::draw");
}

void Renderer::present() {
  Impl& r = *impl_;
  r.target.resolve(0, r.output_width, r.output_height);
  glViewport(0, 0, r.output_width, r.output_height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  check_gl("Renderer::present");
}

}  // namespace anisurf::render
