// Hessian recovery (exact for quadratics on irregular flat meshes, converging
// on a sphere), curvature, L^p / BAMG Hessian metrics and geometric metrics.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <random>

#include "geometry/features.h"
#include "mesh/build.h"
#include "mesh/mesh_data.h"
#include "metric/hessian.h"
#include "metric/surface_metric.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using anisurf::test::rebuilt;

namespace {

// Irregular triangulation of a tilted square in 3D: an n x n grid with the
// interior vertices moved randomly by up to 0.3 of the spacing and random
// diagonals. (u, w) span the plane.
SurfaceMesh irregular_plane(int n, const Vec3& origin, const Vec3& u, const Vec3& w, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::bernoulli_distribution coin(0.5);
  SurfaceMesh m;
  const double h = 1.0 / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double x = i * h, y = j * h;
      if (i > 0 && j > 0 && i < n - 1 && j < n - 1) {
        x += jitter(rng) * h;
        y += jitter(rng) * h;
      }
      m.add_vertex(origin + x * u + y * w);
    }
  auto id = [n](int i, int j) { return Vertex(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      if (coin(rng)) {
        m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        m.add_triangle(id(i, j), id(i + 1, j), id(i, j + 1));
        m.add_triangle(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  return m;
}

// Icosahedron refined `levels` times by edge midpoints, on the unit sphere.
SurfaceMesh icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& q : p) q = normalized(q);
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(normalized(p[a] + p[b]));
      return mid[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tr : f) {
      const int a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]), c = midpoint(tr[2], tr[0]);
      g.push_back({tr[0], a, c});
      g.push_back({tr[1], b, a});
      g.push_back({tr[2], c, b});
      g.push_back({a, b, c});
    }
    f.swap(g);
  }
  SurfaceMesh m;
  for (const Vec3& q : p) m.add_vertex(q);
  for (auto tr : f) {
    if (dot(cross(p[tr[1]] - p[tr[0]], p[tr[2]] - p[tr[0]]), p[tr[0]]) < 0) std::swap(tr[1], tr[2]);
    m.add_triangle(Vertex(tr[0]), Vertex(tr[1]), Vertex(tr[2]));
  }
  return m;
}

// Open cylinder of radius r around z, n vertices around, k rows 2 pi r / n
// apart from z = 0, outward triangles.
SurfaceMesh cylinder(double r, int n, int k) {
  SurfaceMesh m;
  const double dz = 2 * M_PI * r / n;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) {
      const double t = 2 * M_PI * (i + 0.5 * (j % 2)) / n;
      m.add_vertex(Vec3(r * std::cos(t), r * std::sin(t), j * dz));
    }
  auto id = [n](int i, int j) { return Vertex(j * n + (i % n)); };
  for (int j = 0; j + 1 < k; ++j)
    for (int i = 0; i < n; ++i) {
      m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}

// f(p) = p^T A p + b.p + 1 (A symmetric): gradient 2 A p + b, Hessian 2 A.
struct Quadratic {
  SymTensor3 A;
  Vec3 b;
  double operator()(const Vec3& p) const { return quad(A, p) + dot(b, p) + 1.0; }
  Vec3 gradient(const Vec3& p) const { return 2.0 * (A * p) + b; }
};

std::vector<double> sample(const SurfaceMesh& m, const Quadratic& f) {
  std::vector<double> v(m.vertex_capacity());
  for (int i = 0; i < m.vertex_capacity(); ++i) v[i] = f(m.position(Vertex(i)));
  return v;
}

double tensor_error(const SymTensor2& a, const SymTensor2& b) {
  return std::max({std::fabs(a.m[0] - b.m[0]), std::fabs(a.m[1] - b.m[1]), std::fabs(a.m[2] - b.m[2])});
}


}  // namespace

TEST_CASE("hessian: the quadratic and cubic fits are exact for quadratics on irregular flat meshes") {
  const Quadratic f{SymTensor3(3, -1.5, 0.5, 2, 0.7, -4), Vec3(0.3, -2, 1)};
  const Vec3 u = normalized(Vec3(1, 0.4, -0.3)), w = normalized(cross(Vec3(0.2, 0.1, 1), u));
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
    const SurfaceMesh m = irregular_plane(12, Vec3(0.5, -1, 2), u, w, seed);
    REQUIRE(m.validate().ok());
    HessianRecoveryOptions ro;
    ro.degree = seed % 2 ? 2 : 3;
    const RecoveredDerivatives d = recover_derivatives(m, sample(m, f), ro);
    const SymTensor2 exact = restrict_to_tangent(2.0 * f.A, u, w);
    double worst_h = 0, worst_g = 0, worst_normal = 0;
    for (int i = 0; i < m.vertex_capacity(); ++i) {
      const Vec3 p = m.position(Vertex(i));
      worst_h = std::max(worst_h, tensor_error(restrict_to_tangent(d.hessian[i], u, w), exact));
      const Vec3 g = f.gradient(p), n = cross(u, w);
      worst_g = std::max(worst_g, norm(d.gradient[i] - (g - dot(g, n) * n)));
      worst_normal = std::max(worst_normal, norm(d.hessian[i] * n));
    }
    CHECK(worst_h < 1e-9);  // every vertex, boundary and corners included
    CHECK(worst_g < 1e-9);
    CHECK(worst_normal < 1e-12);
  }
}

