// Projection onto surface meshes (report 4.2, 4.3): the local descent from
// hints, certified or completed by the tree, agrees with a brute-force search
// on every shared mesh, on thin parts, across components, and when T_1's
// vertices are projected by topological propagation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <random>
#include <span>
#include <string>

#include "io/mesh_io.h"
#include "locate/locator.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// A triangle at most two rings away from t (a "good" hint: what a vertex of
// T_1 next to the query would hold).
int nearby_triangle(const SurfaceMesh& m, int t, std::mt19937_64& rng) {
  for (int ring = 0; ring < 2; ++ring) {
    const Vertex v = m.vertex(Triangle(t), static_cast<int>(rng() % 3));
    const std::vector<Corner> fan = m.fan(v);
    t = SurfaceMesh::triangle(fan[rng() % fan.size()]).idx;
  }
  return t;
}

struct Tally {
  int queries = 0, bad = 0, inconsistent = 0, certified = 0;
  long long steps = 0;
  void add(const SurfaceMesh& m, const Location& r, const Vec3& x, double ref_d2, double diag) {
    ++queries;
    if (!test::same_distance(r.distance, std::sqrt(ref_d2), diag)) ++bad;
    if (!test::consistent(m, r, x)) ++inconsistent;
    if (!r.used_fallback) ++certified;
    steps += r.steps;
  }
};

const char* kMeshes[] = {"bunny.off",    "spot.obj",      "fandisk.off",    "featuretype.STL", "fixed_top.ply",
                         "falcon.mesh",  "torus.STL",     "mmg_torus.mesh", "mmg_teapot.mesh", "mmg_cube.mesh",
                         "thinker.mesh", "camelhead.off", "beetle.off",     "bun_zipper_res2.ply",
                         "Box.glb",      "Duck.glb",      "Suzanne.gltf",   "Avocado.gltf"};

}  // namespace

TEST_CASE("projection with and without hints agrees with brute force on every shared mesh") {
  for (const char* f : kMeshes) {
    const std::string name = f;
    CAPTURE(name);
    const std::string path = test::shared_file(std::string("meshes/") + f);
    if (path.empty()) {
      MESSAGE("skipped: ../shared/meshes not found (no shared test data)");
      return;
    }
    const SurfaceMesh m = load_mesh(path);
    Locator loc(m);
    const test::PointSampler sample(m);
    const std::vector<int>& tris = sample.triangles();
    const double diag = m.bbox().diagonal();
    std::mt19937_64 rng(11);
    Tally none, good, far, on_surface;
    const int n_brute = std::clamp(6000000 / static_cast<int>(tris.size()), 150, 1500);
    for (int i = 0; i < n_brute; ++i) {
      const bool on = i % 4 == 0;
      const auto np = on ? sample(rng, 0, 0) : sample(rng, 1e-3, 5e-2);
      const double ref = test::brute_force_d2(m, tris, np.x);
      none.add(m, loc.project(np.x), np.x, ref, diag);
      const Location g = loc.project(np.x, Hint{Triangle(nearby_triangle(m, np.source, rng))});
      (on ? on_surface : good).add(m, g, np.x, ref, diag);
      far.add(m, loc.project(np.x, Hint{Triangle(tris[rng() % tris.size()])}), np.x, ref, diag);
    }
    for (const Tally* t : {&none, &good, &far, &on_surface}) {
      CHECK(t->bad == 0);
      CHECK(t->inconsistent == 0);
    }
    CHECK(none.steps == 0);
    CHECK(none.certified == 0);  // no hint: the tree answers
    // From a hint two rings away, a point on the surface is reached in a few
    // moves and certified locally in most cases (not on meshes whose
    // vertices touch other triangles: cracks, pinch points, slivers).
    CHECK(static_cast<double>(on_surface.steps) / on_surface.queries < 4.0);
    MESSAGE(name << ": " << n_brute << " queries against brute force; certified locally: on the surface "
              << on_surface.certified << "/" << on_surface.queries << ", near " << good.certified << "/"
              << good.queries << ", far hints " << far.certified << "/" << far.queries);

    // 2*10^4 hinted queries per mesh against the tree (itself checked above).
    int bad = 0;
    Hint prev;
    for (int i = 0; i < 20000; ++i) {
      const auto np = sample(rng, 1e-4, 2e-2);
      const Location g = loc.project(np.x, std::array<Hint, 2>{prev, Hint{Triangle(nearby_triangle(m, np.source, rng))}});
      const Location t = loc.project(np.x);
      if (!test::same_distance(g.distance, t.distance, diag) || !test::consistent(m, g, np.x)) ++bad;
      prev = g.hint();
    }
    CHECK(bad == 0);
  }
}

