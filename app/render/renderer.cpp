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
  // The interleaved corners of a newer version, prepared in the background.
  std::future<std::vector<float>> corners_job;
  std::uint64_t job_version = ~0ull;
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

// Per corner (3 per triangle): position, normal, interleaved.
std::vector<float> interleaved_corners(const TriangleSet& g) {
  const bool corner_normals = g.corner_normals.size() == 3 * g.triangles.size();
  std::vector<glm::vec3> vn;
  if (!corner_normals) vn = smooth_normals(g);
  std::vector<float> data(g.triangles.size() * 18);
  float* out = data.data();
  for (std::size_t t = 0; t < g.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      unsigned v = g.triangles[t][k];
      const glm::vec3& p = g.positions[v];
      const glm::vec3& n = corner_normals ? g.corner_normals[3 * t + static_cast<std::size_t>(k)] : vn[v];
      for (float x : {p.x, p.y, p.z, n.x, n.y, n.z}) *out++ = x;
    }
  return data;
}

void upload_geometry(GpuSurface& gpu, const SurfaceStructure& s, const std::vector<float>& data) {
  const TriangleSet& g = s.geometry;
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
      upload_geometry(lod.gpu, *lod.structure, interleaved_corners(lod.structure->geometry));
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

// What the passes of one picture share.
struct FrameSetup {
  glm::mat4 view{1}, proj{1};
  glm::vec2 viewport{1};
  int ortho = 0;
  float lift = 0;
  float pixel_scale = 1;  // target pixels per output pixel
};

FrameSetup frame_setup(const Scene& scene, int width, int height, int target_width, int target_height,
                       float pixel_scale) {
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const Camera& cam = scene.camera;
  return {cam.view(), cam.projection(aspect), glm::vec2(target_width, target_height), cam.orthographic ? 1 : 0,
          cam.scene_radius * 2e-3f, pixel_scale};
}

// Binds `target` and clears it to the background, with the state the passes expect.
void begin_picture(RenderTarget& target, int width, int height, int samples, const DisplayOptions& d) {
  target.ensure(width, height, samples);
  target.bind();
  glViewport(0, 0, width, height);
  glClearColor(d.background.r, d.background.g, d.background.b, 1.0f);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void set_pass_state() {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
}

void end_passes() {
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  check_gl("Renderer::draw");
}

std::size_t enabled_triangles(const Scene& scene) {
  std::size_t n = 0;
  for (const SurfaceStructure& s : scene.surfaces) n += s.enabled ? s.geometry.triangles.size() : 0;
  return n;
}

// Which picture present() shows.
enum class Shown { None, Fast, Full };

// The full-detail picture drawn over several frames: the surfaces in order,
// each one's triangles in slices, then its glyphs, curves and markers.
struct FullProgress {
  std::vector<unsigned char> key;  // frame_key() of the picture being drawn (empty: none)
  std::size_t surface = 0;         // next surface
  std::size_t triangle = 0;        // next triangle of that surface
};

}  // namespace

struct Renderer::Impl {
  Program surface{"surface.vert", "surface.frag"};
  Program curves{"curves.vert", "curves.frag"};
  Program markers{"markers.vert", "markers.frag"};
  Program glyphs{"glyphs.vert", "glyphs.frag"};
  std::map<Colormap, Texture2D> colormaps;
  std::map<std::string, GpuSurface> cache;
  std::map<std::string, SurfaceLod> lods;
  RenderTarget fast;      // the moving camera's picture (reduced resolution, one sample)
  // The full-detail picture being drawn, one target per sample count asked
  // (the editor draws with one sample while a pass runs and with its
  // multisampling otherwise): switching keeps each target's memory instead
  // of reallocating it (a 4-sample 1280x800 target is 33 MB of pages to
  // fault in again).
  std::map<int, RenderTarget> building_targets;
  RenderTarget* building_now = nullptr;
  RenderTarget& building_for(int samples) { return *(building_now = &building_targets[samples]); }
  RenderTarget& building() { return building_now ? *building_now : building_for(1); }
  RenderTarget full;      // the last complete full-detail picture, resolved
  std::vector<unsigned char> fast_key, full_key;  // frame_key() of the pictures in `fast` and `full`
  FrameInfo fast_info, full_info;                 // what they hold
  FullProgress progress;
  Shown shown = Shown::None;
  int output_width = 0, output_height = 0;
  glm::vec3 background{1.0f};
  FrameInfo last;

  const Texture2D& colormap(Colormap c) {
    auto it = colormaps.find(c);
    if (it != colormaps.end()) return it->second;
    auto px = colormap_rgba8(c, 256);
    Texture2D& tex = colormaps[c];
    tex.upload_rgba8(256, 1, px.data(), true);
    return tex;
  }

  // The GPU copy of a surface, uploaded when its version changed.
  GpuSurface& gpu_of(const SurfaceStructure& s) {
    GpuSurface& gpu = cache[s.name];
    if (gpu.version != s.version) upload_geometry(gpu, s, interleaved_corners(s.geometry));
    return gpu;
  }

  // Whether the GPU copy of `s` is current; if not, its corners are prepared
  // by a background job and uploaded once the job is done.
  bool uploaded_in_background(const SurfaceStructure& s) {
    using namespace std::chrono_literals;
    GpuSurface& gpu = cache[s.name];
    if (gpu.version == s.version) return true;
    if (gpu.corners_job.valid()) {
      if (gpu.corners_job.wait_for(0s) != std::future_status::ready) return false;  // never waited for
      std::vector<float> corners = gpu.corners_job.get();
      if (gpu.job_version == s.version) {
        upload_geometry(gpu, s, corners);
        return true;
      }
    }
    // None for this version (or an outdated one just ended): start it.
    gpu.job_version = s.version;
    gpu.corners_job = std::async(std::launch::async, [g = TriangleSet{s.geometry}] { return interleaved_corners(g); });
    return false;
  }

  bool all_uploaded_in_background(const Scene& scene) {
    bool all = true;
    for (const SurfaceStructure& s : scene.surfaces)
      if (s.enabled && !s.geometry.triangles.empty()) all = uploaded_in_background(s) && all;
    return all;
  }

  // Triangles the fast picture would draw now (proxies where built).
  std::size_t fast_triangles(const Scene& scene) const {
    std::size_t n = 0;
    for (const SurfaceStructure& s : scene.surfaces) {
      if (!s.enabled) continue;
      auto it = lods.find(s.name);
      const bool proxy = s.geometry.triangles.size() > kProxyMinTriangles && it != lods.end() &&
                         it->second.version == s.version && it->second.structure;
      n += proxy ? it->second.structure->geometry.triangles.size() : s.geometry.triangles.size();
    }
    return n;
  }

  // Triangles [first, first + count) of `shaded`'s GPU copy `gpu`; uniforms
  // (colours, ranges) from the surface `s` it stands for.
  void draw_surface(const SurfaceStructure& s, const SurfaceStructure& shaded, GpuSurface& gpu, const FrameSetup& f,
                    const DisplayOptions& d, std::size_t first, std::size_t count) {
    upload_quantity(gpu, shaded);
    Program& p = surface;
    p.use();
    p.set("u_view", f.view);
    p.set("u_projection", f.proj);
    p.set("u_base_color", s.color);
    p.set("u_flat", d.flat ? 1 : 0);
    p.set("u_wireframe", d.wireframe ? 1 : 0);
    p.set("u_wire_width", std::max(1.0f, d.wire_width_px * f.pixel_scale));
    p.set("u_wire_color", d.wire_color);
    p.set("u_highlight_color", d.highlight_color);
    p.set("u_orthographic", f.ortho);
    p.set("u_has_flags", gpu.has_flags ? 1 : 0);
    p.set("u_colormap", kUnitColormap);
    p.set("u_triangle_values", kUnitTriangleValues);
    p.set("u_triangle_colors", kUnitTriangleColors);
    p.set("u_triangle_flags", kUnitTriangleFlags);
    p.set("u_first_triangle", static_cast<int>(first));
    int mode = 0;
    colormap(Colormap::Viridis).bind(kUnitColormap);
    if (const ScalarQuantity* q = s.active_scalar()) {
      mode = q->location == ScalarLocation::Vertex ? 1 : q->location == ScalarLocation::Triangle ? 2 : 3;
      p.set("u_range", glm::vec2(mapped(q->range_min, q->log_scale), mapped(q->range_max, q->log_scale)));
      colormap(q->colormap).bind(kUnitColormap);
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
    glDrawArrays(GL_TRIANGLES, static_cast<GLint>(3 * first), static_cast<GLsizei>(3 * count));
    glDisable(GL_POLYGON_OFFSET_FILL);
  }

  // Glyphs, curves and markers of `s` (on top of the surfaces drawn so far).
  void draw_overlays(const SurfaceStructure& s, GpuSurface& gpu, const FrameSetup& f) {
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    // Glyphs (translucent fill: no depth writes).
    glDepthMask(GL_FALSE);
    for (std::size_t i = 0; i < s.glyphs.size() && i < gpu.glyphs.size(); ++i) {
      const EllipseGlyphs& e = s.glyphs[i];
      std::size_t n = std::min(e.drawn_count(), gpu.glyphs[i].count);
      if (!e.enabled || n == 0) continue;
      Program& g = glyphs;
      g.use();
      g.set("u_view", f.view);
      g.set("u_projection", f.proj);
      g.set("u_scale", e.scale);
      g.set("u_lift", 0.2f);
      g.set("u_orthographic", f.ortho);
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
      Program& g = curves;
      g.use();
      g.set("u_view", f.view);
      g.set("u_projection", f.proj);
      g.set("u_viewport", f.viewport);
      g.set("u_width", c.width_px * f.pixel_scale);
      g.set("u_lift", f.lift);
      g.set("u_orthographic", f.ortho);
      g.set("u_color", c.color);
      gpu.curves[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(gpu.curves[i].count));
    }
    for (std::size_t i = 0; i < s.markers.size() && i < gpu.markers.size(); ++i) {
      const Markers& m = s.markers[i];
      if (!m.enabled || gpu.markers[i].count == 0) continue;
      Program& g = markers;
      g.use();
      g.set("u_view", f.view);
      g.set("u_projection", f.proj);
      g.set("u_viewport", f.viewport);
      g.set("u_radius", m.radius_px * f.pixel_scale);
      g.set("u_lift", 2.0f * f.lift);
      g.set("u_orthographic", f.ortho);
      g.set("u_color", m.color);
      gpu.markers[i].vao.bind();
      glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(gpu.markers[i].count));
    }
    glDisable(GL_BLEND);
  }

  void draw_fast(const Scene& scene, int width, int height);
  void draw_full(const Scene& scene, int width, int height, const DrawOptions& options);
  std::size_t continue_full(const Scene& scene, int width, int height, std::size_t budget);
};

// The moving camera's picture: reduced resolution, one sample, proxies of
// the large surfaces once built.
void Renderer::Impl::draw_fast(const Scene& scene, int width, int height) {
  const int tw = std::max(1, static_cast<int>(std::lround(static_cast<float>(width) * kMovingScale)));
  const int th = std::max(1, static_cast<int>(std::lround(static_cast<float>(height) * kMovingScale)));
  std::vector<const SurfaceStructure*> proxies(scene.surfaces.size(), nullptr);
  std::vector<bool> through_proxy(scene.surfaces.size(), false);
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const SurfaceStructure& s = scene.surfaces[i];
    if (!s.enabled || s.geometry.triangles.size() <= kProxyMinTriangles) continue;
    proxies[i] = ready_proxy(lods[s.name], s);
    through_proxy[i] = proxies[i] != nullptr;
  }
  shown = Shown::Fast;
  std::vector<unsigned char> key = frame_key(scene, width, height, 1, true, through_proxy);
  if (key == fast_key && fast.width() == tw && fast.height() == th) {
    last = fast_info;
    last.redrawn = false;
    return;
  }
  fast_key = std::move(key);
  last = FrameInfo{true, tw, th, 1, 0, 0, true};
  begin_picture(fast, tw, th, 1, scene.display);
  set_pass_state();
  const FrameSetup f = frame_setup(scene, width, height, tw, th, kMovingScale);
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const SurfaceStructure& s = scene.surfaces[i];
    if (!s.enabled || s.geometry.triangles.empty()) continue;
    GpuSurface& gpu = gpu_of(s);
    const SurfaceStructure& shaded = proxies[i] ? *proxies[i] : s;
    GpuSurface& shaded_gpu = proxies[i] ? lods[s.name].gpu : gpu;
    draw_surface(s, shaded, shaded_gpu, f, scene.display, 0, shaded.geometry.triangles.size());
    draw_overlays(s, gpu, f);
    last.triangles += shaded.geometry.triangles.size();
    last.proxies += proxies[i] ? 1 : 0;
  }
  end_passes();
  fast_info = last;
}

