// Hessians on the meshes that solution-driven cycles produce (the report's
// section 7.1): strips one triangle wide where every vertex is on the
// boundary (recovery), the unit square in two triangles and a discontinuous
// field (the Hessian of an expression), and the cycle defaults.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "metric/expression.h"
#include "metric/hessian.h"
#include "metric/surface_metric.h"

using namespace anisurf;

namespace {

// A strip one triangle wide along u: n + 1 points on the line origin + t u
// and n + 1 on the parallel line at distance `width` along w, with the
// abscissas jittered by up to `jitter` of the spacing (as an adapted mesh
// of a rank-1 metric): every vertex is on the boundary.
SurfaceMesh strip(int n, double width, double jitter, const Vec3& origin, const Vec3& u, const Vec3& w,
                  unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> shake(-jitter, jitter);
  SurfaceMesh m;
  const double h = 1.0 / n;
  for (int side = 0; side < 2; ++side)
    for (int i = 0; i <= n; ++i) {
      const double t = i * h + (i > 0 && i < n ? shake(rng) * h : 0.0);
      m.add_vertex(origin + t * u + (side * width) * w);
    }
  auto bottom = [](int i) { return Vertex(i); };
  auto top = [n](int i) { return Vertex(n + 1 + i); };
  for (int i = 0; i < n; ++i) {
    m.add_triangle(bottom(i), bottom(i + 1), top(i + 1));
    m.add_triangle(bottom(i), top(i + 1), top(i));
  }
  return m;
}

// The unit square in two triangles (the report's figure 17 start of case 1).
SurfaceMesh two_triangle_square() {
  SurfaceMesh m;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}) m.add_vertex(p);
  m.add_triangle(Vertex(0), Vertex(1), Vertex(2));
  m.add_triangle(Vertex(0), Vertex(2), Vertex(3));
  return m;
}

