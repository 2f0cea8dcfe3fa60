// Closest point on a smooth surface parameterised over the mesh, given as a
// callback: an exact sphere over a UV-sphere mesh (the answer is known), a
// feature curve on it (the equator), and the G1 Bezier surface of the
// geometry module plugged in through the same callback.
#include <doctest/doctest.h>

#include <random>

#include "geometry/bezier_surface.h"
#include "geometry/normals.h"
#include "io/mesh_io.h"
#include "locate/surface_projection.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// Latitude-longitude sphere of radius 1 with an equator edge loop.
SurfaceMesh uv_sphere(int n_lat, int n_lon) {
  MeshData d;
  d.vertices.push_back({0, 0, 1});
  for (int i = 1; i < n_lat; ++i)
    for (int j = 0; j < n_lon; ++j) {
      const double th = M_PI * i / n_lat, ph = 2 * M_PI * (j + 0.37 * (i % 3)) / n_lon;
      d.vertices.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  d.vertices.push_back({0, 0, -1});
  const int south = static_cast<int>(d.vertices.size()) - 1;
  auto id = [&](int i, int j) { return 1 + (i - 1) * n_lon + (j % n_lon); };
  for (int j = 0; j < n_lon; ++j) {
    d.triangles.push_back({0, id(1, j), id(1, j + 1)});
    d.triangles.push_back({south, id(n_lat - 1, j + 1), id(n_lat - 1, j)});
  }
  for (int i = 1; i + 1 < n_lat; ++i)
    for (int j = 0; j < n_lon; ++j) {
      d.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      d.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  SurfaceMesh m;
  build_mesh(d, m);
  return m;
}

// The unit sphere over the mesh: S(t, b) = q / |q|, q the point of the flat triangle.
SurfaceEvaluator sphere_evaluator(const SurfaceMesh& m) {
  return [&m](Triangle t, const std::array<double, 3>& b) {
    const Vec3 p0 = m.position(m.vertex(t, 0)), p1 = m.position(m.vertex(t, 1)), p2 = m.position(m.vertex(t, 2));
    const Vec3 q = b[0] * p0 + b[1] * p1 + b[2] * p2;
    const double r = norm(q);
    const Vec3 s = q / r;
    auto d = [&](const Vec3& e) { return (e - dot(s, e) * s) / r; };
    return ParametricPoint{s, d(p1 - p0), d(p2 - p0)};
  };
}

}  // namespace

TEST_CASE("closest point on a parametric surface: the exact sphere over a UV-sphere mesh") {
  const SurfaceMesh m = uv_sphere(12, 24);
  REQUIRE(m.validate().ok());
  Locator loc(m);
  const SurfaceEvaluator eval = sphere_evaluator(m);
  std::mt19937_64 rng(41);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.7, 1.3);
  int not_converged = 0, off = 0, crossed = 0;
  double worst = 0;
  Hint prev;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x = normalized(Vec3(g(rng), g(rng), g(rng))) * u(rng);
    const SurfaceProjection r = project_onto_surface(loc, eval, x, std::span<const Hint>(&prev, 1));
    not_converged += !r.converged;
    const Vec3 exact = normalized(x);
    worst = std::max(worst, norm(r.point - exact));
    off += norm(r.point - exact) > 1e-10;
    CHECK(r.distance == doctest::Approx(std::fabs(norm(x) - 1)).epsilon(1e-9));
    crossed += r.location.triangle != r.polyhedral.triangle;
    prev = r.location.hint();
  }
  CHECK(not_converged == 0);
  CHECK(off == 0);
  CHECK(crossed > 100);  // the parameter walk left the polyhedral triangle
  MESSAGE("sphere: worst error " << worst << ", " << crossed << "/2000 ended in another triangle");
}

TEST_CASE("closest point on a parametric surface along a feature curve (the equator)") {
  SurfaceMesh m = uv_sphere(12, 24);
  // Tag the equator: edges between two vertices with z = 0.
  for (int c = 0; c < 3 * m.triangle_capacity(); ++c) {
    const Corner ch(c);
    if (std::fabs(m.position(m.edge_from(ch)).z) < 1e-12 && std::fabs(m.position(m.edge_to(ch)).z) < 1e-12)
      m.add_edge_tag(ch, kRidge);
  }
  Locator loc(m);
  REQUIRE(loc.n_feature_edges() == 24);
  const SurfaceEvaluator eval = sphere_evaluator(m);
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g;
  int bad = 0, not_converged = 0, hopped = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 x = Vec3(g(rng), g(rng), 0.6 * g(rng)) * 1.1;
    const SurfaceProjection r = project_onto_surface(loc, eval, x, {}, Constraint::OnFeature);
    const Vec3 exact = normalized(Vec3(x.x, x.y, 0));
    bad += norm(r.point - exact) > 1e-10;
    not_converged += !r.converged;
    CHECK(r.location.edge.is_valid());
    CHECK(m.has_tag(r.location.edge, kRidge));
    hopped += r.location.edge != r.polyhedral.edge;
  }
  CHECK(bad == 0);
  CHECK(not_converged == 0);
  CHECK(hopped > 0);
}

TEST_CASE("the G1 Bezier surface through the evaluator callback: optimality at the answer") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/sphere20k.mesh");
  const SurfaceMesh m = load_mesh(path);
  const BezierSurface surface(m, compute_frames(m));
  const SurfaceEvaluator eval = [&](Triangle t, const std::array<double, 3>& b) {
    const SurfacePoint s = surface.evaluate(t, b);
    return ParametricPoint{s.position, s.d1, s.d2};
  };
  Locator loc(m);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(43);
  int not_optimal = 0, worse = 0, not_converged = 0;
  for (int i = 0; i < 500; ++i) {
    const auto np = sample(rng, 1e-3, 3e-2);
    const SurfaceProjection r = project_onto_surface(loc, eval, np.x, std::array<Hint, 1>{Hint{Triangle(np.source)}});
    not_converged += !r.converged;
    // First-order optimality: x - S orthogonal to the surface's derivatives.
    const ParametricPoint p = eval(r.location.triangle, r.location.bary);
    const Vec3 res = np.x - p.position;
    const bool inside = r.location.bary[0] > 1e-9 && r.location.bary[1] > 1e-9 && r.location.bary[2] > 1e-9;
    if (inside && (std::fabs(dot(res, p.d1)) > 1e-8 * norm(res) * norm(p.d1) + 1e-14 ||
                   std::fabs(dot(res, p.d2)) > 1e-8 * norm(res) * norm(p.d2) + 1e-14))
      ++not_optimal;
    // No worse than the surface point at the polyhedral parameters (the
    // report's choice).
    const ParametricPoint start = eval(r.polyhedral.triangle, r.polyhedral.bary);
    worse += r.distance > norm(np.x - start.position) * (1 + 1e-12);
    // The surface of a unit-sphere mesh: the answer is close to the radial projection.
    CHECK(norm(r.point - normalized(np.x)) < 1e-3);
  }
  CHECK(not_converged == 0);
  CHECK(not_optimal == 0);
  CHECK(worse == 0);
}