// Draws the next slices of the full-detail picture, at most `budget`
// triangles (0: all); clears progress.key once the picture is complete.
// Returns the triangles drawn.
std::size_t Renderer::Impl::continue_full(const Scene& scene, int width, int height, std::size_t budget) {
  building().bind();
  glViewport(0, 0, width, height);
  set_pass_state();
  const FrameSetup f = frame_setup(scene, width, height, width, height, 1.0f);
  std::size_t left = budget > 0 ? budget : ~std::size_t{0};
  std::size_t drawn = 0;
  FullProgress& at = progress;
  for (; at.surface < scene.surfaces.size(); ++at.surface, at.triangle = 0) {
    const SurfaceStructure& s = scene.surfaces[at.surface];
    if (!s.enabled || s.geometry.triangles.empty()) continue;
    GpuSurface& gpu = gpu_of(s);
    const std::size_t n = s.geometry.triangles.size();
    const std::size_t count = std::min(left, n - at.triangle);
    if (count > 0) draw_surface(s, s, gpu, f, scene.display, at.triangle, count);
    at.triangle += count;
    left -= count;
    drawn += count;
    if (at.triangle < n) break;  // out of budget
    draw_overlays(s, gpu, f);
  }
  end_passes();
  if (at.surface >= scene.surfaces.size()) at.key.clear();
  return drawn;
}