// Calls check(name, mesh) for each of the shared meshes `files` (none when
// ../shared is absent), the name captured for the checks' messages.
template <class Check>
void for_shared_meshes(std::initializer_list<const char*> files, Check&& check) {
  for (const char* f : files) {
    const std::string name = f;
    CAPTURE(name);
    const std::string path = test::shared_file(std::string("meshes/") + f);
    if (path.empty()) return;
    check(name, load_mesh(path));
  }
}

TEST_CASE("surface meshes with good vertex clearance certify most hinted projections locally") {
  for_shared_meshes({"falcon.mesh", "bunny.off", "torus.STL", "spot.obj"}, [](const std::string& name,
                                                                             const SurfaceMesh& m) {
    Locator loc(m);
    const test::PointSampler sample(m);
    std::mt19937_64 rng(12);
    int certified = 0;
    const int n = 5000;
    for (int i = 0; i < n; ++i) {
      const auto np = sample(rng, 0, 0);
      certified += !loc.project(np.x, Hint{Triangle(np.source)}).used_fallback;
    }
    MESSAGE(name << ": " << certified << "/" << n << " certified locally");
    CHECK(certified > 0.85 * n);
  });
}

TEST_CASE("CAD parts of slivers certify most hinted projections locally by the triangles' clearance") {
  // Vertex clearances certify little where triangles are long and thin (a
  // point in the middle of a sliver is far from its vertices); the distance
  // from the closest triangle to every triangle sharing no vertex with it
  // does, for points near the surface.
  for_shared_meshes({"fixed_top.ply", "featuretype.STL"}, [](const std::string& name, const SurfaceMesh& m) {
    Locator loc(m);
    const test::PointSampler sample(m);
    const std::vector<int>& tris = sample.triangles();
    std::mt19937_64 rng(13);
    int certified = 0, bad = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      const auto np = sample(rng, 1e-5, 1e-3);
      const Location g = loc.project(np.x, Hint{Triangle(np.source)});
      certified += !g.used_fallback;
      if (!test::same_distance(g.distance, std::sqrt(test::brute_force_d2(m, tris, np.x)), m.bbox().diagonal())) ++bad;
    }
    MESSAGE(name << ": " << certified << "/" << n << " certified locally, " << bad << " unlike brute force");
    CHECK(bad == 0);
    CHECK(certified > 0.6 * n);
  });
}

TEST_CASE("thin slab: a hint on the wrong sheet still lands on the closest sheet") {
  const double thickness = 1e-3;
  const SurfaceMesh m = test::box_surface({1, 1, thickness}, 20, 20, 1);
  REQUIRE(m.validate().ok());
  Locator loc(m);
  const test::PointSampler sample(m);
  const std::vector<int>& tris = sample.triangles();
  // Sheet of each triangle: -1 bottom (z = 0), +1 top (z = thickness), 0 sides.
  auto sheet = [&](int t) {
    const auto p = test::triangle_points(m, t);
    if (p[0].z == 0 && p[1].z == 0 && p[2].z == 0) return -1;
    if (p[0].z == thickness && p[1].z == thickness && p[2].z == thickness) return 1;
    return 0;
  };
  std::vector<int> bottom, top;
  for (int t : tris) (sheet(t) < 0 ? bottom : top).push_back(t);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  int bad = 0, wrong_sheet = 0, fallbacks = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const Vec3 x(u(rng), u(rng), thickness * (0.55 + 0.4 * u(rng)));  // nearer the top, maybe inside
    // The bottom triangle right below: the local minimum of the wrong sheet.
    double best = INFINITY;
    int below = -1;
    for (int t : bottom) {
      const auto p = test::triangle_points(m, t);
      const double d = point_triangle_distance2(Vec3(x.x, x.y, 0), p[0], p[1], p[2]);
      if (d < best) best = d, below = t;
    }
    const Location r = loc.project(x, Hint{Triangle(below)});
    const double ref = test::brute_force_d2(m, tris, x);
    if (!test::same_distance(r.distance, std::sqrt(ref), 1.0)) ++bad;
    if (r.point.z != thickness) ++wrong_sheet;
    fallbacks += r.used_fallback;
  }
  CHECK(bad == 0);
  CHECK(wrong_sheet == 0);
  CHECK(fallbacks == n);  // the bottom sheet's clearance (the thickness) cannot certify it
}