TEST_CASE("hessian: recovery converges with second order on a sphere (cubic fit), first order (quadratic fit)") {
  // On the unit sphere (outward normal n = p) the recovered Hessian is the
  // Hessian over the tangent-plane parametrisation: T^T (2A) T - (grad f . n) I.
  const Quadratic f{SymTensor3(1, 0, 0, 0, 1, 0), Vec3(0.5, 0, 0)};  // x^2 + 2yz + x/2
  for (int degree : {2, 3}) {
    std::vector<double> errs, hs;
    HessianRecoveryOptions ro;
    ro.degree = degree;
    for (int level = 2; level <= 5; ++level) {
      const SurfaceMesh m = icosphere(level);
      const RecoveredDerivatives d = recover_derivatives(m, sample(m, f), ro);
      double worst = 0, hmean = 0;
      for (int i = 0; i < m.vertex_capacity(); ++i) {
        const Vec3 p = m.position(Vertex(i));
        const auto fr = tangent_frame(p);
        SymTensor2 exact = restrict_to_tangent(2.0 * f.A, fr[0], fr[1]);
        const double gn = dot(f.gradient(p), p);
        exact.m[0] -= gn;
        exact.m[2] -= gn;
        worst = std::max(worst, tensor_error(restrict_to_tangent(d.hessian[i], fr[0], fr[1]), exact));
      }
      const auto edges = mesh_edges(m);
      for (const auto& e : edges) hmean += norm(m.position(Vertex(e[1])) - m.position(Vertex(e[0])));
      errs.push_back(worst);
      hs.push_back(hmean / static_cast<double>(edges.size()));
    }
    double order = 0;
    for (size_t k = 0; k + 1 < errs.size(); ++k) {
      order = std::log(errs[k] / errs[k + 1]) / std::log(hs[k] / hs[k + 1]);
      MESSAGE("degree " << degree << ", h " << hs[k + 1] << ": max error " << errs[k + 1] << ", observed order "
                        << order);
    }
    if (degree == 3) {
      CHECK(order > 1.8);
      CHECK(errs.back() < 5e-3);
    } else {
      CHECK(order > 0.7);
    }
  }
}

TEST_CASE("hessian: curvature of the sphere and the geometric metric for hausd") {
  auto curvature_error = [](const SurfaceMesh& m) {
    const auto II = recover_curvature(m);
    double worst = 0;
    for (int i = 0; i < m.vertex_capacity(); ++i) {
      const auto fr = tangent_frame(m.position(Vertex(i)));
      worst = std::max(worst, tensor_error(restrict_to_tangent(II[i], fr[0], fr[1]), SymTensor2(1, 0, 1)));
    }
    return worst;
  };
  const double e3 = curvature_error(icosphere(3)), e4 = curvature_error(icosphere(4));
  const SurfaceMesh m = rebuilt(icosphere(4));
  MESSAGE("curvature of the unit sphere: max error " << e3 << " (1280 triangles), " << e4 << " (5120)");
  CHECK(e4 < 0.01);
  CHECK(e3 / e4 > 3.5);  // second order
  // Sizes sqrt(8 hausd / kappa) in the tangent plane; the normal gets the same.
  // hausd 1e-2: the facets (edges 0.1) sag by 1.2e-3, below hausd / 4, so the
  // creases between them ask for less than the curvature.
  const double hausd = 1e-2;
  const MetricField M = curvature_metric(m, hausd);
  for (int i = 0; i < m.vertex_capacity(); i += 7) {
    const SizesDirections sd = sizes_and_directions(M[i]);
    for (double h : sd.sizes) CHECK(h == doctest::Approx(std::sqrt(8 * hausd)).epsilon(2e-3));
  }
  // hmax caps the sizes of a flat region: the irregular plane.
  MetricBounds b;
  b.hmax = 0.3;
  // Its boundary is a feature curve: tagged (corners where it turns) as adapt does.
  SurfaceMesh flat = rebuilt(irregular_plane(8, Vec3(), Vec3(1, 0, 0), Vec3(0, 1, 0), 5));
  detect_features(flat);
  const MetricField F = curvature_metric(flat, hausd, b);
  for (const SymTensor3& X : F) CHECK(frobenius_norm(X - isotropic_metric(0.3)) < 1e-9 * frobenius_norm(X));
}

