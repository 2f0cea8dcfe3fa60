// The renderer: camera, colormaps, legend ticks, glyph ellipses and mesh
// structures in process; headless pictures (OSMesa) of meshes built in code;
// and `anisurf shot` on the shared meshes as a user runs it, checking the
// pictures (not blank, centred, background in the corners, views differ,
// same bytes twice, close to the reference images in tests/data/ref/).
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "mesh/build.h"
#include "mesh/surface_mesh.h"
#include "render/camera.h"
#include "render/colormap.h"
#include "render/headless.h"
#include "render/image.h"
#include "render/mesh_structure.h"
#include "render/ui.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::render;

namespace {

struct Run {
  int code;
  std::string out;
  std::string err;
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `prefix anisurf args` (prefix: e.g. "env -u DISPLAY").
Run run_anisurf_env(const std::string& prefix, const std::string& args, const std::filesystem::path& dir) {
  std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
  std::string cmd = prefix + " \"" + ANISURF_BINARY + "\" " + args + " >" + out + " 2>" + err;
  int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

Run run_anisurf(const std::string& args, const std::filesystem::path& dir) { return run_anisurf_env("", args, dir); }

const std::uint8_t kWhite[3] = {255, 255, 255};

// Projects p with the camera; true if inside the view (NDC in [-1, 1]).
bool in_view(const Camera& cam, const glm::vec3& p, float aspect) {
  glm::vec4 c = cam.projection(aspect) * cam.view() * glm::vec4(p, 1.0f);
  if (c.w <= 0) return false;
  glm::vec3 n = glm::vec3(c) / c.w;
  return std::abs(n.x) <= 1.0001f && std::abs(n.y) <= 1.0001f && n.z >= -1.0001f && n.z <= 1.0001f;
}

// A unit cube (8 vertices, 12 triangles) with its 12 sharp edges tagged as
// ridges and its 8 vertices as corners.
SurfaceMesh cube() {
  MeshData d;
  for (int i = 0; i < 8; ++i) d.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    d.triangles.push_back({q[0], q[1], q[2]});
    d.triangles.push_back({q[0], q[2], q[3]});
  }
  SurfaceMesh m;
  build_mesh(d, m);
  REQUIRE(m.validate().ok());
  for (int t = 0; t < m.triangle_capacity(); ++t)
    for (int k = 0; k < 3; ++k) {
      Corner c = SurfaceMesh::corner(Triangle(t), k);
      Corner o = m.opposite(c);
      if (!o.is_valid()) continue;
      Vec3 a = normalized(m.triangle_normal(Triangle(t)));
      Vec3 b = normalized(m.triangle_normal(SurfaceMesh::triangle(o)));
      if (dot(a, b) < 0.5) m.add_edge_tag(c, kRidge);
    }
  for (int i = 0; i < 8; ++i) m.add_vertex_tag(Vertex(i), kCorner);
  return m;
}

Scene scene_of(const SurfaceMesh& mesh, NamedView view, float aspect) {
  Scene scene;
  scene.surfaces.push_back(make_mesh_structure(mesh, "cube").structure);
  scene.camera.set_view(view);
  scene.fit_camera(aspect);
  return scene;
}

}  // namespace

// --- camera -------------------------------------------------------------------

TEST_CASE("camera: named views look along the axes, up axis y or z") {
  Camera c;
  auto near = [](glm::vec3 a, glm::vec3 b) { return glm::length(a - b) < 1e-5f; };
  c.set_view(NamedView::Front);
  CHECK(near(c.forward(), {0, 0, -1}));
  CHECK(near(c.up(), {0, 1, 0}));
  c.set_view(NamedView::Right);
  CHECK(near(c.forward(), {-1, 0, 0}));
  c.set_view(NamedView::Top);
  CHECK(near(c.forward(), {0, -1, 0}));
  CHECK(near(c.up(), {0, 0, -1}));
  c.set_view(NamedView::Bottom);
  CHECK(near(c.forward(), {0, 1, 0}));
  c.set_view(NamedView::Iso);
  CHECK(near(c.forward(), glm::normalize(glm::vec3(-1, -1, -1))));
  c.up_axis = UpAxis::Z;
  c.set_view(NamedView::Front);
  CHECK(near(c.forward(), {0, 1, 0}));
  CHECK(near(c.up(), {0, 0, 1}));
  c.set_view(NamedView::Top);
  CHECK(near(c.forward(), {0, 0, -1}));
  // Orbiting never tips over the poles.
  c.orbit(0.3f, 10.0f);
  CHECK(c.pitch == doctest::Approx(1.5707963f));
  CHECK(!parse_view("sideways"));
  CHECK(parse_view("back") == NamedView::Back);
}

TEST_CASE("camera: fit puts every point in view, tightly, in perspective and ortho") {
  std::vector<glm::vec3> pts;
  for (int i = 0; i < 200; ++i) {
    float t = static_cast<float>(i) * 0.37f;
    pts.emplace_back(10.0f + 4.0f * std::cos(t), -3.0f + 0.5f * std::sin(2 * t), 100.0f + 1.5f * std::sin(t));
  }
  for (bool ortho : {false, true})
    for (NamedView v : {NamedView::Iso, NamedView::Front, NamedView::Top, NamedView::Left})
      for (float aspect : {1.6f, 0.5f}) {
        CAPTURE(ortho);
        CAPTURE(view_name(v));
        CAPTURE(aspect);
        Camera c;
        c.orthographic = ortho;
        c.set_view(v);
        c.fit(pts, aspect);
        for (const auto& p : pts) REQUIRE(in_view(c, p, aspect));
        // Tight: zooming in by 25% loses some point.
        c.zoom(0.75f);
        bool lost = false;
        for (const auto& p : pts) lost |= !in_view(c, p, aspect);
        CHECK(lost);
      }
}

TEST_CASE("camera: fitting with strips kept free (panel left, legend right)") {
  std::vector<glm::vec3> pts;
  for (int i = 0; i < 100; ++i) pts.emplace_back(std::cos(i * 0.7f), std::sin(i * 1.3f), 0.3f * std::sin(i * 0.1f));
  for (bool ortho : {false, true}) {
    CAPTURE(ortho);
    Camera c;
    c.orthographic = ortho;
    c.set_view(NamedView::Iso);
    const float aspect = 1.6f, left = 0.2f, right = 0.25f;
    c.fit(pts, aspect, 0.06f, left, right);
    float xmin = 2, xmax = -2;
    for (const auto& p : pts) {
      glm::vec4 q = c.projection(aspect) * c.view() * glm::vec4(p, 1.0f);
      xmin = std::min(xmin, q.x / q.w);
      xmax = std::max(xmax, q.x / q.w);
    }
    CHECK(xmin >= -1 + 2 * left - 1e-4f);
    CHECK(xmax <= 1 - 2 * right + 1e-4f);
    // Centred in the free part.
    CHECK(0.5f * (xmin + xmax) == doctest::Approx(left - right).epsilon(0.02));
  }
}

// --- colormaps, legend ----------------------------------------------------------

TEST_CASE("colormaps: viridis ends and monotone lightness, coolwarm blue-grey-red") {
  auto lum = [](glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
  glm::vec3 a = colormap_color(Colormap::Viridis, 0), b = colormap_color(Colormap::Viridis, 1);
  CHECK(std::lround(a.r * 255) == 0x44);
  CHECK(std::lround(a.b * 255) == 0x54);
  CHECK(std::lround(b.r * 255) == 0xfd);
  CHECK(std::lround(b.g * 255) == 0xe7);
  for (int i = 0; i < 32; ++i)
    CHECK(lum(colormap_color(Colormap::Viridis, (i + 1) / 32.0f)) > lum(colormap_color(Colormap::Viridis, i / 32.0f)));
  glm::vec3 lo = colormap_color(Colormap::Coolwarm, 0), mid = colormap_color(Colormap::Coolwarm, 0.5f),
            hi = colormap_color(Colormap::Coolwarm, 1);
  CHECK(lo.b > lo.r + 0.3f);
  CHECK(hi.r > hi.b + 0.3f);
  CHECK(std::abs(mid.r - mid.b) < 0.03f);
  CHECK(lum(mid) > lum(lo));
  CHECK(lum(mid) > lum(hi));
  CHECK(colormap_rgba8(Colormap::Coolwarm, 256).size() == 1024);
  CHECK(categorical_color(3) != categorical_color(4));
}

TEST_CASE("legend ticks: sorted, inside the range, both ends, nice values") {
  for (const auto& range : {std::tuple{0.0f, 1.0f, false}, std::tuple{0.5f, 2.0f, true},
                             std::tuple{0.03464f, 0.1f, true}, std::tuple{-3.0f, 250.0f, false},
                             std::tuple{1.0f, 8.3f, true}}) {
    // Plain variables, not structured bindings: CAPTURE's lambda cannot take
    // those with clang 14.
    const float lo = std::get<0>(range), hi = std::get<1>(range);
    const bool log = std::get<2>(range);
    CAPTURE(lo);
    CAPTURE(hi);
    auto t = legend_ticks(lo, hi, log);
    REQUIRE(t.size() >= 2);
    CHECK(t.front() == lo);
    CHECK(t.back() == hi);
    for (std::size_t i = 1; i < t.size(); ++i) CHECK(t[i] > t[i - 1]);
  }
  auto t = legend_ticks(0.5f, 2.0f, true);
  CHECK(std::find(t.begin(), t.end(), 1.0f) != t.end());
}

// --- glyphs and mesh structures ---------------------------------------------------

TEST_CASE("tangent ellipse: semi-axes are the metric sizes in the tangent plane, largest first") {
  // Sizes 0.5 along x, 2 along y, 0.1 along z; tangent plane z = const.
  SymTensor3 M = SymTensor3::diagonal(1 / 0.25, 1 / 4.0, 1 / 0.01);
  auto e = tangent_ellipse(M, Vec3(0, 0, 1));
  REQUIRE(e);
  CHECK(norm(e->major) == doctest::Approx(2.0));
  CHECK(norm(e->minor) == doctest::Approx(0.5));
  CHECK(std::abs(e->major.y) == doctest::Approx(2.0));
  CHECK(std::abs(dot(e->major, e->minor)) < 1e-12);
  // Tangent plane x = const: sizes along y (2) and z (0.1).
  e = tangent_ellipse(M, Vec3(1, 0, 0));
  REQUIRE(e);
  CHECK(norm(e->major) == doctest::Approx(2.0));
  CHECK(norm(e->minor) == doctest::Approx(0.1));
  // Every point of the ellipse has metric length 1.
  for (double t = 0; t < 6.28; t += 0.5) CHECK(metric_length(M, std::cos(t) * e->major + std::sin(t) * e->minor) == doctest::Approx(1.0));
  CHECK(!tangent_ellipse(SymTensor3::diagonal(1, -1, 1), Vec3(0, 0, 1)));
}

TEST_CASE("spread order: a permutation whose prefixes cover the whole set") {
  std::vector<Vec3> pts;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) pts.emplace_back(i, j, 0);  // row-major: index order is badly spread
  auto order = spread_order(pts);
  REQUIRE(order.size() == pts.size());
  CHECK(std::set<int>(order.begin(), order.end()).size() == pts.size());
  // The first 16 fall in 16 different 10x10 blocks.
  std::set<int> blocks;
  for (int k = 0; k < 16; ++k) blocks.insert(static_cast<int>(pts[order[k]].x) / 10 * 4 + static_cast<int>(pts[order[k]].y) / 10);
  CHECK(blocks.size() == 16);
}

TEST_CASE("mesh structure: features, split normals, quantities, highlight ids") {
  SurfaceMesh m = cube();
  MeshStructure s = make_mesh_structure(m, "cube");
  const SurfaceStructure& st = s.structure;
  CHECK(st.geometry.positions.size() == 8);
  CHECK(st.geometry.triangles.size() == 12);
  REQUIRE(st.curves.size() == 1);
  CHECK(st.curves[0].name == "ridges");
  CHECK(st.curves[0].points.size() == 24);
  REQUIRE(st.markers.size() == 1);
  CHECK(st.markers[0].positions.size() == 8);
  // Ridges split the normals: every corner normal is its face normal.
  REQUIRE(st.geometry.corner_normals.size() == 36);
  for (std::size_t t = 0; t < 12; ++t) {
    const auto& tri = st.geometry.triangles[t];
    glm::vec3 fn = glm::normalize(glm::cross(st.geometry.positions[tri.y] - st.geometry.positions[tri.x],
                                             st.geometry.positions[tri.z] - st.geometry.positions[tri.x]));
    for (int k = 0; k < 3; ++k) CHECK(glm::dot(st.geometry.corner_normals[3 * t + k], fn) > 0.9999f);
  }
  // No metric: quality and lengths are Euclidean; no size, no glyphs.
  CHECK(s.metric_field.empty());
  const ScalarQuantity* q = nullptr;
  for (const auto& x : st.scalars)
    if (x.name == quantity::kQuality) q = &x;
  REQUIRE(q);
  // Right isosceles triangles (1, 1, sqrt 2): 27 (p - a)(p - b)(p - c) / p^3.
  const double a = 1, b = 1, c = std::sqrt(2.0), p = (a + b + c) / 2;
  for (float v : q->values) CHECK(v == doctest::Approx(27 * (p - a) * (p - b) * (p - c) / (p * p * p)).epsilon(1e-5));
  CHECK(st.glyphs.empty());
  // Ids out of range: a message numbering from 1.
  CHECK_THROWS_WITH_AS(highlight(s, {12}, {}), doctest::Contains("triangle 13 does not exist"), Error);
  highlight(s, {0, 5}, {7});
  CHECK(s.structure.highlight_triangles.size() == 2);
  CHECK(s.structure.markers.back().positions.size() == 1);
}

TEST_CASE("mesh structure: a metric field gives size, anisotropy, metric lengths and glyphs") {
  SurfaceMesh m = cube();
  Property<FieldValue> f = m.add_field("metric", FieldKind::Tensor, 6);
  for (int v = 0; v < m.vertex_capacity(); ++v) f[Vertex(v)] = {1 / 0.25, 0, 1 / 4.0, 0, 0, 1 / 0.01};
  MeshStructure s = make_mesh_structure(m, "cube");
  CHECK(s.metric_field == "metric");
  std::set<std::string> names;
  for (const auto& q : s.structure.scalars) names.insert(q.name);
  for (const char* n : {quantity::kQuality, quantity::kLength, quantity::kSize, quantity::kAniso}) CHECK(names.count(n));
  REQUIRE(s.structure.glyphs.size() == 1);
  CHECK(s.structure.glyphs[0].centers.size() == 8);
  for (const auto& q : s.structure.scalars)
    if (q.name == quantity::kLength) {
      // An x edge of length 1 in sizes 0.5: metric length 2; a y edge: 0.5; a z edge: 10.
      std::set<int> rounded;
      for (float v : q.values) rounded.insert(static_cast<int>(std::lround(v * 10)));
      CHECK(rounded.count(20));
      CHECK(rounded.count(5));
      CHECK(rounded.count(100));
    }
  // A field that is not a metric is reported, not fatal, unless named.
  SurfaceMesh n = cube();
  Property<FieldValue> g = n.add_field("u", FieldKind::Scalar, 1);
  for (int v = 0; v < n.vertex_capacity(); ++v) g[Vertex(v)] = {v - 3.0};
  MeshStructure t = make_mesh_structure(n, "cube");
  CHECK(t.metric_field.empty());
  CHECK(t.metric_problem.find("'u'") != std::string::npos);
  MeshStructureOptions named;
  named.metric_field = "u";
  CHECK_THROWS_AS(make_mesh_structure(n, "cube", named), MetricError);
}

// --- headless pictures in process -----------------------------------------------------

TEST_CASE("headless: the cube is drawn, centred, the background in the corners, deterministic") {
  const int w = 240, h = 160;
  HeadlessRenderer r(w, h);
  CHECK(r.description().find("OpenGL") != std::string::npos);
  SurfaceMesh m = cube();
  Scene scene = scene_of(m, NamedView::Iso, static_cast<float>(w) / h);
  UiState ui;
  ui.show_panel = false;
  scene.display.legend = false;
  Image a = r.render(scene, ui, w, h);
  REQUIRE(a.width == w);
  REQUIRE(a.height == h);
  Coverage c = foreground(a, kWhite);
  CHECK(c.fraction > 0.15);
  CHECK(c.fraction < 0.9);
  CHECK(std::abs(c.cx - w / 2.0) < 0.08 * w);
  CHECK(std::abs(c.cy - h / 2.0) < 0.08 * h);
  for (auto [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}})
    for (int k = 0; k < 3; ++k) CHECK(a.pixel(x, y)[k] == 255);
  // The ridges (blue) and corners (yellow) are drawn.
  int blue = 0, yellow = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto* p = a.pixel(x, y);
      blue += p[2] > 150 && p[0] < 60;
      yellow += p[0] > 200 && p[1] > 150 && p[2] < 60;
    }
  CHECK(blue > 50);
  CHECK(yellow > 10);
  // Same scene, same pixels; another view, another picture.
  Image b = r.render(scene, ui, w, h);
  CHECK(a.rgba == b.rgba);
  scene.camera.set_view(NamedView::Top);
  scene.fit_camera(static_cast<float>(w) / h);
  Image top = r.render(scene, ui, w, h);
  CHECK(mean_abs_diff(a, top) > 3.0);
  // The wireframe and flat shading change the picture; the panel adds pixels.
  scene.display.wireframe = true;
  Image wire = r.render(scene, ui, w, h);
  CHECK(mean_abs_diff(top, wire) > 0.5);
  ui.show_panel = true;
  Image panel = r.render(scene, ui, 480, 320);
  CHECK(panel.width == 480);
  CHECK(foreground(panel, kWhite).fraction > c.fraction * 0.5);
}