TEST_CASE("falcon thin parts: hints on the opposite sheet") {
  ANISURF_REQUIRE_SHARED(path, "meshes/falcon.mesh");
  const SurfaceMesh m = load_mesh(path);
  Locator loc(m);
  const test::PointSampler sample(m);
  const std::vector<int>& tris = sample.triangles();
  // Thin places: a vertex whose nearest non-incident triangle is much closer
  // than its own edges (trailing edges, wing tips). The opposite sheet is that
  // nearest triangle.
  std::vector<std::array<int, 2>> pairs;  // (triangle at v, triangle across)
  for (int v = 0; v < m.vertex_capacity() && pairs.size() < 400; v += 7) {
    const Vertex vh(v);
    double h = 0;
    for (Corner c : m.fan(vh)) h = std::max(h, norm(m.position(m.vertex(SurfaceMesh::next(c))) - m.position(vh)));
    if (!(loc.clearance(vh) < 0.25 * h)) continue;
    const Vec3 x = m.position(vh);
    double best = INFINITY;
    int across = -1;
    for (int t : tris) {
      const auto p = test::triangle_points(m, t);
      bool incident = false;
      for (int k = 0; k < 3; ++k) incident |= m.vertex(Triangle(t), k) == vh;
      const double d = point_triangle_distance2(x, p[0], p[1], p[2]);
      if (!incident && d < best) best = d, across = t;
    }
    pairs.push_back({SurfaceMesh::triangle(m.corner(vh)).idx, across});
  }
  REQUIRE(pairs.size() > 50);
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(0, 1);
  int bad = 0, moved_sheet = 0;
  for (const auto& pr : pairs) {
    // A point just off the triangle at v, searched from the triangle across.
    const auto p = test::triangle_points(m, pr[0]);
    const Vec3 n = normalized(cross(p[1] - p[0], p[2] - p[0]));
    const double h = norm(p[1] - p[0]);
    const double a = u(rng), b = u(rng) * (1 - a);
    const Vec3 x = (1 - a - b) * p[0] + a * p[1] + b * p[2] + n * (h * 0.05 * (u(rng) - 0.5));
    const Location r = loc.project(x, Hint{Triangle(pr[1])});
    if (!test::same_distance(r.distance, std::sqrt(test::brute_force_d2(m, tris, x)), m.bbox().diagonal())) ++bad;
    moved_sheet += r.used_fallback;
  }
  CHECK(bad == 0);
  MESSAGE("falcon thin parts: " << pairs.size() << " queries from the opposite sheet, " << moved_sheet
                                << " needed the tree");
}

TEST_CASE("several components (Suzanne): a hint on the head, a point near an eye") {
  ANISURF_REQUIRE_SHARED(path, "meshes/Suzanne.gltf");
  const SurfaceMesh m = load_mesh(path);
  int nc = 0;
  const std::vector<int> comp = test::triangle_components(m, &nc);
  REQUIRE(nc == 3);
  Locator loc(m);
  const test::PointSampler sample(m);
  const std::vector<int>& tris = sample.triangles();
  std::vector<std::vector<int>> by_comp(3);
  for (int t : tris) by_comp[comp[t]].push_back(t);
  std::mt19937_64 rng(15);
  int bad = 0, switched = 0, n = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto np = sample(rng, 1e-4, 1e-2);
    // The hint in another component than the point's source triangle.
    const int other = (comp[np.source] + 1 + static_cast<int>(rng() % 2)) % 3;
    const int hint = by_comp[other][rng() % by_comp[other].size()];
    const Location r = loc.project(np.x, Hint{Triangle(hint)});
    const double ref = test::brute_force_d2(m, tris, np.x);
    if (!test::same_distance(r.distance, std::sqrt(ref), m.bbox().diagonal())) ++bad;
    switched += comp[r.triangle.idx] != other;
    ++n;
  }
  CHECK(bad == 0);
  CHECK(switched > n / 2);  // most points are closest to their own component
}

