// Point location kernels: closest points on triangles and segments, distances
// between segments and triangles, and the bounding-box tree against a
// brute-force search on every shared mesh.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "locate/aabb_tree.h"
#include "locate/closest_point.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

Vec3 random_vec(std::mt19937_64& rng, double s = 1) {
  std::uniform_real_distribution<double> u(-s, s);
  return {u(rng), u(rng), u(rng)};
}

// The projection q of p onto a convex set is characterised by
// (p - q).(r - q) <= 0 for every r of the set; for a triangle it suffices to
// check its vertices.
void check_projection(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const TriangleClosest& r) {
  const double scale = std::max({norm(a - p), norm(b - p), norm(c - p), 1.0});
  CHECK(r.bary[0] >= 0);
  CHECK(r.bary[1] >= 0);
  CHECK(r.bary[2] >= 0);
  CHECK(r.bary[0] + r.bary[1] + r.bary[2] == doctest::Approx(1).epsilon(1e-14));
  CHECK(norm(r.bary[0] * a + r.bary[1] * b + r.bary[2] * c - r.point) <= 1e-13 * scale);
  CHECK(r.distance2 == doctest::Approx(norm2(p - r.point)).epsilon(1e-14));
  for (const Vec3* v : {&a, &b, &c}) CHECK(dot(p - r.point, *v - r.point) <= 1e-12 * scale * scale);
}

// Minimum over a grid of (n+1)(n+2)/2 points of triangle s of the distance to
// triangle t: an upper bound of the triangle-triangle distance.
double sampled_triangle_distance(const std::array<Vec3, 3>& s, const std::array<Vec3, 3>& t, int n) {
  double best = INFINITY;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q = s[0] + (double(i) / n) * (s[1] - s[0]) + (double(j) / n) * (s[2] - s[0]);
      best = std::min(best, point_triangle_distance2(q, t[0], t[1], t[2]));
    }
  return std::sqrt(best);
}

}  // namespace

TEST_CASE("closest point on a triangle: the projection inequality in every region") {
  std::mt19937_64 rng(1);
  int regions[7] = {};
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = random_vec(rng), b = random_vec(rng), c = random_vec(rng), p = random_vec(rng, 2);
    const TriangleClosest r = closest_point_on_triangle(p, a, b, c);
    ++regions[static_cast<int>(r.region)];
    check_projection(p, a, b, c, r);
  }
  for (int k = 0; k < 7; ++k) CHECK(regions[k] > 100);

  // Exact answers in a right triangle.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto r = closest_point_on_triangle({0.25, 0.25, 3}, a, b, c);
  CHECK(r.region == TriangleRegion::Face);
  CHECK(r.distance2 == 9);
  CHECK(r.point == Vec3(0.25, 0.25, 0));
  r = closest_point_on_triangle({-1, -1, 0}, a, b, c);
  CHECK(r.region == TriangleRegion::Vertex0);
  CHECK(r.point == a);
  r = closest_point_on_triangle({2, 0.5, 0}, a, b, c);
  CHECK(r.region == TriangleRegion::Vertex1);
  r = closest_point_on_triangle({1, 1, 0}, a, b, c);
  CHECK(r.region == TriangleRegion::Edge12);
  CHECK(r.point.x == doctest::Approx(0.5));
  CHECK(r.bary[1] == doctest::Approx(0.5));
  r = closest_point_on_triangle({0.5, -2, 1}, a, b, c);
  CHECK(r.region == TriangleRegion::Edge01);
  CHECK(r.distance2 == doctest::Approx(5));
}

TEST_CASE("closest point on degenerate triangles: no division by zero") {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 5000; ++i) {
    const Vec3 a = random_vec(rng), b = random_vec(rng), p = random_vec(rng, 2);
    const double t = std::uniform_real_distribution<double>(-0.5, 1.5)(rng);
    // collinear, repeated vertex, all three equal
    for (const auto& tri : {std::array<Vec3, 3>{a, b, a + t * (b - a)}, std::array<Vec3, 3>{a, a, b},
                            std::array<Vec3, 3>{a, b, b}, std::array<Vec3, 3>{a, a, a}}) {
      const TriangleClosest r = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
      REQUIRE(std::isfinite(r.distance2));
      check_projection(p, tri[0], tri[1], tri[2], r);
      // The closest point of a flat triangle is that of its longest edge.
      double best = INFINITY;
      for (int k = 0; k < 3; ++k) best = std::min(best, point_segment_distance2(p, tri[k], tri[(k + 1) % 3]));
      CHECK(r.distance2 == doctest::Approx(best).epsilon(1e-9));
    }
  }
}