TEST_CASE("headless: colour quantities use the colormap, highlighted triangles stand out") {
  const int w = 200, h = 200;
  HeadlessRenderer r(w, h);
  SurfaceMesh m = cube();
  Property<FieldValue> f = m.add_field("metric", FieldKind::Tensor, 6);
  for (int v = 0; v < m.vertex_capacity(); ++v) f[Vertex(v)] = {4, 0, 4, 0, 0, 4};  // h = 0.5: every edge too long
  MeshStructure ms = make_mesh_structure(m, "cube");
  highlight(ms, {2}, {});  // on the face z = 1, seen from the iso view
  Scene scene;
  scene.surfaces.push_back(ms.structure);
  scene.surfaces[0].activate(quantity::kLength);
  scene.camera.set_view(NamedView::Iso);
  scene.fit_camera(1.0f);
  scene.display.legend = false;
  UiState ui;
  ui.show_panel = false;
  Image img = r.render(scene, ui, w, h);
  // Metric lengths 2 and 2.8 (> range max 2): coolwarm's red end dominates.
  int red = 0, pink = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto* p = img.pixel(x, y);
      red += p[0] > 100 && p[1] < 40 && p[2] < 60;
      pink += p[0] > 180 && p[1] < 80 && p[2] > 80;  // the highlight colour
    }
  CHECK(red > 0.1 * w * h);
  CHECK(pink > 100);
}