TEST_CASE("initialization by topological propagation (4.3): T_1 a jittered copy of T_G") {
  for (const char* f : {"bunny.off", "Suzanne.gltf", "beetle.off"}) {
    const std::string name = f;
    CAPTURE(name);
    const std::string path = test::shared_file(std::string("meshes/") + f);
    if (path.empty()) return;
    const SurfaceMesh g = load_mesh(path);
    Locator loc(g);
    SurfaceMesh t1 = g;
    std::mt19937_64 rng(16);
    std::normal_distribution<double> gauss;
    for (int v = 0; v < t1.vertex_capacity(); ++v) {
      const Vertex vh(v);
      double h = INFINITY;
      for (Corner c : t1.fan(vh)) h = std::min(h, norm(t1.position(t1.vertex(SurfaceMesh::next(c))) - t1.position(vh)));
      t1.position(vh) += Vec3(gauss(rng), gauss(rng), gauss(rng)) * (0.1 * h);
    }
    int nc = 0;
    test::triangle_components(t1, &nc);
    std::vector<Hint> hints;
    PropagationStats st;
    const std::vector<Location> r = project_vertices(t1, loc, hints, false, &st);
    CHECK(st.projected == t1.n_vertices());
    CHECK(st.seeds == nc);
    CHECK(hints.size() == r.size());
    const std::vector<int> tris = test::live_triangles(g);
    int bad = 0;
    // Brute force on about 600 of the vertices.
    for (int v = 0; v < t1.vertex_capacity(); v += std::max(1, t1.vertex_capacity() / 600)) {
      const Vec3& x = t1.position(Vertex(v));
      if (!test::same_distance(r[v].distance, std::sqrt(test::brute_force_d2(g, tris, x)), g.bbox().diagonal())) ++bad;
      CHECK(hints[v].triangle == r[v].triangle);
    }
    CHECK(bad == 0);
    CHECK(st.mean_steps() < 3.0);
    // Again from the stored hints: each vertex starts next to its answer.
    PropagationStats again;
    project_vertices(t1, loc, hints, false, &again);
    CHECK(again.mean_steps() <= st.mean_steps());
    MESSAGE(name << ": propagation mean steps " << st.mean_steps() << ", with stored hints " << again.mean_steps()
              << ", tree needed for " << st.fallbacks << "/" << st.projected);
  }
}

TEST_CASE("torus inside: hints on the opposite wall of the tube and across the hole") {
  ANISURF_REQUIRE_SHARED(path, "meshes/torus.STL");
  const SurfaceMesh m = load_mesh(path);  // axis z, radii 1 and 0.5
  Locator loc(m);
  const test::PointSampler sample(m);
  const std::vector<int>& tris = sample.triangles();
  auto torus_point = [](double phi, double theta, double s) {
    const double rho = 1 + s * std::cos(theta);
    return Vec3(rho * std::cos(phi), rho * std::sin(phi), s * std::sin(theta));
  };
  auto nearest_triangle = [&](const Vec3& p) {
    double best = INFINITY;
    int t = -1;
    for (int u : tris) {
      const auto q = test::triangle_points(m, u);
      const double d = point_triangle_distance2(p, q[0], q[1], q[2]);
      if (d < best) best = d, t = u;
    }
    return t;
  };
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ua(0, 2 * M_PI), us(0.3, 0.47);
  int bad = 0, far_side = 0, fallbacks = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const double phi = ua(rng), theta = ua(rng), s = us(rng);
    // Inside the tube near the wall at theta, from the wall across the tube.
    const Vec3 x = torus_point(phi, theta, s);
    const Location r = loc.project(x, Hint{Triangle(nearest_triangle(torus_point(phi, theta + M_PI, 0.5)))});
    bad += !test::same_distance(r.distance, std::sqrt(test::brute_force_d2(m, tris, x)), sample.diagonal());
    far_side += norm(r.point - x) > 0.25;
    fallbacks += r.used_fallback;
    // In the hole near the inner equator, from the inner equator across the hole.
    const Vec3 y(0.45 * std::cos(phi), 0.45 * std::sin(phi), 0.1 * std::sin(theta));
    const Location h = loc.project(y, Hint{Triangle(nearest_triangle(torus_point(phi + M_PI, M_PI, 0.5)))});
    bad += !test::same_distance(h.distance, std::sqrt(test::brute_force_d2(m, tris, y)), sample.diagonal());
    far_side += dot(h.point, y) < 0;
  }
  CHECK(bad == 0);
  CHECK(far_side == 0);
  // The far wall is where the distance is largest around the tube, so the
  // descent itself crosses over; the points, deep inside relative to the
  // edge length, are then confirmed by the tree.
  MESSAGE("torus inside: " << fallbacks << "/" << n << " tube points confirmed by the tree");
}

