// Level of detail of the renderer: the clustered proxy (size bound, vertices
// near the surface, quantities read through it), and the frames: a frame
// with unchanged inputs keeps the picture, a moving camera draws at half
// resolution through the proxy of a large surface, and the still picture
// after the motion is the full-detail picture again, byte for byte.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "render/gl.h"
#include "render/image.h"
#include "render/lod.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"

using namespace anisurf::render;

namespace {

// A latitude-longitude sphere of radius `radius`: `rings` x `sectors` quads
// split in two, the poles single vertices.
TriangleSet uv_sphere(int rings, int sectors, float radius) {
  TriangleSet g;
  g.positions.emplace_back(0, 0, radius);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const float theta = static_cast<float>(M_PI) * static_cast<float>(i) / static_cast<float>(rings);
      const float phi = 2.0f * static_cast<float>(M_PI) * static_cast<float>(j) / static_cast<float>(sectors);
      g.positions.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                               radius * std::cos(theta));
    }
  const unsigned south = static_cast<unsigned>(g.positions.size());
  g.positions.emplace_back(0, 0, -radius);
  auto at = [&](int ring, int j) { return 1u + static_cast<unsigned>((ring - 1) * sectors + (j % sectors)); };
  for (int j = 0; j < sectors; ++j) g.triangles.emplace_back(0u, at(1, j), at(1, j + 1));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      g.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      g.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  for (int j = 0; j < sectors; ++j) g.triangles.emplace_back(at(rings - 1, j), south, at(rings - 1, j + 1));
  return g;
}

Scene sphere_scene(TriangleSet g) {
  Scene scene;
  SurfaceStructure s;
  s.name = "sphere";
  s.geometry = std::move(g);
  ScalarQuantity height{"height", ScalarLocation::Vertex};
  for (const auto& p : s.geometry.positions) height.values.push_back(p.z);
  height.set_range_from_data();
  s.scalars.push_back(std::move(height));
  s.active = "height";
  s.version = 1;
  scene.surfaces.push_back(std::move(s));
  scene.camera.set_view(NamedView::Iso);
  scene.fit_camera(4.0f / 3.0f);
  return scene;
}

Image read_framebuffer(int width, int height) {
  using namespace anisurf::gl;
  glFinish();
  Image img(width, height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  return img;
}

// Mean absolute difference per channel, 0-255.
double mean_difference(const Image& a, const Image& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
  return sum / static_cast<double>(a.rgba.size());
}

// Draws moving frames until the proxies are built (at most a minute).
void draw_moving_until_proxies_built(Renderer& r, const Scene& scene, int w, int h) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  do {
    r.render(scene, w, h, DrawOptions{1, true});
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  } while (r.proxies_pending() && std::chrono::steady_clock::now() < end);
  r.render(scene, w, h, DrawOptions{1, true});
}

}  // namespace

TEST_CASE("lod proxy: at most the budget of triangles, vertices within a cell of the surface") {
  const float radius = 2.0f;
  const TriangleSet sphere = uv_sphere(300, 400, radius);  // 239,400 triangles
  for (std::size_t budget : {2000u, 20000u}) {
    CAPTURE(budget);
    const ProxyMesh proxy = make_proxy(sphere, budget);
    CHECK(proxy.geometry.triangles.size() <= budget);
    CHECK(proxy.geometry.triangles.size() >= budget / 4);  // not decimated far beyond the budget
    REQUIRE(proxy.cell_size > 0);
    // A cluster's mean lies in its cell, whose points lie on the sphere.
    for (const auto& p : proxy.geometry.positions) CHECK(std::abs(glm::length(p) - radius) <= std::sqrt(3.0f) * proxy.cell_size);
    REQUIRE(proxy.source_triangle.size() == proxy.geometry.triangles.size());
    REQUIRE(proxy.source_vertex.size() == proxy.geometry.positions.size());
    REQUIRE(proxy.geometry.corner_normals.size() == 3 * proxy.geometry.triangles.size());
    for (std::size_t v = 0; v < proxy.source_vertex.size(); ++v) {
      // The source vertex lies in the proxy vertex's cell.
      const glm::vec3 d = glm::abs(sphere.positions[proxy.source_vertex[v]] - proxy.geometry.positions[v]);
      CHECK(std::max({d.x, d.y, d.z}) <= proxy.cell_size * 1.0001f);
    }
    // The normals of a sphere point outwards.
    for (std::size_t t = 0; t < proxy.geometry.triangles.size(); ++t)
      CHECK(glm::dot(proxy.geometry.corner_normals[3 * t], proxy.geometry.positions[proxy.geometry.triangles[t].x]) > 0);
  }
}