TEST_CASE("headless: a second structure from a bare triangle set (a sampled surface) is drawn too") {
  const int w = 240, h = 160;
  HeadlessRenderer r(w, h);
  SurfaceMesh m = cube();
  Scene scene;
  scene.surfaces.push_back(make_mesh_structure(m, "cube").structure);
  // A sampled surface: a 16 x 16 grid over a paraboloid beside the cube,
  // smooth normals left to the renderer (no corner normals).
  SurfaceStructure sampled;
  sampled.name = "sampled surface";
  sampled.color = {0.1f, 0.8f, 0.2f};
  const int n = 16;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      float u = static_cast<float>(i) / n, v = static_cast<float>(j) / n;
      sampled.geometry.positions.emplace_back(2.0f + u, 0.2f * (u * u + v * v), v);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      unsigned a = static_cast<unsigned>(i * (n + 1) + j), b = a + n + 1;
      sampled.geometry.triangles.emplace_back(a, a + 1, b + 1);
      sampled.geometry.triangles.emplace_back(a, b + 1, b);
    }
  sampled.version = 1;
  scene.surfaces.push_back(sampled);
  scene.camera.set_view(NamedView::Iso);
  scene.fit_camera(static_cast<float>(w) / h);
  scene.display.legend = false;
  UiState ui;
  ui.show_panel = false;
  auto green_pixels = [&](const Image& img) {
    int count = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto* p = img.pixel(x, y);
        count += p[1] > p[0] + 60 && p[1] > p[2] + 60;
      }
    return count;
  };
  Image both = r.render(scene, ui, w, h);
  CHECK(green_pixels(both) > 0.05 * w * h);
  scene.surfaces[1].enabled = false;
  Image cube_only = r.render(scene, ui, w, h);
  CHECK(green_pixels(cube_only) == 0);
}

