// The G1 Bezier surface (report section 3): planes reproduced, vertices
// interpolated, G1 across every interior non-feature edge, C0 across
// features, derivatives, third-order convergence on spheres, the hemisphere
// error, and the sampled mesh.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/error.h"
#include "geometry/bezier_surface.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "geometry/parallel_chunks.h"
#include "geometry/sample.h"
#include "io/mesh_io.h"
#include "mesh/stats.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using anisurf::test::angle;

namespace {

struct Built {
  SurfaceMesh mesh;
  SurfaceFrames frames;
  BezierSurface surface;
};

Built reconstruct(SurfaceMesh mesh, const NormalOptions& no = {}, const BezierOptions& bo = {},
                  const FeatureOptions& fo = {}) {
  Built b;
  b.mesh = std::move(mesh);
  detect_features(b.mesh, fo);
  b.frames = compute_frames(b.mesh, no);
  b.surface = BezierSurface(b.mesh, b.frames, bo);
  return b;
}

// Barycentric coordinates of parameter u along the edge opposite corner c
// (from edge_from(c) at u = 0 to edge_to(c) at u = 1).
Bary on_edge(Corner c, double u) {
  const int k = SurfaceMesh::local_index(c);
  Bary b{0, 0, 0};
  b[(k + 1) % 3] = 1 - u;
  b[(k + 2) % 3] = u;
  return b;
}

struct EdgeCheck {
  double max_normal_angle = 0;  // over interior non-feature edges
  double max_gap = 0;           // position difference, every interior edge
  double max_ridge_gap = 0;     // position difference on feature edges
  int smooth_edges = 0, feature_edges = 0;
};

// Evaluates both sides of every interior edge at `samples` inner points.
EdgeCheck check_edges(const SurfaceMesh& m, const BezierSurface& s, int samples = 7) {
  EdgeCheck r;
  for (int c = 0; c < 3 * m.triangle_capacity(); ++c) {
    const Corner e(c);
    if (m.is_deleted(SurfaceMesh::triangle(e))) continue;
    const Corner o = m.opposite(e);
    if (!o.is_valid() || o < e) continue;
    const bool feature = is_feature_edge(m, e);
    (feature ? r.feature_edges : r.smooth_edges)++;
    for (int i = 1; i <= samples; ++i) {
      const double u = double(i) / (samples + 1);
      const SurfacePoint a = s.evaluate(SurfaceMesh::triangle(e), on_edge(e, u));
      const SurfacePoint b = s.evaluate(SurfaceMesh::triangle(o), on_edge(o, 1 - u));
      const double gap = norm(a.position - b.position);
      r.max_gap = std::fmax(r.max_gap, gap);
      if (feature) r.max_ridge_gap = std::fmax(r.max_ridge_gap, gap);
      else r.max_normal_angle = std::fmax(r.max_normal_angle, angle(a.normal, b.normal));
    }
  }
  return r;
}

double max_vertex_gap(const SurfaceMesh& m, const BezierSurface& s) {
  double mx = 0;
  for (int t = 0; t < m.triangle_capacity(); ++t) {
    if (m.is_deleted(Triangle(t))) continue;
    for (int k = 0; k < 3; ++k) {
      Bary b{0, 0, 0};
      b[k] = 1;
      mx = std::fmax(mx, norm(s.position(Triangle(t), b) - m.position(m.vertex(Triangle(t), k))));
    }
  }
  return mx;
}

// A tilted, shifted copy of a grid: the plane n . x = d.
MeshData tilted_plane(Vec3& n, double& d) {
  MeshData g = test::square_grid(6);
  const Vec3 u = normalized(Vec3(1, 0.3, -0.4)), w = normalized(cross(u, Vec3(0.2, 1, 0.5))), v = cross(w, u);
  for (Vec3& p : g.vertices) {
    // a jittered grid, so that edges are not parallel
    const double x = p.x + 0.03 * std::sin(7 * p.y), y = p.y + 0.03 * std::cos(5 * p.x);
    p = Vec3(0.5, -1, 2) + x * u + y * v;
  }
  n = w;
  d = dot(w, Vec3(0.5, -1, 2));
  return g;
}

}  // namespace