TEST_CASE("deleted triangle slots are never returned, stale hints are ignored") {
  ANISURF_REQUIRE_SHARED(path, "meshes/bunny.off");
  SurfaceMesh m = load_mesh(path);
  std::vector<int> deleted;
  for (int t = 0; t < m.triangle_capacity(); t += 97) {
    m.delete_triangle(Triangle(t));
    deleted.push_back(t);
  }
  REQUIRE(m.has_garbage());
  Locator loc(m);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(18);
  int bad = 0;
  for (int i = 0; i < 500; ++i) {
    const auto np = sample(rng, 1e-4, 1e-2);
    const std::array<Hint, 3> hints{Hint{Triangle(deleted[i % deleted.size()])}, Hint{Triangle(-5)},
                                    Hint{Triangle(m.triangle_capacity() + 3)}};
    for (const Location& r : {loc.project(np.x, hints), loc.project(np.x, Hint{Triangle(np.source)})}) {
      bad += !test::consistent(m, r, np.x);  // fails on a deleted triangle
      bad += !test::same_distance(r.distance, std::sqrt(test::brute_force_d2(m, sample.triangles(), np.x)),
                                  sample.diagonal());
    }
  }
  CHECK(bad == 0);
}

TEST_CASE("hints a dozen rings from the point: the walk across edges and fans lands on the closest triangle") {
  // The walk crosses K's edge that holds the closest point while the
  // triangle beyond is closer, then searches the vertices' fans: from a hint
  // 12 rings away on a smooth scan it must still reach the brute-force
  // answer, nearly always certified without the tree.
  ANISURF_REQUIRE_SHARED(path, "meshes/bunny.off");
  const SurfaceMesh m = load_mesh(path);
  Locator loc(m);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(29);
  Tally tally;
  for (int i = 0; i < 400; ++i) {
    const auto np = sample(rng, 1e-4, 5e-3);
    int hint = np.source;
    for (int k = 0; k < 6; ++k) hint = nearby_triangle(m, hint, rng);
    const Location r = loc.project(np.x, Hint{Triangle(hint)});
    tally.add(m, r, np.x, test::brute_force_d2(m, sample.triangles(), np.x), sample.diagonal());
  }
  INFO("queries " << tally.queries << ", certified " << tally.certified << ", steps " << tally.steps);
  CHECK(tally.bad == 0);
  CHECK(tally.inconsistent == 0);
  CHECK(tally.certified >= 0.9 * tally.queries);
  CHECK(tally.steps >= tally.queries);  // the hints were far: the walk moved
}