// --- `anisurf shot` on the shared meshes ------------------------------------------------

namespace {

// Bounding box centre of the pixels that differ from the background.
std::pair<double, double> foreground_box_centre(const Image& img) {
  int x0 = img.width, y0 = img.height, x1 = -1, y1 = -1;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (!std::equal(kWhite, kWhite + 3, img.pixel(x, y))) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  return {0.5 * (x0 + x1 + 1), 0.5 * (y0 + y1 + 1)};
}

// Renders a shared mesh with `args`, checks the common properties (not blank,
// the object's box centred and its pixel centroid within `centroid_tolerance`
// of the centre, background in the corners), returns the picture.
Image shot_checked(const std::string& mesh, const std::string& args, const std::filesystem::path& dir,
                   const std::string& name, double centroid_tolerance = 0.12) {
  std::string out = (dir / (name + ".png")).string();
  Run r = run_anisurf("shot \"" + mesh + "\" " + args + " -o \"" + out + "\"", dir);
  CAPTURE(args);
  CAPTURE(r.err);
  REQUIRE(r.code == 0);
  Image img = read_png(out);
  Coverage c = foreground(img, kWhite);
  CHECK(c.fraction > 0.04);  // not blank
  CHECK(c.fraction < 0.95);
  CHECK(std::abs(c.cx - img.width / 2.0) < centroid_tolerance * img.width);  // centred
  CHECK(std::abs(c.cy - img.height / 2.0) < centroid_tolerance * img.height);
  auto [bx, by] = foreground_box_centre(img);
  CHECK(std::abs(bx - img.width / 2.0) < 0.04 * img.width);
  CHECK(std::abs(by - img.height / 2.0) < 0.04 * img.height);
  for (auto [x, y] : {std::pair{0, 0}, {img.width - 1, 0}, {0, img.height - 1}, {img.width - 1, img.height - 1}})
    CHECK(std::equal(kWhite, kWhite + 3, img.pixel(x, y)));
  return img;
}

// Compares with tests/data/ref/NAME.png (mean absolute difference of RGB).
void compare_reference(const Image& img, const std::string& name, const std::string& command) {
  std::string ref = anisurf::test::data_file("ref/" + name + ".png");
  INFO("reference " << ref << "; to update it after a deliberate change: anisurf " << command << " -o " << ref);
  REQUIRE(std::filesystem::exists(ref));
  Image expected = read_png(ref);
  REQUIRE(expected.width == img.width);
  REQUIRE(expected.height == img.height);
  CHECK(mean_abs_diff(img, expected) < 1.5);
}

}  // namespace