TEST_CASE("hessian: the geometric metric of a cylinder: sqrt(8 hausd r) across, hmax along the axis") {
  // hausd 5e-2: the facets (edges 0.13) sag by 2e-3, far below hausd / 4, so
  // neither the creases between them across the axis nor those of the
  // diagonals (a chord along the axis crosses them) ask for less than the
  // curvature and hmax.
  const double r = 2, hausd = 5e-2, hmax = 1.5;
  const int n = 96, k = 40;
  const SurfaceMesh m = rebuilt(cylinder(r, n, k));
  MetricBounds b;
  b.hmax = hmax;
  const MetricField M = curvature_metric(m, hausd, b);
  double worst_across = 0, worst_along = 0;
  for (int j = 3; j < k - 3; ++j)  // away from the open ends
    for (int i = 0; i < n; ++i) {
      const Vertex v(j * n + i);
      const Vec3 p = m.position(v);
      const Vec3 across = normalized(Vec3(-p.y, p.x, 0));
      const double h_across = 1 / metric_length(M[v.idx], across);
      const double h_along = 1 / metric_length(M[v.idx], Vec3(0, 0, 1));
      worst_across = std::max(worst_across, std::fabs(h_across / std::sqrt(8 * hausd * r) - 1));
      worst_along = std::max(worst_along, std::fabs(h_along / hmax - 1));
    }
  MESSAGE("cylinder r = 2: sizes across within " << worst_across << ", along within " << worst_along);
  CHECK(worst_across < 1e-2);
  CHECK(worst_along < 1e-4);  // principal directions a hair off the axis mix in the size across
}

TEST_CASE("hessian: the ring quadric fits of the deviation bound give the sphere's and the cylinder's sizes") {
  // MetricRecipe::deviation_fit: quadrics over 1-rings, first order. On the
  // unit sphere (5120 triangles) the sizes are sqrt(8 hausd) within 1%, on
  // the cylinder sqrt(8 hausd r) across and hmax along the axis.
  const double hausd = 1e-2;
  const SurfaceMesh sphere = rebuilt(icosphere(4));
  const MetricField S = curvature_metric(sphere, hausd, {}, ring_quadric_fit());
  double worst = 0;
  for (int i = 0; i < sphere.vertex_capacity(); ++i)
    for (double h : sizes_and_directions(S[i]).sizes) worst = std::max(worst, std::fabs(h / std::sqrt(8 * hausd) - 1));
  const double r = 2, hmax = 1.5, cyl_hausd = 5e-2;
  const int n = 96, k = 40;
  const SurfaceMesh cyl = rebuilt(cylinder(r, n, k));
  MetricBounds b;
  b.hmax = hmax;
  const MetricField C = curvature_metric(cyl, cyl_hausd, b, ring_quadric_fit());
  double worst_across = 0, worst_along = 0;
  for (int j = 3; j < k - 3; ++j)
    for (int i = 0; i < n; ++i) {
      const Vertex v(j * n + i);
      const Vec3 p = cyl.position(v);
      const Vec3 across = normalized(Vec3(-p.y, p.x, 0));
      worst_across = std::max(worst_across, std::fabs(1 / metric_length(C[v.idx], across) / std::sqrt(8 * cyl_hausd * r) - 1));
      worst_along = std::max(worst_along, std::fabs(1 / metric_length(C[v.idx], Vec3(0, 0, 1)) / hmax - 1));
    }
  MESSAGE("ring quadric fits: sphere sizes within " << worst << ", cylinder across within " << worst_across
                                                     << ", along within " << worst_along);
  CHECK(worst < 0.01);
  CHECK(worst_across < 0.005);
  CHECK(worst_along < 1e-4);
}