namespace {

// The clearance of every `stride`-th vertex against a brute-force search:
// the distance to the nearest triangle not incident to it, less the rounding
// margin at most.
void check_clearances(const SurfaceMesh& m, const char* what, int stride = 1) {
  const Locator loc(m);
  const std::vector<int> tris = test::live_triangles(m);
  const double diag = m.bbox().diagonal();
  int checked = 0, wrong = 0;
  for (Vertex v : m.vertices()) {
    if (m.is_isolated(v) || v.idx % stride != 0) continue;
    const Vec3 x = m.position(v);
    double best = INFINITY;
    for (int t : tris) {
      bool incident = false;
      for (int k = 0; k < 3; ++k) incident |= m.vertex(Triangle(t), k) == v;
      if (incident) continue;
      const auto p = test::triangle_points(m, t);
      best = std::min(best, point_triangle_distance2(x, p[0], p[1], p[2]));
    }
    const double exact = std::sqrt(best), found = loc.clearance(v);
    ++checked;
    if (std::isinf(exact) ? !std::isinf(found) : !(found <= exact && found >= exact * (1 - 1e-8) - 1e-12 * diag))
      ++wrong;
  }
  INFO(std::string(what) << ": " << wrong << " of " << checked << " vertices with a clearance off the brute force");
  CHECK(checked > 0);
  CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("locator: every vertex's clearance is the distance to its nearest triangle not incident to it") {
  // A thin plate (the other sheet nearer than the vertex's own ring), a plate
  // of long slivers (rings far larger than the tree's leaves), an open grid
  // (boundary vertices with no triangle across their links), a lone
  // triangle (no triangle to measure: an infinite clearance), and a shared
  // mesh with thin parts.
  check_clearances(test::box_surface({1, 1, 0.01}, 12, 12, 1), "thin plate");
  check_clearances(test::box_surface({4, 0.05, 0.3}, 40, 1, 2), "slivers");
  {
    MeshData d;
    const int n = 9;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) d.vertices.push_back({i * 0.1, j * 0.1, 0.02 * std::sin(i + 2.0 * j)});
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, e = a + n + 1;
        d.triangles.push_back({a, b, c});
        d.triangles.push_back({a, c, e});
      }
    SurfaceMesh m;
    build_mesh(d, m);
    check_clearances(m, "open grid");
  }
  {
    MeshData d;
    d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    d.triangles = {{0, 1, 2}};
    SurfaceMesh m;
    build_mesh(d, m);
    check_clearances(m, "lone triangle");
  }
  if (const std::string path = test::shared_file("meshes/falcon.mesh"); std::filesystem::exists(path))
    check_clearances(load_mesh(path), "falcon", 29);
  else
    MESSAGE("skipped falcon: ../shared is absent");
}

namespace {

// within(x, tol) against the brute-force distance d of x to the mesh, for
// tolerances below, at and above d, from hints near and far: the answer is
// d <= tol (up to the rounding of d itself at tol = d), and a point the
// descent passes clearly within tol needs no certification.
void check_within(const SurfaceMesh& m, const char* what, std::uint64_t seed) {
  CAPTURE(what);
  Locator loc(m);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(seed);
  int wrong = 0, checked = 0;
  for (int i = 0; i < 300; ++i) {
    const auto np = sample(rng, 1e-4, 2e-2);
    const double d = std::sqrt(test::brute_force_d2(m, sample.triangles(), np.x));
    int hint = np.source;
    for (int k = 0; k < static_cast<int>(rng() % 8); ++k) hint = nearby_triangle(m, hint, rng);
    for (double f : {0.0, 0.25, 0.5, 0.9, 0.999, 1.001, 1.1, 2.0, 10.0}) {
      const double tol = f * d;
      ++checked;
      if (loc.within(np.x, tol, std::span<const Hint>()) != (d <= tol)) ++wrong;
      const Hint h{Triangle(hint)};
      if (loc.within(np.x, tol, std::span<const Hint>(&h, 1)) != (d <= tol)) ++wrong;
    }
    // At tol = d the answer is the projection's own comparison.
    const Hint h{Triangle(hint)};
    const Location r = loc.project(np.x, h);
    CHECK(loc.within(np.x, r.distance, std::span<const Hint>(&h, 1)) == (norm(r.point - np.x) <= r.distance));
  }
  INFO(checked << " queries");
  CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("locator: within(x, tol) tells whether the mesh comes within tol of x, from any hint") {
  check_within(test::box_surface({1, 1, 0.01}, 12, 12, 1), "thin plate", 41);
  check_within(test::box_surface({4, 0.05, 0.3}, 40, 1, 2), "slivers", 43);
  if (const std::string path = test::shared_file("meshes/bunny.off"); std::filesystem::exists(path))
    check_within(load_mesh(path), "bunny", 47);
  else
    MESSAGE("skipped bunny: ../shared is absent");
}