TEST_CASE("shot: bunny, views differ, the same command gives the same bytes, matches the reference") {
  ANISURF_REQUIRE_SHARED(bunny, "meshes/bunny.off");
  auto dir = anisurf::test::temp_dir("render_bunny");
  const std::string args = "--size 320x200 --view iso";
  Image iso = shot_checked(bunny, args, dir, "iso");
  Image again = shot_checked(bunny, args, dir, "iso_again");
  CHECK(slurp(dir / "iso.png") == slurp(dir / "iso_again.png"));
  Image front = shot_checked(bunny, "--size 320x200 --view front", dir, "front");
  CHECK(mean_abs_diff(iso, front) > 3.0);
  Image ortho = shot_checked(bunny, "--size 320x200 --view front --ortho", dir, "ortho");
  CHECK(mean_abs_diff(front, ortho) > 0.3);
  compare_reference(iso, "bunny_iso", "shot " + bunny + " " + args);
}

TEST_CASE("shot: fandisk with wireframe, flat shading, orthographic front view") {
  ANISURF_REQUIRE_SHARED(fandisk, "meshes/fandisk.off");
  auto dir = anisurf::test::temp_dir("render_fandisk");
  const std::string args = "--size 320x200 --wire --flat --ortho --view front";
  Image wire = shot_checked(fandisk, args, dir, "wire");
  Image plain = shot_checked(fandisk, "--size 320x200 --flat --ortho --view front", dir, "plain");
  // Wireframe lines darken the surface.
  auto mean = [](const Image& im) {
    double s = 0;
    for (std::size_t i = 0; i < im.rgba.size(); i += 4) s += im.rgba[i] + im.rgba[i + 1] + im.rgba[i + 2];
    return s / static_cast<double>(im.rgba.size());
  };
  CHECK(mean(wire) < mean(plain) - 2.0);
  compare_reference(wire, "fandisk_wire", "shot " + fandisk + " " + args);
}