TEST_CASE("surface: a plane is reproduced exactly, with and without features, for every option") {
  Vec3 n;
  double d;
  const MeshData g = tilted_plane(n, d);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  for (auto handle : {BezierOptions::Handle::Circular, BezierOptions::Handle::Projection})
    for (bool g1 : {true, false})
      for (bool ridge : {false, true}) {
        BezierOptions bo;
        bo.handle = handle;
        bo.g1_corrections = g1;
        FeatureOptions fo;
        if (ridge) fo.add_ridges = {{8, 16}, {16, 24}};  // an inner polyline
        const Built b = reconstruct(test::build(g), {}, bo, fo);
        double off = 0, normal_dev = 0;
        for (int t = 0; t < b.mesh.triangle_capacity(); ++t)
          for (int i = 0; i < 20; ++i) {
            double x = U(rng), y = U(rng);
            if (x + y > 1) x = 1 - x, y = 1 - y;
            const SurfacePoint p = b.surface.evaluate(Triangle(t), {1 - x - y, x, y});
            off = std::fmax(off, std::fabs(dot(p.position, n) - d));
            normal_dev = std::fmax(normal_dev, norm(p.normal - n));
          }
        CHECK(off < 1e-12);
        CHECK(normal_dev < 1e-9);
      }
}

TEST_CASE("surface: the cube is reproduced exactly (flat faces, C0 along its ridges)") {
  const Built b = reconstruct(test::build(test::cube()));
  for (int t = 0; t < b.mesh.triangle_capacity(); ++t) {
    const Vec3 fn = normalized(b.mesh.triangle_normal(Triangle(t)));
    const double d = dot(fn, b.mesh.position(b.mesh.vertex(Triangle(t), 0)));
    for (double x : {0.1, 0.3, 0.6})
      for (double y : {0.05, 0.2, 0.35}) {
        const SurfacePoint p = b.surface.evaluate(Triangle(t), {1 - x - y, x, y});
        CHECK(std::fabs(dot(fn, p.position) - d) < 1e-12);
        CHECK(norm(p.normal - fn) < 1e-9);
      }
  }
  const EdgeCheck ec = check_edges(b.mesh, b.surface);
  CHECK(ec.feature_edges == 12);
  CHECK(ec.max_ridge_gap < 1e-12);
}

TEST_CASE("surface: interpolates the vertices, G1 across interior edges, C0 along the boundary (icosphere, hemi)") {
  const Built ico = reconstruct(test::build(test::icosphere(2)));
  CHECK(max_vertex_gap(ico.mesh, ico.surface) < 1e-14);
  EdgeCheck ec = check_edges(ico.mesh, ico.surface);
  CHECK(ec.smooth_edges == 480);
  CHECK(ec.max_normal_angle < 1e-6);
  CHECK(ec.max_gap < 1e-12);
  MESSAGE("icosphere(2): normal angle across edges " << ec.max_normal_angle << ", gap " << ec.max_gap);

  // the check can fail: without the G1 corrections the normals disagree
  BezierOptions plain;
  plain.g1_corrections = false;
  const Built ico_plain = reconstruct(test::build(test::icosphere(2)), {}, plain);
  CHECK(check_edges(ico_plain.mesh, ico_plain.surface).max_normal_angle > 1e-4);

  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  const Built hemi = reconstruct(load_mesh(path));
  CHECK(max_vertex_gap(hemi.mesh, hemi.surface) < 1e-14);
  ec = check_edges(hemi.mesh, hemi.surface);
  CHECK(ec.max_normal_angle < 1e-6);
  CHECK(ec.max_gap < 1e-12);
}