// The still picture: full resolution and multisampling, drawn over as many
// frames as options.triangle_budget asks; the last complete picture (full
// or fast) stays shown meanwhile.
void Renderer::Impl::draw_full(const Scene& scene, int width, int height, const DrawOptions& options) {
  const int samples = std::max(1, options.samples > 0 ? options.samples : scene.display.msaa_samples);
  const std::vector<bool> no_proxy(scene.surfaces.size(), false);
  std::vector<unsigned char> key = frame_key(scene, width, height, samples, false, no_proxy);
  if (key == full_key && full.width() == width && full.height() == height) {
    shown = Shown::Full;
    last = full_info;
    last.redrawn = false;
    return;
  }
  const bool sliced = options.triangle_budget > 0;
  if (key != progress.key) {
    // A new picture: with a budget, once the GPU copies are prepared in the
    // background (the last picture stays shown meanwhile).
    last = FrameInfo{false, width, height, samples, 0, 0, false};
    if (sliced && !all_uploaded_in_background(scene)) return;
    const bool interrupted = !progress.key.empty();
    progress = FullProgress{key, 0, 0};
    begin_picture(building_for(samples), width, height, samples, scene.display);
    // A picture left unfinished for a newer one: the fast picture of this
    // frame answers meanwhile when it fits the budget.
    if (interrupted && fast_triangles(scene) <= options.triangle_budget) {
      draw_fast(scene, width, height);
      last.complete = false;
      return;
    }
  }
  last = FrameInfo{true, width, height, samples, continue_full(scene, width, height, options.triangle_budget), 0,
                   false};
  if (!progress.key.empty()) return;  // more slices in the next frames
  full.ensure(width, height, 1);
  building().resolve_into(full);
  full_key = std::move(key);
  shown = Shown::Full;
  last = FrameInfo{true, width, height, samples, enabled_triangles(scene), 0, true};
  full_info = last;
}

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  // Dummy textures so every sampler has a complete texture bound.
  for (auto c : {Colormap::Viridis, Colormap::Coolwarm}) impl_->colormap(c);
  check_gl("Renderer setup");
}