TEST_CASE("shot: falcon coloured by reference, views, the legend") {
  ANISURF_REQUIRE_SHARED(falcon, "meshes/falcon.mesh");
  auto dir = anisurf::test::temp_dir("render_falcon");
  // The swept wings make the silhouette lopsided: a wider centroid tolerance.
  Image img = shot_checked(falcon, "--size 400x250 --color ref --no-legend", dir, "ref", 0.2);
  // Many distinct colours: the 29 references, shaded.
  std::set<std::uint32_t> colors;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4)
    colors.insert(img.rgba[i] >> 4 << 8 | img.rgba[i + 1] >> 4 << 4 | img.rgba[i + 2] >> 4);
  CHECK(colors.size() > 150);
  Image top = shot_checked(falcon, "--size 400x250 --color ref --no-legend --view top", dir, "top", 0.2);
  CHECK(mean_abs_diff(img, top) > 3.0);
  // With the legend (bottom right): more non-background pixels there.
  const std::string args = "--size 400x250 --color ref";
  Run r = run_anisurf("shot \"" + falcon + "\" " + args + " -o " + (dir / "legend.png").string(), dir);
  REQUIRE(r.code == 0);
  Image legend = read_png((dir / "legend.png").string());
  CHECK(!std::equal(kWhite, kWhite + 3, legend.pixel(legend.width - 40, legend.height - 30)));
  CHECK(std::equal(kWhite, kWhite + 3, img.pixel(img.width - 40, img.height - 30)));
  compare_reference(legend, "falcon_ref", "shot " + falcon + " " + args);
}