TEST_CASE("lod proxy: quantities are read through the source triangles and vertices") {
  SurfaceStructure full;
  full.name = "s";
  full.geometry = uv_sphere(40, 60, 1.0f);
  ScalarQuantity per_triangle{"t", ScalarLocation::Triangle}, per_vertex{"v", ScalarLocation::Vertex},
      per_edge{"e", ScalarLocation::Edge};
  for (std::size_t t = 0; t < full.geometry.triangles.size(); ++t) {
    per_triangle.values.push_back(static_cast<float>(t));
    for (int k = 0; k < 3; ++k) per_edge.values.push_back(static_cast<float>(3 * t + static_cast<std::size_t>(k)));
  }
  for (std::size_t v = 0; v < full.geometry.positions.size(); ++v) per_vertex.values.push_back(static_cast<float>(v));
  full.scalars = {per_triangle, per_vertex, per_edge};
  full.labels.push_back({"ref", std::vector<int>(full.geometry.triangles.size(), 7)});
  full.highlight_triangles = {0, 5};
  REQUIRE(full.activate("t"));
  const ProxyMesh proxy = make_proxy(full.geometry, 600);
  const SurfaceStructure s = proxy_structure(full, proxy);
  REQUIRE(s.scalars.size() == 3);
  CHECK(s.active == "t");
  CHECK(s.geometry.triangles.size() == proxy.geometry.triangles.size());
  for (std::size_t t = 0; t < proxy.source_triangle.size(); ++t) {
    CHECK(s.scalars[0].values[t] == static_cast<float>(proxy.source_triangle[t]));
    CHECK(s.scalars[2].values[3 * t + 1] == static_cast<float>(3 * proxy.source_triangle[t] + 1));
    CHECK(s.labels[0].triangle_labels[t] == 7);
  }
  for (std::size_t v = 0; v < proxy.source_vertex.size(); ++v)
    CHECK(s.scalars[1].values[v] == static_cast<float>(proxy.source_vertex[v]));
  for (std::uint32_t t : s.highlight_triangles) CHECK((proxy.source_triangle[t] == 0 || proxy.source_triangle[t] == 5));
}

TEST_CASE("renderer frames: unchanged inputs keep the picture, a camera change redraws") {
  const int w = 320, h = 240;
  OffscreenContext context(w, h);
  Renderer r;
  Scene scene = sphere_scene(uv_sphere(30, 40, 1.0f));
  r.render(scene, w, h);
  CHECK(r.last_frame().redrawn);
  const Image first = read_framebuffer(w, h);
  r.render(scene, w, h);
  CHECK_FALSE(r.last_frame().redrawn);
  CHECK(read_framebuffer(w, h).rgba == first.rgba);  // the kept picture is presented
  scene.camera.yaw += 0.3f;
  r.render(scene, w, h);
  CHECK(r.last_frame().redrawn);
  CHECK(read_framebuffer(w, h).rgba != first.rgba);
  scene.surfaces[0].scalars[0].range_max *= 2;  // a toggle without a new version
  r.render(scene, w, h);
  CHECK(r.last_frame().redrawn);
}

TEST_CASE("renderer frames: a moving camera draws at half resolution through the proxy, full detail once still") {
  const int w = 400, h = 300;
  OffscreenContext context(w, h);
  Renderer r;
  Scene scene = sphere_scene(uv_sphere(360, 600, 1.0f));  // 431,400 triangles: over kProxyMinTriangles
  const std::size_t full = scene.surfaces[0].geometry.triangles.size();
  REQUIRE(full > kProxyMinTriangles);

  r.render(scene, w, h, DrawOptions{4, false});
  const Image still = read_framebuffer(w, h);
  CHECK(r.last_frame().triangles == full);
  CHECK(r.last_frame().proxies == 0);
  CHECK(r.last_frame().width == w);

  draw_moving_until_proxies_built(r, scene, w, h);
  REQUIRE_FALSE(r.proxies_pending());
  const FrameInfo moving = r.last_frame();
  CHECK(moving.width == w / 2);
  CHECK(moving.height == h / 2);
  CHECK(moving.samples == 1);
  CHECK(moving.proxies == 1);
  CHECK(moving.triangles <= kProxyMaxTriangles);
  const Image moving_picture = read_framebuffer(w, h);
  CHECK(moving_picture.rgba != still.rgba);
  // The proxy shows the same sphere: close to the full-detail picture.
  CHECK(mean_difference(moving_picture, still) < 6.0);

  r.render(scene, w, h, DrawOptions{4, false});  // the camera stopped where it was
  CHECK(r.last_frame().complete);
  CHECK(r.last_frame().triangles == full);
  CHECK(r.last_frame().proxies == 0);
  CHECK(read_framebuffer(w, h).rgba == still.rgba);
  // Stopped elsewhere: drawn again in full detail.
  scene.camera.yaw += 0.5f;
  r.render(scene, w, h, DrawOptions{1, true});
  r.render(scene, w, h, DrawOptions{4, false});
  CHECK(r.last_frame().redrawn);
  CHECK(r.last_frame().complete);
  CHECK(r.last_frame().width == w);
  CHECK(r.last_frame().triangles == full);
  CHECK(r.last_frame().proxies == 0);
  const Image elsewhere = read_framebuffer(w, h);
  {
    OffscreenContext fresh_context(w, h);
    Renderer fresh;
    fresh.render(scene, w, h, DrawOptions{4, false});
    CHECK(read_framebuffer(w, h).rgba == elsewhere.rgba);
  }
  context.resize(w, h);

  // A new version of the surface: the old proxy is not drawn for it.
  scene.surfaces[0].version += 1;
  r.render(scene, w, h, DrawOptions{1, true});
  CHECK(r.last_frame().proxies == 0);
  CHECK(r.last_frame().triangles == full);
}