TEST_CASE("surface: derivatives match finite differences in every subtriangle") {
  const Built b = reconstruct(test::build(test::icosphere(1)));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0.02, 0.96);
  const double h = 1e-6;
  double worst = 0;
  for (int t = 0; t < b.mesh.triangle_capacity(); ++t)
    for (int i = 0; i < 10; ++i) {
      double x = U(rng), y = U(rng);
      if (x + y > 0.98) x = 0.98 - x * 0.5, y = 0.98 - x - 0.01;
      const SurfacePoint p = b.surface.evaluate(Triangle(t), {1 - x - y, x, y});
      // central differences along v1 - v0 and v2 - v0, kept inside one
      // subtriangle (the patch is C1 inside, so crossing would also be fine)
      const Vec3 fd1 = (b.surface.position(Triangle(t), {1 - x - h - y, x + h, y}) -
                        b.surface.position(Triangle(t), {1 - x + h - y, x - h, y})) /
                       (2 * h);
      const Vec3 fd2 = (b.surface.position(Triangle(t), {1 - x - y - h, x, y + h}) -
                        b.surface.position(Triangle(t), {1 - x - y + h, x, y - h})) /
                       (2 * h);
      worst = std::fmax(worst, norm(fd1 - p.d1) / norm(p.d1));
      worst = std::fmax(worst, norm(fd2 - p.d2) / norm(p.d2));
      CHECK(std::fabs(norm(p.normal) - 1) < 1e-12);
      CHECK(dot(p.normal, p.position) > 0);  // outward on the sphere
    }
  CHECK(worst < 1e-6);
}

TEST_CASE("surface: flat_deviation bounds the distance of every patch point from its flat triangle, and is reached") {
  // A coarse sphere (curved patches) and the cube (flat faces, ridges).
  for (const Built& b : {reconstruct(test::build(test::icosphere(1))), reconstruct(test::build(test::cube()))}) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    double largest_bound = 0;
    for (Triangle t : b.mesh.triangles()) {
      const int* v = b.mesh.triangle_vertices(t);
      const std::array<Vec3, 3> x = {b.mesh.position(Vertex(v[0])), b.mesh.position(Vertex(v[1])),
                                     b.mesh.position(Vertex(v[2]))};
      const double dev = b.surface.flat_deviation(t, x);
      largest_bound = std::max(largest_bound, dev);
      double seen = 0;
      for (int i = 0; i < 400; ++i) {
        double p = U(rng), q = U(rng);
        if (p + q > 1) p = 1 - p, q = 1 - q;
        const Bary bc{1 - p - q, p, q};
        const Vec3 flat = bc[0] * x[0] + bc[1] * x[1] + bc[2] * x[2];
        seen = std::max(seen, norm(b.surface.position(t, bc) - flat));
      }
      CHECK(seen <= dev);
      // A bound, not far above what the patch reaches (the control net of a
      // smooth patch stays close to it).
      CHECK(dev <= 4 * seen + 1e-12);
    }
    if (b.mesh.n_triangles() == 12) CHECK(largest_bound < 1e-12);  // the cube's flat faces
    if (b.mesh.n_triangles() != 12) CHECK(largest_bound > 1e-3);
  }
}

TEST_CASE("surface: on icospheres the distance to the sphere falls at third order or better") {
  std::vector<double> err, h;
  for (int level = 1; level <= 4; ++level) {
    const Built b = reconstruct(test::build(test::icosphere(level)));
    err.push_back(test::max_sphere_distance(b.mesh, b.surface, 8));
    h.push_back(compute_stats(b.mesh).max_edge);
  }
  for (std::size_t i = 1; i < err.size(); ++i) {
    const double rate = std::log(err[i - 1] / err[i]) / std::log(h[i - 1] / h[i]);
    MESSAGE("icosphere level " << i + 1 << ": h " << h[i] << ", max distance " << err[i] << ", rate " << rate);
    CHECK(rate > 2.8);
  }
}

TEST_CASE("surface: on tori (not exact for any of the estimators) the distance falls at third order") {
  const double R = 1, r = 0.4;
  auto torus = [&](int n, int m) {
    MeshData d;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = 2 * std::numbers::pi * (i + 0.5 * (j % 2)) / n, v = 2 * std::numbers::pi * j / m;
        d.vertices.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
      }
    auto id = [&](int i, int j) { return ((j + m) % m) * n + ((i + n) % n); };
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < n; ++i) {
        if (j % 2 == 0) {
          d.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
          d.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        } else {
          d.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
          d.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
      }
    return d;
  };
  auto distance = [&](const Vec3& p) { return std::fabs(std::hypot(std::hypot(p.x, p.y) - R, p.z) - r); };
  std::vector<double> err;
  for (int n : {24, 48, 96}) {
    const Built b = reconstruct(test::build(torus(n, n / 2)));
    double mx = 0;
    for (int t = 0; t < b.mesh.triangle_capacity(); ++t)
      for (int j = 0; j <= 6; ++j)
        for (int i = 0; i + j <= 6; ++i)
          mx = std::fmax(mx, distance(b.surface.position(Triangle(t), {(6.0 - i - j) / 6, i / 6.0, j / 6.0})));
    err.push_back(mx);
  }
  for (std::size_t i = 1; i < err.size(); ++i) {
    const double rate = std::log2(err[i - 1] / err[i]);
    MESSAGE("torus " << 24 * (1 << i) << " x " << 12 * (1 << i) << ": max distance " << err[i] << ", rate " << rate);
    CHECK(rate > 2.8);
  }
}