TEST_CASE("shot: metric glyphs and colours on the demo, --ui draws the panel") {
  std::string demo = anisurf::test::data_file("../../assets/demo.mesh");
  std::string sol = anisurf::test::data_file("../../assets/demo.sol");
  REQUIRE(std::filesystem::exists(demo));
  auto dir = anisurf::test::temp_dir("render_demo");
  Image plain = shot_checked(demo, "--size 320x240 --sol " + sol, dir, "plain");
  Image glyphs = shot_checked(demo, "--size 320x240 --no-legend --glyphs --sol " + sol, dir, "glyphs");
  CHECK(mean_abs_diff(plain, glyphs) > 1.0);
  for (const char* c : {"quality", "length", "size", "aniso"}) {
    Image col = shot_checked(demo, std::string("--size 320x240 --no-legend --color ") + c + " --sol " + sol, dir, c);
    CHECK(mean_abs_diff(plain, col) > 5.0);
  }
  Run r = run_anisurf("shot " + demo + " --ui --size 640x400 -o " + (dir / "ui.png").string(), dir);
  REQUIRE(r.code == 0);
  Image ui = read_png((dir / "ui.png").string());
  // The panel sits in the top-left corner: not background there any more.
  CHECK(!std::equal(kWhite, kWhite + 3, ui.pixel(40, 40)));
}

