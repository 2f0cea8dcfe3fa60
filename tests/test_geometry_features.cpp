// Features (ridges, boundaries, interfaces, corners, user edits) and the
// tangent planes per sector with the feature-curve tangents.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using anisurf::test::angle;

namespace {

int count_edges(const SurfaceMesh& m, Tag tag) {
  int n = 0;
  for (int c = 0; c < 3 * m.triangle_capacity(); ++c)
    if (m.canonical(Corner(c)) == Corner(c) && m.has_tag(Corner(c), tag)) ++n;
  return n;
}

int count_vertices(const SurfaceMesh& m, Tag tag) {
  int n = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v)
    if (m.has_tag(Vertex(v), tag)) ++n;
  return n;
}

}  // namespace

TEST_CASE("features: the cube's 12 edges are ridges, its 8 vertices corners, -nr and a wider angle find none") {
  SurfaceMesh m = test::build(test::cube());
  FeatureReport r = detect_features(m);
  CHECK(r.detected_ridges == 12);
  CHECK(count_edges(m, kRidge) == 12);
  CHECK(r.corners == 8);
  CHECK(count_vertices(m, kCorner) == 8);
  CHECK(r.feature_vertices == 8);
  // idempotent
  r = detect_features(m);
  CHECK(count_edges(m, kRidge) == 12);
  CHECK(r.detected_ridges == 0);  // already tagged

  SurfaceMesh m2 = test::build(test::cube());
  FeatureOptions no_ridges;
  no_ridges.detect_ridges = false;
  r = detect_features(m2, no_ridges);
  CHECK(count_edges(m2, kRidge) == 0);
  CHECK(r.corners == 0);

  SurfaceMesh m3 = test::build(test::cube());
  FeatureOptions wide;
  wide.ridge_angle_deg = 91;
  detect_features(m3, wide);
  CHECK(count_edges(m3, kRidge) == 0);
}

TEST_CASE("features: boundaries, square corners by turning angle, interfaces between references") {
  MeshData d = test::square_grid(4);
  // left half reference 1, right half reference 2
  for (const auto& t : d.triangles) {
    const double cx = (d.vertices[t[0]].x + d.vertices[t[1]].x + d.vertices[t[2]].x) / 3;
    d.triangle_refs.push_back(cx < 0.5 ? 1 : 2);
  }
  SurfaceMesh m = test::build(d);
  FeatureReport r = detect_features(m);
  CHECK(r.boundary_edges == 16);
  CHECK(r.interface_edges == 4);  // the line x = 0.5
  CHECK(r.detected_ridges == 0);
  CHECK(r.feature_edges == 20);
  // 4 square corners (turn 90 deg) + 2 ends of the interface (3 feature edges)
  CHECK(r.corners == 6);
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    const Vec3 p = m.position(Vertex(v));
    const bool square_corner = (p.x == 0 || p.x == 1) && (p.y == 0 || p.y == 1);
    const bool interface_end = p.x == 0.5 && (p.y == 0 || p.y == 1);
    CHECK(m.has_tag(Vertex(v), kCorner) == (square_corner || interface_end));
  }
  // a sharper corner threshold keeps the square's corners as corners (90 > 45)
  // but a threshold above 90 drops them
  SurfaceMesh m2 = test::build(d);
  FeatureOptions o;
  o.corner_angle_deg = 95;
  o.reference_interfaces = false;
  r = detect_features(m2, o);
  CHECK(r.corners == 0);
  CHECK(r.feature_edges == 16);
}

TEST_CASE("features: user edits add and remove ridges and corners, bad ids are refused with a message") {
  SurfaceMesh m = test::build(test::square_grid(2));
  FeatureOptions o;
  o.add_ridges = {{0, 4}};  // the diagonal of the first cell
  o.add_corners = {4};
  o.remove_corners = {0};
  detect_features(m, o);
  CHECK(m.has_tag(m.find_edge(Vertex(0), Vertex(4)).is_valid() ? m.find_edge(Vertex(0), Vertex(4))
                                                                 : m.find_edge(Vertex(4), Vertex(0)),
                  kRidge));
  CHECK(m.has_tag(Vertex(4), kCorner));
  CHECK_FALSE(m.has_tag(Vertex(0), kCorner));
  CHECK(m.has_tag(Vertex(4), kRidge));

  FeatureOptions rm;
  rm.remove_ridges = {{0, 4}};
  detect_features(m, rm);
  CHECK(count_edges(m, kRidge) == 0);

  FeatureOptions bad;
  bad.add_ridges = {{0, 8}};  // opposite corners of the square: not an edge
  CHECK_THROWS_WITH_AS(detect_features(m, bad), doctest::Contains("not an edge"), Error);
  FeatureOptions bad2;
  bad2.add_corners = {100};
  CHECK_THROWS_WITH_AS(detect_features(m, bad2), doctest::Contains("vertex 100"), Error);
}