// A regular n x n grid of the unit square (z = 0), diagonals alternating.
SurfaceMesh grid_square(int n) {
  SurfaceMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_vertex(Vec3(double(i) / n, double(j) / n, 0));
  auto id = [n](int i, int j) { return Vertex(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2) {
        m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        m.add_triangle(id(i, j), id(i + 1, j), id(i, j + 1));
        m.add_triangle(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  return m;
}

bool all_on_boundary(const SurfaceMesh& m) {
  for (int i = 0; i < m.vertex_capacity(); ++i)
    if (!m.is_boundary(Vertex(i))) return false;
  return true;
}

double max_abs_difference(const SymTensor2& a, const SymTensor2& b) {
  return std::max({std::fabs(a.m[0] - b.m[0]), std::fabs(a.m[1] - b.m[1]), std::fabs(a.m[2] - b.m[2])});
}

}  // namespace

TEST_CASE("hessian loop: recovery on a strip of boundary vertices is exact along the strip, zero across") {
  // f = 100 x^2 + 30 x y + 7 y^2 + 3 x - 2 y in the strip's coordinates: on two
  // parallel lines the curvature across (7 y^2 = 7 y on y in {0, 1}) is not
  // in the data; the curvature along (200) and the twist (30) are.
  const Vec3 u = normalized(Vec3(1, 0.3, -0.2)), w = normalized(cross(Vec3(0.1, -0.2, 1), u));
  auto f = [&](const Vec3& p) {
    const double x = dot(p, u), y = dot(p, w);
    return 100 * x * x + 30 * x * y + 7 * y * y + 3 * x - 2 * y;
  };
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const double width = seed % 2 ? 1.0 : 0.05;  // a square's strip, or a thin band
    const SurfaceMesh m = strip(20 + 7 * seed, width, 0.3, Vec3(0.2, -0.4, 1), u, w, seed);
    REQUIRE(m.validate().ok());
    REQUIRE(all_on_boundary(m));
    std::vector<double> values(m.vertex_capacity());
    for (int i = 0; i < m.vertex_capacity(); ++i) values[i] = f(m.position(Vertex(i)));
    HessianRecoveryOptions ro;
    ro.degree = seed <= 2 ? 3 : 2;
    const RecoveredDerivatives d = recover_derivatives(m, values, ro);
    CAPTURE(seed);
    CHECK(d.reduced == m.n_vertices());
    CHECK(d.unfitted == 0);
    double worst = 0;
    for (int i = 0; i < m.vertex_capacity(); ++i) {
      const SymTensor2 T = restrict_to_tangent(d.hessian[i], u, w);
      worst = std::max(worst, max_abs_difference(T, SymTensor2(200, 30, 0)));
    }
    CHECK(worst < 1e-6 * 200);
  }
}

TEST_CASE("hessian loop: the metric recovered on a strip predicts the vertex count of the exact Hessian's") {
  // The first cycle of f = 100 x^2 from a coarse square gives a strip (hmax is
  // the diagonal across x); the next metric must not collapse it.
  const SurfaceMesh m = strip(60, 1.0, 0.35, Vec3(), Vec3(1, 0, 0), Vec3(0, 1, 0), 9);
  std::vector<double> values(m.vertex_capacity());
  for (int i = 0; i < m.vertex_capacity(); ++i) values[i] = 100 * std::pow(m.position(Vertex(i)).x, 2);
  HessianMetricOptions o = cycle_metric_defaults();
  o.error = 0.01;
  const MetricField recovered = hessian_metric(m, recover_derivatives(m, values).hessian, o);
  const MetricField exact = hessian_metric(m, hessian_of_expression(m, "100*x^2"), o);
  const double n_recovered = predicted_vertex_count(metric_complexity(m, recovered));
  const double n_exact = predicted_vertex_count(metric_complexity(m, exact));
  MESSAGE("predicted vertices on the strip: recovered " << n_recovered << ", exact " << n_exact);
  CHECK(n_exact > 50);
  CHECK(n_recovered == doctest::Approx(n_exact).epsilon(0.02));
}

TEST_CASE("hessian loop: the Hessian of an expression is exact on the two-triangle square") {
  const SurfaceMesh m = two_triangle_square();
  // A recovery sees the P1 field only (100 x here): no curvature.
  std::vector<double> values(m.vertex_capacity());
  for (int i = 0; i < m.vertex_capacity(); ++i) values[i] = 100 * std::pow(m.position(Vertex(i)).x, 2);
  const RecoveredDerivatives d = recover_derivatives(m, values);
  for (const SymTensor3& H : d.hessian) CHECK(frobenius_norm(H) == 0.0);
  // The expression's Hessian: diag(200, 0) at every vertex.
  const std::vector<SymTensor3> H = hessian_of_expression(m, "100*x^2");
  for (const SymTensor3& X : H) CHECK(frobenius_norm(X - SymTensor3::diagonal(200, 0, 0)) < 1e-6 * 200);
  // A general quadratic, mixed term included.
  const std::vector<SymTensor3> G = hessian_of_expression(m, "3*x^2 - 2*x*y + 0.5*y^2 + x - 4*y + z");
  for (const SymTensor3& X : G) CHECK(frobenius_norm(X - SymTensor3(6, -2, 1, 0, 0, 0)) < 1e-6 * 6);
  // Hence the cycle metric at once: c / eps |H| along x, hmax (the diagonal) across.
  HessianMetricOptions o = cycle_metric_defaults();
  o.error = 0.01;
  const MetricField M = hessian_metric(m, H, o);
  for (const SymTensor3& X : M) {
    CHECK(X.xx() == doctest::Approx(2.0 / 9.0 * 200 / 0.01).epsilon(1e-6));
    CHECK(X.yy() == doctest::Approx(0.5).epsilon(1e-6));
  }
}

TEST_CASE("hessian loop: the Hessian of an expression on a sphere includes the curvature term") {
  // On the unit sphere (outward normals) the Hessian over the tangent-plane
  // parametrisation of f = x^2 + 2 y z + x / 2 is T^T (2A) T - (grad f . n) I,
  // as recover_derivatives gives it (tests/test_metric_hessian.cpp).
  SurfaceMesh m;
  const int rings = 24, sectors = 48;
  m.add_vertex(Vec3(0, 0, 1));
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const double th = M_PI * r / rings, ph = 2 * M_PI * s / sectors;
      m.add_vertex(Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  m.add_vertex(Vec3(0, 0, -1));
  auto id = [&](int r, int s) { return Vertex(1 + (r - 1) * sectors + (s % sectors)); };
  const Vertex south(1 + (rings - 1) * sectors);
  for (int s = 0; s < sectors; ++s) {
    m.add_triangle(Vertex(0), id(1, s), id(1, s + 1));
    for (int r = 1; r + 1 < rings; ++r) {
      m.add_triangle(id(r, s), id(r + 1, s), id(r + 1, s + 1));
      m.add_triangle(id(r, s), id(r + 1, s + 1), id(r, s + 1));
    }
    m.add_triangle(id(rings - 1, s), south, id(rings - 1, s + 1));
  }
  REQUIRE(m.validate().ok());
  const std::vector<SymTensor3> H = hessian_of_expression(m, "x^2 + 2*y*z + x/2");
  const SymTensor3 A2(2, 0, 0, 0, 2, 0);  // 2A: xx = 2, yz = 2
  double worst = 0;
  for (int i = 0; i < m.vertex_capacity(); ++i) {
    const Vec3 p = m.position(Vertex(i));
    const auto fr = tangent_frame(p);
    const Vec3 grad(2 * p.x + 0.5, 2 * p.z, 2 * p.y);
    SymTensor2 exact = restrict_to_tangent(A2, fr[0], fr[1]);
    exact += SymTensor2::identity(-dot(grad, p));
    worst = std::max(worst, max_abs_difference(restrict_to_tangent(H[i], fr[0], fr[1]), exact));
  }
  // Differences are exact for a quadratic; what remains is the error of the
  // fitted curvature (largest at the poles' 48-valent fans).
  MESSAGE("sphere, 24 x 48: max error of the expression Hessian " << worst);
  CHECK(worst < 0.1);
}

TEST_CASE("hessian loop: a discontinuity takes the recovered Hessian near it, the exact one away from it") {
  const int n = 20;
  const SurfaceMesh m = grid_square(n);
  const std::string f = "(x<0.33)?100*x^2:5";
  const std::vector<SymTensor3> H = hessian_of_expression(m, f);
  const RecoveredDerivatives recovered = recover_derivatives(m, evaluate_at_vertices(m, f));
  const double h = 1.0 / n;
  double largest_at_jump = 0;
  for (int i = 0; i < m.vertex_capacity(); ++i) {
    const double x = m.position(Vertex(i)).x;
    CAPTURE(x);
    REQUIRE(std::isfinite(frobenius_norm(H[i])));
    // Beyond the one-ring stencils that see the jump and 2 rings more: exact.
    if (x < 0.33 - 3.5 * h) CHECK(H[i].xx() == doctest::Approx(200).epsilon(1e-6));
    if (x > 0.33 + 3.5 * h) CHECK(frobenius_norm(H[i]) < 1e-6);
    // Next to the jump (f from 10.9 to 5): the recovered Hessian.
    if (std::fabs(x - 0.33) < h) {
      CHECK(frobenius_norm(H[i] - recovered.hessian[i]) == 0.0);
      largest_at_jump = std::max(largest_at_jump, std::fabs(H[i].xx()));
    }
  }
  // Of the order of the jump over h^2 there.
  CHECK(largest_at_jump > 0.1 * 5.0 / (h * h));
  // A domain ending beyond the mesh (sqrt of a negative number past x = 1.03):
  // shorter steps there, finite values.
  for (const SymTensor3& X : hessian_of_expression(m, "sqrt(1.03 - x)")) CHECK(std::isfinite(frobenius_norm(X)));
  // Ending at a vertex: refused, naming it.
  CHECK_THROWS_WITH_AS(hessian_of_expression(m, "sqrt(1 - x)"), doctest::Contains("vertex"), ExpressionError);
}