TEST_CASE("shot: bad command lines give a clear message and exit code 2, bad input 1") {
  std::string demo = anisurf::test::data_file("../../assets/demo.mesh");
  auto dir = anisurf::test::temp_dir("render_bad");
  std::string out = " -o " + (dir / "x.png").string();
  struct Case {
    std::string args;
    int code;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           {demo + " --size 10x10" + out, 2, "--size expects WIDTHxHEIGHT"},
           {demo + " --size big" + out, 2, "--size expects"},
           {demo + " --view sideways" + out, 2, "--view expects iso|front"},
           {demo + " --color rainbow" + out, 2, "--color expects"},
           {demo + " --color field" + out, 2, "--color field needs the field's name"},
           {demo + " --colormap jet" + out, 2, "--colormap expects viridis or coolwarm"},
           {demo + " --range 2:1" + out, 2, "--range expects MIN:MAX"},
           {demo + " --highlight-tri 0" + out, 2, "numbered from 1"},
           {demo, 2, "missing -o OUT.png"},
           {demo + " -o " + (dir / "x.jpg").string(), 2, "must be a .png"},
           {demo + " --frobnicate" + out, 2, "unknown option '--frobnicate'"},
           {demo + " --glyphs" + out, 1, "--glyphs needs a metric"},
           {demo + " --color size" + out, 1, "--color size needs a metric"},
           {demo + " --highlight-tri 100000" + out, 1, "triangle 100000 does not exist"},
           {(dir / "absent.mesh").string() + out, 1, "absent.mesh"},
       }) {
    CAPTURE(c.args);
    Run r = run_anisurf("shot " + c.args, dir);
    CAPTURE(r.err);
    CHECK(r.code == c.code);
    CHECK(r.err.find(c.message) != std::string::npos);
  }
  CHECK(!std::filesystem::exists(dir / "x.png"));
  Run help = run_anisurf("shot --help", dir);
  CHECK(help.code == 0);
  CHECK(help.out.find("example:") != std::string::npos);
  CHECK(help.out.find("anisurf shot") != std::string::npos);
}

TEST_CASE("view: without a display it says what to do instead, under Xvfb it orbits and reports fps") {
  auto dir = anisurf::test::temp_dir("render_view");
  std::string demo = anisurf::test::data_file("../../assets/demo.mesh");
  Run r = run_anisurf_env("env -u DISPLAY -u WAYLAND_DISPLAY", "view " + demo + " --bench-orbit 2", dir);
  CHECK(r.code == 1);
  CHECK(r.err.find("anisurf shot") != std::string::npos);
  if (!std::filesystem::exists("/usr/bin/xvfb-run")) {
    MESSAGE("skipped the window: xvfb-run not installed");
    return;
  }
  Run w = run_anisurf_env("xvfb-run -a -s \"-screen 0 1280x800x24\"",
                          "view " + demo + " --bench-orbit 8 --size 480x320 --wire", dir);
  CAPTURE(w.err);
  CHECK(w.code == 0);
  CHECK(w.out.find("orbit: 8 frames") != std::string::npos);
  CHECK(w.out.find("fps") != std::string::npos);
}

#endif  // ANISURF_WITH_GL