TEST_CASE("normals: circle tangents are exact for uneven spacing") {
  auto on_circle = [](double a) { return Vec3(std::cos(a), std::sin(a), 0.3); };
  for (double a0 : {0.1, 0.5}) {
    const double a1 = a0 + 0.4, a2 = a1 + 0.9;
    const Vec3 t = circle_tangent(on_circle(a0), on_circle(a1), on_circle(a2));
    CHECK(angle(t, Vec3(-std::sin(a1), std::cos(a1), 0)) < 1e-12);
  }
}

TEST_CASE("normals: exact on a plane, one per side of a ridge, corner sectors spanned by their curve tangents") {
  SurfaceMesh plane = test::build(test::square_grid(5));
  detect_features(plane);
  for (auto method : {NormalOptions::Method::AngleWeighted, NormalOptions::Method::LocalFit}) {
    NormalOptions o;
    o.method = method;
    const SurfaceFrames f = compute_frames(plane, o);
    for (int c = 0; c < 3 * plane.triangle_capacity(); ++c) CHECK(norm(f.normal(Corner(c)) - Vec3(0, 0, 1)) < 1e-12);
  }
  // cube: every vertex has 3 sectors; each sector normal is its face normal
  SurfaceMesh cube = test::build(test::cube());
  detect_features(cube);
  const SurfaceFrames f = compute_frames(cube);
  CHECK(f.n_sectors() == 24);
  for (int c = 0; c < 3 * cube.triangle_capacity(); ++c) {
    const Vec3 fn = normalized(cube.triangle_normal(SurfaceMesh::triangle(Corner(c))));
    CHECK(norm(f.normal(Corner(c)) - fn) < 1e-12);
  }
  // curve tangents on the cube are the edge directions
  for (int c = 0; c < 3 * cube.triangle_capacity(); ++c) {
    const Corner e(c);
    if (!cube.has_tag(e, kRidge)) continue;
    const Vec3 dir = normalized(cube.position(cube.edge_to(e)) - cube.position(cube.edge_from(e)));
    CHECK(norm(f.tangent_from(e) - dir) < 1e-12);
    CHECK(norm(f.tangent_to(e) + dir) < 1e-12);
  }
}

TEST_CASE("normals: on an icosphere the fitted normals beat the angle-weighted ones and are close to exact") {
  SurfaceMesh m = test::build(test::icosphere(2));
  detect_features(m);
  auto max_error = [&](const SurfaceFrames& f) {
    double e = 0;
    for (int s = 0; s < f.n_sectors(); ++s) e = std::fmax(e, angle(f.sector_normal(s), m.position(f.sector_vertex(s))));
    return e;
  };
  NormalOptions aw;
  aw.method = NormalOptions::Method::AngleWeighted;
  aw.mirror_iterations = 0;
  NormalOptions fit;
  fit.mirror_iterations = 0;
  const double e_aw = max_error(compute_frames(m, aw));
  const double e_fit = max_error(compute_frames(m, fit));
  const double e_default = max_error(compute_frames(m));
  MESSAGE("icosphere(2) max normal error: angle-weighted " << e_aw << ", fit " << e_fit << ", fit + consistency "
                                                           << e_default);
  CHECK(e_fit < e_aw);
  CHECK(e_default < 1e-3);
}