TEST_CASE("renderer frames: a still picture over the triangle budget is drawn in slices, the last complete one shown meanwhile") {
  const int w = 320, h = 240;
  OffscreenContext context(w, h);
  Scene scene = sphere_scene(uv_sphere(60, 80, 1.0f));  // 9,440 triangles
  const std::size_t n = scene.surfaces[0].geometry.triangles.size();
  const float yaw = scene.camera.yaw;
  Renderer whole;
  whole.render(scene, w, h);
  const Image reference = read_framebuffer(w, h);
  scene.camera.yaw = yaw + 0.4f;
  whole.render(scene, w, h);
  const Image turned = read_framebuffer(w, h);

  Renderer sliced;
  scene.camera.yaw = yaw;
  sliced.render(scene, w, h);  // no budget: one frame
  CHECK(read_framebuffer(w, h).rgba == reference.rgba);
  scene.camera.yaw = yaw + 0.4f;
  const DrawOptions budget{0, false, n / 3 + 1};
  for (int frame = 0; frame < 2; ++frame) {
    sliced.render(scene, w, h, budget);
    CHECK_FALSE(sliced.last_frame().complete);
    CHECK(sliced.last_frame().triangles <= budget.triangle_budget);
    CHECK(read_framebuffer(w, h).rgba == reference.rgba);  // the last complete picture
  }
  sliced.render(scene, w, h, budget);
  CHECK(sliced.last_frame().complete);
  CHECK(read_framebuffer(w, h).rgba == turned.rgba);  // the slices make the one-frame picture

  // A newer picture interrupts an unfinished one (its fast picture, without
  // a proxy, would not fit the budget): the last complete picture stays
  // until the newer one is complete.
  scene.camera.yaw += 0.4f;
  sliced.render(scene, w, h, budget);
  scene.camera.yaw += 0.4f;
  sliced.render(scene, w, h, budget);
  CHECK_FALSE(sliced.last_frame().complete);
  CHECK(sliced.last_frame().triangles <= budget.triangle_budget);
  CHECK(read_framebuffer(w, h).rgba == turned.rgba);
  for (int frame = 0; frame < 3 && !sliced.last_frame().complete; ++frame) sliced.render(scene, w, h, budget);
  CHECK(sliced.last_frame().complete);
  whole.render(scene, w, h);
  const Image expected = read_framebuffer(w, h);
  sliced.render(scene, w, h, budget);
  CHECK(read_framebuffer(w, h).rgba == expected.rgba);

  // New data with a budget: its GPU copy is prepared in the background, the
  // last picture shown meanwhile, then the new one drawn in slices.
  scene.surfaces[0].version += 1;
  int frames = 0;
  do {
    sliced.render(scene, w, h, budget);
    CHECK(read_framebuffer(w, h).rgba == expected.rgba);  // the same geometry: the same picture throughout
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  } while (!sliced.last_frame().complete && ++frames < 5000);
  CHECK(sliced.last_frame().complete);
  CHECK(frames >= 3);  // at least the three slices
}

TEST_CASE("renderer frames: switching between one sample and multisampling keeps each target (no reallocation)") {
  // The editor draws with one sample while a pass runs and with 4 otherwise.
  // A 4-sample 1280x800 target is 33 MB: allocated again at each switch, its
  // 8000 pages would be faulted in again.
  const int w = 1280, h = 800;
  OffscreenContext context(w, h);
  Renderer r;
  Scene scene = sphere_scene(uv_sphere(30, 40, 1.0f));
  r.render(scene, w, h, DrawOptions{4, false});
  const Image multisampled = read_framebuffer(w, h);
  scene.camera.yaw += 0.3f;
  r.render(scene, w, h, DrawOptions{1, false});
  scene.camera.yaw -= 0.3f;
  rusage before{}, after{};
  getrusage(RUSAGE_SELF, &before);
  r.render(scene, w, h, DrawOptions{4, false});
  const Image again = read_framebuffer(w, h);
  getrusage(RUSAGE_SELF, &after);
  const long faults = after.ru_minflt - before.ru_minflt;
  const long target_pages = static_cast<long>(w) * h * 4 * 8 / 4096;
  MESSAGE("page faults while drawing with 4 samples again: " << faults << " (the target: " << target_pages << " pages)");
  CHECK(faults < target_pages / 4);
  CHECK(again.rgba == multisampled.rgba);
}

#endif  // ANISURF_WITH_GL