TEST_CASE("segment and triangle distances against sampling") {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 300; ++i) {
    std::array<Vec3, 3> s{random_vec(rng), random_vec(rng), random_vec(rng)};
    std::array<Vec3, 3> t{random_vec(rng), random_vec(rng), random_vec(rng)};
    const Vec3 shift = random_vec(rng, 1.5);
    for (auto& v : t) v += shift;
    const double d = std::sqrt(triangle_triangle_distance2(s, t));
    const double sampled = std::min(sampled_triangle_distance(s, t, 60), sampled_triangle_distance(t, s, 60));
    // The sampling is an upper bound, within the grid spacing of the truth.
    CHECK(d <= sampled + 1e-12);
    CHECK(sampled - d <= 0.05 * 4);
    CHECK(triangle_triangle_distance2(t, s) == doctest::Approx(d * d).epsilon(1e-9));
  }
  // Two triangles crossing through their interiors (no edge touches an edge).
  const std::array<Vec3, 3> s{Vec3(-1, -1, 0), Vec3(2, -1, 0), Vec3(-1, 2, 0)};
  const std::array<Vec3, 3> t{Vec3(0.2, 0.2, -1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)};
  CHECK(triangle_triangle_distance2(s, t) == 0);
  // Parallel triangles one above the other: the distance is the gap.
  std::array<Vec3, 3> u = s;
  for (auto& v : u) v.z += 0.125;
  CHECK(triangle_triangle_distance2(s, u) == doctest::Approx(0.125 * 0.125));
  // Parallel and collinear segments, zero-length segments.
  CHECK(segment_segment_distance2({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}) == doctest::Approx(1));
  CHECK(segment_segment_distance2({0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {3, 1, 0}) == doctest::Approx(1));
  CHECK(segment_segment_distance2({0, 0, 0}, {0, 0, 0}, {1, 1, 0}, {1, 1, 0}) == doctest::Approx(2));
  CHECK(segment_segment_distance2({0, 0, 0}, {1, 0, 0}, {0.5, -1, 1}, {0.5, 1, 1}) == doctest::Approx(1));
  CHECK(segment_triangle_distance2({0.2, 0.2, 1}, {0.2, 0.2, -1}, s[0], s[1], s[2]) == 0);
}

namespace {

// n boxes with a corner in [-10, 10]^3 (random_vec) and sides up to `side`.
std::vector<BBox> random_boxes(std::mt19937_64& rng, int n, double side) {
  std::uniform_real_distribution<double> u(0, side);
  std::vector<BBox> boxes(static_cast<std::size_t>(n));
  for (auto& b : boxes) {
    const Vec3 c = random_vec(rng, 10);
    b.add(c);
    b.add(c + Vec3(u(rng), u(rng), u(rng)));
  }
  return boxes;
}

}  // namespace

TEST_CASE("AABB tree: nearest and range queries against brute force on random boxes") {
  std::mt19937_64 rng(4);
  std::vector<BBox> boxes = random_boxes(rng, 3000, 1.0);
  boxes[17] = BBox();  // a deleted slot
  AabbTree tree(boxes);
  CHECK(tree.n_primitives() == 2999);
  CHECK(tree.depth() < 40);
  // Every node box holds its children / primitives.
  for (const auto& n : tree.nodes()) {
    if (n.is_leaf()) {
      CHECK(n.count <= AabbTree::kMaxLeafSize);
      for (const int* p = tree.leaf_begin(n); p != tree.leaf_end(n); ++p)
        for (int k = 0; k < 3; ++k) {  // the leaf box holds the primitive's box
          CHECK(n.lower()[k] <= boxes[*p].lo[k]);
          CHECK(n.upper()[k] >= boxes[*p].hi[k]);
        }
    }
  }
  for (int q = 0; q < 500; ++q) {
    const Vec3 x = random_vec(rng, 14);
    double best = INFINITY;
    const int id = tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                                [&](int i, double) { return box_point_distance2(boxes[i].lo, boxes[i].hi, x); }, best);
    double ref = INFINITY;
    for (std::size_t i = 0; i < boxes.size(); ++i)
      if (!boxes[i].empty()) ref = std::min(ref, box_point_distance2(boxes[i].lo, boxes[i].hi, x));
    CHECK(id >= 0);
    CHECK(id != 17);
    CHECK(best == ref);
    // A bound below the answer finds nothing.
    double bound = ref;
    CHECK(tree.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                       [&](int i, double) { return box_point_distance2(boxes[i].lo, boxes[i].hi, x); }, bound) == -1);
    // Range query: every box within r.
    const double r2 = 4.0;
    std::vector<int> got;
    tree.for_each_within([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); }, r2,
                         [&](int i) {
                           if (box_point_distance2(boxes[i].lo, boxes[i].hi, x) <= r2) got.push_back(i);
                         });
    std::vector<int> want;
    for (std::size_t i = 0; i < boxes.size(); ++i)
      if (!boxes[i].empty() && box_point_distance2(boxes[i].lo, boxes[i].hi, x) <= r2) want.push_back(int(i));
    std::sort(got.begin(), got.end());
    CHECK(got == want);
  }
}

