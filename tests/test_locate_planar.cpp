// The 2D walk by oriented areas (report 4.1) with the fix for non-convex
// domains: an L-shape and an annulus built here, the shared square meshes;
// every answer against a brute-force search over all triangles.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "io/mesh_io.h"
#include "locate/planar_locator.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// Structured triangulation of the unit cells (i, j) of an n x n grid of step
// h kept by `keep`, diagonals alternating so the mesh is not too regular.
template <class Keep>
SurfaceMesh grid_domain(int n, double h, Keep keep) {
  MeshData d;
  d.dimension = 2;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) d.vertices.push_back({i * h, j * h, 0});
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (!keep(i, j)) continue;
      if ((i + j) % 2) {
        d.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        d.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        d.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        d.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  SurfaceMesh m;
  build_mesh(d, m);
  return m;
}

// Annulus r0 <= r <= r1: nr rings of nt quads, each split in two, with the
// radii perturbed so that cells differ.
SurfaceMesh annulus(double r0, double r1, int nr, int nt) {
  MeshData d;
  d.dimension = 2;
  for (int j = 0; j <= nr; ++j)
    for (int i = 0; i < nt; ++i) {
      const double a = 2 * M_PI * (i + 0.3 * (j % 2)) / nt;
      const double r = r0 + (r1 - r0) * j / nr;
      d.vertices.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
  auto id = [&](int i, int j) { return j * nt + (i % nt); };
  for (int j = 0; j < nr; ++j)
    for (int i = 0; i < nt; ++i) {
      d.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      d.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  SurfaceMesh m;
  build_mesh(d, m);
  return m;
}

struct PlanarTally {
  int queries = 0, bad = 0, inconsistent = 0, inside = 0, inside_by_walk = 0, outside = 0;
  long long steps = 0;
};

// Queries uniform in `box` (grown by 20%), from random hints; every answer
// against brute force. With verify_exterior off, the walk and its fix answer
// alone.
PlanarTally run_queries(const SurfaceMesh& m, bool verify, int n, std::uint64_t seed) {
  PlanarLocateOptions o;
  o.verify_exterior = verify;
  PlanarLocator loc(m, o);
  const std::vector<int> tris = test::live_triangles(m);
  const BBox box = m.bbox();
  const Vec3 grow = (box.hi - box.lo) * 0.2;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(box.lo.x - grow.x, box.hi.x + grow.x), uy(box.lo.y - grow.y, box.hi.y + grow.y);
  PlanarTally t;
  Hint prev;
  for (int i = 0; i < n; ++i) {
    const Vec3 x(ux(rng), uy(rng), 0);
    const Hint hint = i % 2 ? prev : Hint{Triangle(tris[rng() % tris.size()])};
    const Location r = loc.locate(x, hint);
    const double ref = std::sqrt(test::brute_force_d2(m, tris, x));
    ++t.queries;
    if (!test::same_distance(r.distance, ref, box.diagonal())) ++t.bad;
    if (!test::consistent(m, r, x)) ++t.inconsistent;
    if (ref <= 1e-13 * box.diagonal()) {  // inside (up to the rounding of the brute force)
      ++t.inside;
      t.inside_by_walk += !r.used_fallback && r.distance == 0;
    } else {
      ++t.outside;
    }
    t.steps += r.steps;
    prev = r.hint();
  }
  return t;
}

}  // namespace

TEST_CASE("planar walk: L-shaped domain (non-convex), with and without the tree's confirmation") {
  const SurfaceMesh m = grid_domain(20, 0.1, [](int i, int j) { return i < 10 || j < 10; });
  REQUIRE(m.validate().ok());
  for (bool verify : {false, true}) {
    CAPTURE(verify);
    const PlanarTally t = run_queries(m, verify, 4000, 21);
    CHECK(t.bad == 0);
    CHECK(t.inconsistent == 0);
    CHECK(t.inside > 1000);
    CHECK(t.outside > 1000);
    CHECK(t.inside_by_walk == t.inside);  // found by the walk, not by the tree
  }
}

TEST_CASE("planar walk: annulus (a hole between hint and point)") {
  const SurfaceMesh m = annulus(0.5, 1.0, 6, 48);
  REQUIRE(m.validate().ok());
  PlanarLocateOptions o;
  o.verify_exterior = false;
  PlanarLocator loc(m, o);
  CHECK(loc.n_boundary_edges() == 96);
  // Points in the ring with hints diametrically opposite: the straight walk
  // runs into the hole and the fix must carry it across.
  const std::vector<int> tris = test::live_triangles(m);
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> ua(0, 2 * M_PI), ur(0.55, 0.95);
  int found = 0, n = 500;
  for (int i = 0; i < n; ++i) {
    const double a = ua(rng), r = ur(rng);
    const Vec3 x(r * std::cos(a), r * std::sin(a), 0);
    // The triangle holding the opposite point.
    const Vec3 y = -1.0 * x;
    int hint = -1;
    double best = INFINITY;
    for (int t : tris) {
      const auto p = test::triangle_points(m, t);
      const double d = point_triangle_distance2(y, p[0], p[1], p[2]);
      if (d < best) best = d, hint = t;
    }
    REQUIRE(hint >= 0);
    const Location l = loc.locate(x, Hint{Triangle(hint)});
    found += l.distance == 0 && !l.used_fallback && test::consistent(m, l, x);
  }
  CHECK(found == n);
  // Random points, inside, in the hole and outside.
  for (bool verify : {false, true}) {
    CAPTURE(verify);
    const PlanarTally t = run_queries(m, verify, 4000, 23);
    CHECK(t.bad == 0);
    CHECK(t.inconsistent == 0);
    CHECK(t.inside_by_walk == t.inside);
    CHECK(t.inside > 1000);
  }
}

TEST_CASE("planar walk: comb domain (many reflex corners)") {
  // Teeth of width 1 cell, gaps of 1 cell: walks from one tooth to another
  // stop on the boundary again and again.
  const SurfaceMesh m = grid_domain(24, 1.0 / 24, [](int i, int j) { return j < 4 || i % 2 == 0; });
  REQUIRE(m.validate().ok());
  const PlanarTally t = run_queries(m, false, 4000, 24);
  CHECK(t.bad == 0);
  CHECK(t.inconsistent == 0);
  CHECK(t.inside_by_walk == t.inside);
}

TEST_CASE("planar walk on the shared square meshes (2D and flat 3D)") {
  for (const char* f : {"bench/inputs/square2d.mesh", "bench/inputs/square3d.mesh"}) {
    const std::string name = f;
    CAPTURE(name);
    const std::string path = test::shared_file(f);
    if (path.empty()) return;
    const SurfaceMesh m = load_mesh(path);
    REQUIRE(PlanarLocator::is_planar(m));
    const PlanarTally t = run_queries(m, false, 3000, 25);
    CHECK(t.bad == 0);
    CHECK(t.inconsistent == 0);
    CHECK(t.inside_by_walk == t.inside);
    // Hinted by the previous answer, a query crosses about half the square.
    CHECK(static_cast<double>(t.steps) / t.queries < 20);
  }
}

TEST_CASE("planar locator: refuses a surface that is not flat, answers without a hint") {
  const SurfaceMesh box = test::box_surface({1, 1, 1}, 2, 2, 2);
  CHECK_FALSE(PlanarLocator::is_planar(box));
  CHECK_THROWS_AS(PlanarLocator{box}, Error);
  const SurfaceMesh m = grid_domain(4, 0.25, [](int, int) { return true; });
  PlanarLocator loc(m);
  const Location r = loc.locate({2, 0.5, 7});  // z ignored
  CHECK(r.used_fallback);
  CHECK(r.distance == doctest::Approx(1));
  CHECK(r.point.x == doctest::Approx(1));
  CHECK(r.point.y == doctest::Approx(0.5));
  const Location in = loc.locate({0.3, 0.6, 0}, r.hint());
  CHECK(in.distance == 0);
  CHECK_FALSE(in.used_fallback);
  CHECK(in.steps > 0);
}