TEST_CASE("surface: hemi.mesh sampled with k = 4 stays within 5e-3 of the unit sphere") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  const SurfaceMesh input = load_mesh(path);
  const Built b = reconstruct(input);
  const SurfaceMesh fine = sample_surface(b.mesh, b.surface, 4);
  double dmax = 0;
  for (int v = 0; v < fine.vertex_capacity(); ++v) dmax = std::fmax(dmax, std::fabs(norm(fine.position(Vertex(v))) - 1));
  // the other constructions, for the record
  NormalOptions aw;
  aw.method = NormalOptions::Method::AngleWeighted;
  aw.mirror_iterations = 0;
  NormalOptions fit;
  fit.mirror_iterations = 0;
  BezierOptions proj;
  proj.handle = BezierOptions::Handle::Projection;
  proj.g1_corrections = false;
  const Built b_aw = reconstruct(input, aw, proj), b_fit = reconstruct(input, fit, proj), b_fit_c = reconstruct(input, fit);
  MESSAGE("hemi k=4 max vertex distance: " << dmax << " (cubic + projection with angle-weighted normals "
                                           << test::max_sphere_distance(b_aw.mesh, b_aw.surface, 4) << ", with fitted normals "
                                           << test::max_sphere_distance(b_fit.mesh, b_fit.surface, 4)
                                           << "; G1 quartic with fitted normals without consistency "
                                           << test::max_sphere_distance(b_fit_c.mesh, b_fit_c.surface, 4) << ")");
  CHECK(dmax < 5e-3);
  CHECK(dmax < 1e-3);
}

TEST_CASE("sample: k^2 split, shared edge points, tags and references kept") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  const Built b = reconstruct(load_mesh(path));
  const MeshStats in = compute_stats(b.mesh);
  for (int k : {1, 2, 3, 4}) {
    const SurfaceMesh fine = sample_surface(b.mesh, b.surface, k);
    auto rep = fine.validate();
    INFO(rep.summary());
    CHECK(rep.ok());
    const MeshStats out = compute_stats(fine);
    CHECK(out.triangles == in.triangles * k * k);
    CHECK(out.vertices == in.vertices + in.edges * (k - 1) + in.triangles * (k - 1) * (k - 2) / 2);
    CHECK(out.boundary_edges == in.boundary_edges * k);
    CHECK(out.listed_edges == in.listed_edges * k);
    CHECK(out.boundary_loops == 1);
    CHECK(out.euler_characteristic == in.euler_characteristic);
  }
  // edge refs carried over
  const SurfaceMesh fine = sample_surface(b.mesh, b.surface, 3);
  int ref1 = 0;
  for (int c = 0; c < 3 * fine.triangle_capacity(); ++c)
    if (fine.is_boundary_edge(Corner(c))) ref1 += fine.edge_ref(Corner(c)) == 1;
  CHECK(ref1 == 72);
  CHECK_THROWS_AS(sample_surface(b.mesh, b.surface, 0), Error);
}

TEST_CASE("sample: ridges stay ridges, corners stay corners, triangle references kept (cube)") {
  MeshData d = test::cube();
  for (std::size_t t = 0; t < d.triangles.size(); ++t) d.triangle_refs.push_back(static_cast<int>(t / 2) + 1);
  FeatureOptions fo;
  fo.reference_interfaces = false;  // the ridges come from the dihedral angle
  const Built b = reconstruct(test::build(d), {}, {}, fo);
  const SurfaceMesh fine = sample_surface(b.mesh, b.surface, 3);
  CHECK(fine.validate().ok());
  const MeshStats s = compute_stats(fine);
  CHECK(s.ridge_edges == 36);
  CHECK(s.corner_vertices == 8);
  CHECK(s.triangle_refs == 6);
  // every sampled vertex on the cube's surface
  for (int v = 0; v < fine.vertex_capacity(); ++v) {
    const Vec3 p = fine.position(Vertex(v));
    const double dist = std::fmin(std::fmin(std::fmin(std::fabs(p.x), std::fabs(p.x - 1)), std::fmin(std::fabs(p.y), std::fabs(p.y - 1))),
                                  std::fmin(std::fabs(p.z), std::fabs(p.z - 1)));
    CHECK(dist < 1e-12);
  }
}