TEST_CASE("AABB tree: the root's two subtrees built on two threads make the tree one thread makes") {
  // 100000 boxes: the subtrees are built apart and appended. Node for node
  // the same arrays on 1 and 2 threads; every inner node's box holds its
  // children's, every primitive sits in one leaf, and nearest queries agree
  // with brute force.
  std::mt19937_64 rng(8);
  const std::vector<BBox> boxes = random_boxes(rng, 100000, 0.05);
  const test::ThreadLimitScope scope(thread_limit().load());
  thread_limit() = 1;
  const AabbTree one(boxes);
  thread_limit() = 2;
  const AabbTree two(boxes);
  REQUIRE(one.nodes().size() == two.nodes().size());
  int differ = 0;
  for (std::size_t i = 0; i < one.nodes().size(); ++i) {
    const AabbTree::Node &a = one.nodes()[i], &b = two.nodes()[i];
    differ += a.first != b.first || a.count != b.count || a.lower() != b.lower() || a.upper() != b.upper();
    if (a.is_leaf()) differ += !std::equal(one.leaf_begin(a), one.leaf_end(a), two.leaf_begin(b));
  }
  CHECK(differ == 0);
  std::vector<int> seen(boxes.size(), 0);
  int outside = 0;
  for (const auto& n : two.nodes()) {
    if (n.is_leaf()) {
      for (const int* p = two.leaf_begin(n); p != two.leaf_end(n); ++p) ++seen[static_cast<std::size_t>(*p)];
      continue;
    }
    for (int c : {n.first, n.first + 1})
      for (int k = 0; k < 3; ++k)
        outside += two.nodes()[c].lower()[k] < n.lower()[k] || two.nodes()[c].upper()[k] > n.upper()[k];
  }
  CHECK(outside == 0);
  CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(boxes.size()));
  for (int q = 0; q < 100; ++q) {
    const Vec3 x = random_vec(rng, 12);
    double best = INFINITY;
    two.nearest([&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, x); },
                [&](int i, double) { return box_point_distance2(boxes[i].lo, boxes[i].hi, x); }, best);
    double ref = INFINITY;
    for (const BBox& b : boxes) ref = std::min(ref, box_point_distance2(b.lo, b.hi, x));
    CHECK(best == ref);
  }
}

TEST_CASE("AABB tree over the triangles of every shared mesh agrees with brute force") {
  const char* files[] = {"bunny.off",     "spot.obj",      "fandisk.off",     "featuretype.STL", "fixed_top.ply",
                         "falcon.mesh",   "torus.STL",     "mmg_torus.mesh",  "mmg_teapot.mesh", "mmg_cube.mesh",
                         "thinker.mesh",  "camelhead.off", "beetle.off",      "bun_zipper_res2.ply",
                         "Box.glb",       "Duck.glb",      "Suzanne.gltf",    "Avocado.gltf"};
  for (const char* f : files) {
    const std::string name = f;
    CAPTURE(name);
    const std::string path = test::shared_file(std::string("meshes/") + f);
    if (path.empty()) {
      MESSAGE("skipped: ../shared/meshes not found (no shared test data)");
      return;
    }
    const SurfaceMesh m = load_mesh(path);
    const test::PointSampler sample(m);
    const std::vector<int>& tris = sample.triangles();
    std::vector<BBox> boxes(static_cast<std::size_t>(m.triangle_capacity()));
    for (int t : tris)
      for (const Vec3& p : test::triangle_points(m, t)) boxes[t].add(p);
    const AabbTree tree(boxes);
    REQUIRE(tree.n_primitives() == static_cast<int>(tris.size()));
    const double diag = m.bbox().diagonal();
    std::mt19937_64 rng(5);
    // About 10^7 point-triangle tests of brute force per mesh.
    const int n = std::clamp(10000000 / static_cast<int>(tris.size()), 200, 2000);
    int bad = 0;
    for (int i = 0; i < n; ++i) {
      const auto np = i % 8 == 0 ? sample(rng, 0, 0)
                                 : sample(rng, 1e-3, 5e-2);
      double best = INFINITY;
      const int t = tree.nearest(
          [&](const Vec3& lo, const Vec3& hi) { return box_point_distance2(lo, hi, np.x); },
          [&](int k, double) {
            const auto p = test::triangle_points(m, k);
            return point_triangle_distance2(np.x, p[0], p[1], p[2]);
          },
          best);
      const double ref = test::brute_force_d2(m, tris, np.x);
      if (t < 0 || !test::same_distance(std::sqrt(best), std::sqrt(ref), diag)) ++bad;
    }
    CHECK(bad == 0);
  }
}