Renderer::~Renderer() = default;

void Renderer::clear_cache() {
  impl_->cache.clear();
  impl_->lods.clear();
  impl_->fast_key.clear();
  impl_->full_key.clear();
  impl_->progress = FullProgress{};
}

const FrameInfo& Renderer::last_frame() const { return impl_->last; }

bool Renderer::proxies_pending() const {
  for (const auto& [name, lod] : impl_->lods)
    if (lod.job.valid()) return true;
  return false;
}

void Renderer::draw(const Scene& scene, int width, int height, const DrawOptions& options) {
  Impl& r = *impl_;
  r.output_width = width;
  r.output_height = height;
  r.background = scene.display.background;
  if (options.camera_moving) {
    r.progress = FullProgress{};  // the still picture starts again once the camera stops
    r.draw_fast(scene, width, height);
  } else {
    r.draw_full(scene, width, height, options);
  }
}

void Renderer::present() {
  Impl& r = *impl_;
  if (r.shown == Shown::Full) {
    r.full.resolve(0, r.output_width, r.output_height);
  } else if (r.shown == Shown::Fast) {
    r.fast.resolve(0, r.output_width, r.output_height);
  } else {  // nothing complete yet
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glClearColor(r.background.r, r.background.g, r.background.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  glViewport(0, 0, r.output_width, r.output_height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  check_gl("Renderer::present");
}

}  // namespace anisurf::render