TEST_CASE("surface: the stored points assemble patches that agree bitwise along every edge and satisfy the C1 conditions") {
  // Each point is stored once (vertices, 2 cubic points per edge, the 9
  // corrected points per triangle) and the rest recomputed: both sides of an
  // edge must rebuild the very same boundary curve, and a corrected patch its
  // centre and inner-edge points from the Clough-Tocher C1 conditions.
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  for (const bool g1 : {true, false}) {
    BezierOptions bo;
    bo.g1_corrections = g1;
    const Built b = reconstruct(load_mesh(path), {}, bo);
    const SurfaceMesh& m = b.mesh;
    int compared = 0;
    double c1_gap = 0;
    for (int t = 0; t < m.triangle_capacity(); ++t) {
      if (m.is_deleted(Triangle(t))) continue;
      const BezierSurface::Patch P = b.surface.patch(Triangle(t));
      for (int k = 0; k < 3; ++k) {
        const Corner c = SurfaceMesh::corner(Triangle(t), k), o = m.opposite(c);
        if (!o.is_valid()) continue;
        const BezierSurface::Patch Q = b.surface.patch(SurfaceMesh::triangle(o));
        const int ko = SurfaceMesh::local_index(o);
        for (int i = 0; i < 3; ++i) {
          const Vec3& p = P[4 + 3 * k + i];
          const Vec3& q = Q[4 + 3 * ko + 2 - i];
          CHECK((p.x == q.x && p.y == q.y && p.z == q.z));
        }
        ++compared;
      }
      // diamonds: inner-edge point (j, 1) is the mean of (j, 0) and the two
      // points beside it; (j, 2) likewise; the centre the mean of the (j, 2)
      for (int j = 0; j < 3; ++j) {
        const Vec3 m1 = (P[22 + 2 * ((j + 2) % 3)] + P[23 + 2 * ((j + 1) % 3)] + P[13 + 3 * j]) / 3.0;
        const Vec3 m2 = (P[28 + (j + 2) % 3] + P[28 + (j + 1) % 3] + P[14 + 3 * j]) / 3.0;
        c1_gap = std::fmax(c1_gap, std::fmax(norm(P[14 + 3 * j] - m1), norm(P[15 + 3 * j] - m2)));
      }
      c1_gap = std::fmax(c1_gap, norm(P[3] - (P[15] + P[18] + P[21]) / 3.0));
    }
    CHECK(compared > 0);
    CHECK(c1_gap < 1e-14);
  }
}

TEST_CASE("surface: built on one thread or on several, every patch is bitwise the same") {
  // The edges' cubic points and G1 corrections run in parallel chunks of the
  // edges (each edge moves only its own points): the chunks must not change
  // a bit. An icosphere of 30720 edges (4 chunks), its vertices moved off the
  // sphere so that the corrections differ from edge to edge.
  const MeshData d = test::jittered_icosphere(5, 0.97, 1.03, 7);
  const test::ThreadLimitScope scope(thread_limit().load());
  thread_limit() = 1;
  const Built one = reconstruct(test::build(d));
  thread_limit() = 3;
  const Built several = reconstruct(test::build(d));
  int compared = 0;
  for (int t = 0; t < one.mesh.triangle_capacity(); ++t) {
    if (one.mesh.is_deleted(Triangle(t))) continue;
    const BezierSurface::Patch P = one.surface.patch(Triangle(t)), Q = several.surface.patch(Triangle(t));
    bool same = true;
    for (std::size_t i = 0; i < P.size(); ++i) same = same && P[i].x == Q[i].x && P[i].y == Q[i].y && P[i].z == Q[i].z;
    CHECK(same);
    ++compared;
  }
  CHECK(compared == 20480);
}