TEST_CASE("hessian metric: f = 100 x^2 on the flat square gives diag(2/9 200/eps, hmax^-2, hmax^-2)") {
  const SurfaceMesh m = irregular_plane(11, Vec3(), Vec3(1, 0, 0), Vec3(0, 1, 0), 7);
  const Quadratic f{SymTensor3::diagonal(100, 0, 0), Vec3()};
  const RecoveredDerivatives d = recover_derivatives(m, sample(m, f));
  for (double p : {double(INFINITY), 1.0, 2.0}) {
    HessianMetricOptions o;
    o.error = 0.01;
    o.p = p;
    o.bounds.hmax = 1.0;
    const MetricField M = hessian_metric(m, d.hessian, o);
    // A constant Hessian makes every L^p metric the L^inf one.
    const SymTensor3 expect = SymTensor3::diagonal(2.0 / 9.0 * 200 / 0.01, 1, 1);
    double worst = 0;
    for (const SymTensor3& X : M) worst = std::max(worst, frobenius_norm(X - expect) / frobenius_norm(expect));
    CAPTURE(p);
    CHECK(worst < 1e-9);
  }
  // Default hmax: the bounding-box diagonal (sqrt 2 here).
  HessianMetricOptions o;
  o.error = 0.01;
  const MetricField M = hessian_metric(m, d.hessian, o);
  CHECK(M[0].yy() == doctest::Approx(0.5).epsilon(1e-9));
  CHECK(M[0].zz() == doctest::Approx(0.5).epsilon(1e-9));
  // Error constant as an option: 1/8.
  o.error_constant = 1.0 / 8.0;
  CHECK(hessian_metric(m, d.hessian, o)[0].xx() == doctest::Approx(200.0 / 8 / 0.01).epsilon(1e-9));
  // Exactly one target.
  o.target_vertices = 100;
  CHECK_THROWS_AS(hessian_metric(m, d.hessian, o), MetricError);
}

TEST_CASE("hessian metric: L^p metric for a target vertex count, and the L^p error scaling") {
  const SurfaceMesh m = icosphere(4);
  const Quadratic f{SymTensor3(4, 1, 0.2, 0, 0.5, 0.1), Vec3(0, 0, 1)};
  const RecoveredDerivatives d = recover_derivatives(m, sample(m, f));
  for (double p : {1.0, 2.0, double(INFINITY)}) {
    HessianMetricOptions o;
    o.p = p;
    o.target_vertices = 3000;
    o.bounds.hmin = 1e-3;
    const MetricField M = hessian_metric(m, d.hessian, o);
    const double n = predicted_vertex_count(metric_complexity(m, M));
    CAPTURE(p);
    CHECK(n == doctest::Approx(3000).epsilon(1e-6));
    for (const SymTensor3& X : M) CHECK(is_spd(X));
  }
  // Error mode without clamping: halving eps doubles M for every p (M ~ 1/eps),
  // so the vertex count doubles (in 2D, N ~ 1/eps).
  HessianMetricOptions o;
  o.p = 2;
  o.bounds.hmax = 1e6;
  o.error = 1e-3;
  const double n1 = predicted_vertex_count(metric_complexity(m, hessian_metric(m, d.hessian, o)));
  o.error = 5e-4;
  const double n2 = predicted_vertex_count(metric_complexity(m, hessian_metric(m, d.hessian, o)));
  CHECK(n2 == doctest::Approx(2 * n1).epsilon(1e-9));
}

TEST_CASE("hessian: refuses non-finite values naming the vertex") {
  const SurfaceMesh m = icosphere(1);
  std::vector<double> f(m.vertex_capacity(), 1.0);
  f[3] = NAN;
  CHECK_THROWS_WITH_AS(recover_derivatives(m, f), doctest::Contains("vertex 4"), MetricError);
}

TEST_CASE("hessian: vertices whose neighbours do not determine a quadratic take their neighbours' fit") {
  // An icosphere plus a separate fan of 3 triangles (4 points, too few for
  // a quadratic even over 4 rings): its vertices are counted and filled
  // from their neighbours, or zero when none was fitted.
  MeshData data = to_mesh_data(icosphere(2));
  const int base = static_cast<int>(data.vertices.size());
  for (const Vec3& p : {Vec3(3, 0, 0), Vec3(3.1, 0, 0), Vec3(3, 0.1, 0), Vec3(2.9, 0, 0.1)}) data.vertices.push_back(p);
  data.triangles.push_back({base, base + 1, base + 2});
  data.triangles.push_back({base, base + 2, base + 3});
  SurfaceMesh m;
  build_mesh(data, m);
  const ValidationReport v = m.validate();
  REQUIRE_MESSAGE(v.ok(), v.summary());
  std::vector<double> f(m.vertex_capacity());
  for (int i = 0; i < m.vertex_capacity(); ++i) f[i] = m.position(Vertex(i)).x * m.position(Vertex(i)).x;
  const RecoveredDerivatives r = recover_derivatives(m, f);
  CHECK(r.unfitted == 4);
  for (int i = base; i < m.vertex_capacity(); ++i) CHECK(frobenius_norm(r.hessian[i]) == 0.0);
  // The sphere's vertices are fitted as before: curvatures +1, +1 (trace 2).
  int unfitted = -1;
  const auto II = recover_curvature(m, {}, &unfitted);
  CHECK(unfitted == 4);
  for (int i = 0; i < base; ++i) CHECK(II[i].m[0] + II[i].m[2] + II[i].m[5] == doctest::Approx(2.0).epsilon(0.1));
}