TEST_CASE("normals: hemi.mesh boundary normals are horizontal and radial (one-sided neighbourhoods corrected)") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  SurfaceMesh m = load_mesh(path);
  detect_features(m);
  auto boundary_error = [&](const SurfaceFrames& f) {
    double e = 0, all = 0;
    for (int s = 0; s < f.n_sectors(); ++s) {
      const double a = angle(f.sector_normal(s), m.position(f.sector_vertex(s)));
      all = std::fmax(all, a);
      if (m.is_boundary(f.sector_vertex(s))) e = std::fmax(e, a);
    }
    return std::array<double, 2>{e, all};
  };
  NormalOptions aw;
  aw.method = NormalOptions::Method::AngleWeighted;
  aw.mirror_iterations = 0;
  NormalOptions fit;
  fit.mirror_iterations = 0;
  const auto e_aw = boundary_error(compute_frames(m, aw));
  const auto e_fit = boundary_error(compute_frames(m, fit));
  const auto e_def = boundary_error(compute_frames(m));
  MESSAGE("hemi max normal error (boundary / all): angle-weighted " << e_aw[0] << " / " << e_aw[1] << ", fit "
                                                                   << e_fit[0] << " / " << e_fit[1]
                                                                   << ", fit + consistency " << e_def[0] << " / "
                                                                   << e_def[1]);
  CHECK(e_fit[1] < e_aw[1]);
  CHECK(e_def[0] < 0.01);
  CHECK(e_def[1] < 0.01);
}

TEST_CASE("normals: the file's NormalAtVertices are taken when asked") {
  SurfaceMesh m = test::build(test::icosphere(1));
  detect_features(m);
  auto n = m.vertex_property<Vec3>("normal");
  auto has = m.vertex_property<std::uint8_t>("has_normal", 0);
  // the exact normal turned by about 6 degrees
  const Vec3 exact = m.position(Vertex(0));
  const Vec3 tilted = normalized(exact + 0.1 * normalized(cross(exact, Vec3(0, 0, 1))));
  n[Vertex(0)] = tilted * 3.0;  // not unit: normalized on use
  has[Vertex(0)] = 1;
  NormalOptions o;
  const SurfaceFrames f = compute_frames(m, o);
  CHECK(f.from_file == 1);
  for (Corner c : m.fan(Vertex(0))) CHECK(norm(f.normal(c) - tilted) < 1e-12);
  // its neighbours' normals are still estimated (close to exact)
  const Vertex w = m.vertex(SurfaceMesh::next(m.corner(Vertex(0))));
  CHECK(angle(f.normal(m.corner(w)), m.position(w)) < 0.05);
  o.use_file_normals = false;
  CHECK(compute_frames(m, o).from_file == 0);
}

TEST_CASE("features: the same tags and counts on one thread and on several") {
  // An icosphere of 327680 triangles (3 chunks of edges and 3 of vertices
  // on 3 threads), its vertices moved so that a share of its edges turn past
  // the ridge angle, some of them meeting at corners.
  const MeshData d = test::jittered_icosphere(7, 0.996, 1.004, 5);
  const test::ThreadLimitScope scope(thread_limit().load());
  thread_limit() = 1;
  SurfaceMesh one = test::build(d);
  const FeatureReport r1 = detect_features(one);
  thread_limit() = 3;
  SurfaceMesh three = test::build(d);
  const FeatureReport r3 = detect_features(three);
  INFO("ridges " << r1.detected_ridges << ", corners " << r1.corners);
  CHECK(r1.detected_ridges > 100);
  CHECK(r1.corners > 0);
  CHECK(r1.detected_ridges == r3.detected_ridges);
  CHECK(r1.feature_edges == r3.feature_edges);
  CHECK(r1.feature_vertices == r3.feature_vertices);
  CHECK(r1.corners == r3.corners);
  int differ = 0, ridge_vertices = 0;
  for (int c = 0; c < one.corner_capacity(); ++c) differ += one.edge_tags(Corner(c)) != three.edge_tags(Corner(c));
  for (int v = 0; v < one.vertex_capacity(); ++v) {
    differ += one.vertex_tags(Vertex(v)) != three.vertex_tags(Vertex(v));
    ridge_vertices += one.has_tag(Vertex(v), kRidge);
  }
  CHECK(differ == 0);
  CHECK(ridge_vertices == r1.feature_vertices);  // no boundary: the feature vertices are the ridge vertices
}
