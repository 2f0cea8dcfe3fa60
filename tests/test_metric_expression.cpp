// Metrics from user expressions (muParser): values, and refusals with the
// expression, the position of a parse error, or the vertex of a bad value.
#include <doctest/doctest.h>

#include "metric/expression.h"
#include "metric/hessian.h"

using namespace anisurf;

namespace {

// 3 x 3 vertices on the unit square z = 0 (vertex 0 at the origin).
SurfaceMesh small_square() {
  SurfaceMesh m;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.add_vertex(Vec3(0.5 * i, 0.5 * j, 0));
  auto id = [](int i, int j) { return Vertex(3 * j + i); };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}

}  // namespace

#ifdef ANISURF_HAVE_MUPARSER

TEST_CASE("expression: values, constants, several results") {
  const Expression e("x + 2*y^2 - z, sin(pi/2), e");
  CHECK(e.results() == 3);
  const auto r = e.evaluate(Vec3(1, 2, 3));
  CHECK(r[0] == doctest::Approx(6.0));
  CHECK(r[1] == doctest::Approx(1.0));
  CHECK(r[2] == doctest::Approx(M_E));
  CHECK(Expression("1e-3*x").evaluate(Vec3(2, 0, 0))[0] == doctest::Approx(2e-3));
}

TEST_CASE("expression: size and tensor metrics") {
  const SurfaceMesh m = small_square();
  const MetricField S = metric_from_size_expression(m, "0.1 + x");
  CHECK(S[1] == isotropic_metric(0.6));  // vertex 1 at x = 0.5
  CHECK(S[2] == isotropic_metric(1.1));  // vertex 2 at x = 1
  const MetricField T = metric_from_tensor_expression(m, "1/(0.1+x)^2, 0, 100, 0, 0, 1");
  CHECK(T[1].xx() == doctest::Approx(1 / 0.36));
  CHECK(T[1].yy() == doctest::Approx(100));
  const std::vector<double> f = evaluate_at_vertices(m, "100*x^2");
  CHECK(f[2] == doctest::Approx(100.0));
}

TEST_CASE("expression: a parse error quotes the expression and marks the position") {
  try {
    Expression("100*x^^2");
    FAIL("no exception");
  } catch (const ExpressionError& e) {
    const std::string msg = e.what();
    MESSAGE(msg);
    CHECK(msg.find("'100*x^^2'") != std::string::npos);
    CHECK(msg.find("position 6") != std::string::npos);  // muParser counts from 0
    CHECK(msg.find("\n        ^") != std::string::npos);  // under the second '^'
  }
  CHECK_THROWS_WITH_AS(Expression("2*w"), doctest::Contains("'2*w'"), ExpressionError);
  CHECK_THROWS_WITH_AS(Expression("sin(x"), doctest::Contains("'sin(x': Missing parenthesis"), ExpressionError);
  CHECK_THROWS_AS(Expression(""), ExpressionError);
}

TEST_CASE("expression: non-finite values and invalid metrics name the vertex") {
  const SurfaceMesh m = small_square();
  // 1/x is infinite at the vertices with x = 0: vertex 1 (1-based) first.
  CHECK_THROWS_WITH_AS(metric_from_size_expression(m, "1/x"),
                       doctest::Contains("vertex 1 (1-based) at (x, y, z) = (0, 0, 0): a division by zero"),
                       ExpressionError);
  // The numbering of the file through vertex_origin.
  std::vector<int> origin = {41, 1, 2, 3, 4, 5, 6, 7, 8};
  CHECK_THROWS_WITH_AS(evaluate_at_vertices(m, "1/x", origin), doctest::Contains("vertex 42"), ExpressionError);
  CHECK_THROWS_WITH_AS(evaluate_at_vertices(m, "sqrt(x-0.75)"), doctest::Contains("outside the domain"),
                       ExpressionError);
  CHECK_THROWS_WITH_AS(metric_from_size_expression(m, "0.5 - x"), doctest::Contains("expected h > 0"),
                       ExpressionError);
  CHECK_THROWS_WITH_AS(metric_from_tensor_expression(m, "1, 0, 1"), doctest::Contains("expected 6"),
                       ExpressionError);
  CHECK_THROWS_WITH_AS(metric_from_tensor_expression(m, "1, 2, 1, 0, 0, 1"),
                       doctest::Contains("not positive definite"), ExpressionError);
  CHECK_THROWS_WITH_AS(evaluate_at_vertices(m, "x, y"), doctest::Contains("expected one value"), ExpressionError);
}

TEST_CASE("expression: --hessian-of pipeline, f = 100 x^2") {
  const SurfaceMesh m = small_square();
  const RecoveredDerivatives d = recover_derivatives(m, evaluate_at_vertices(m, "100*x^2"));
  HessianMetricOptions o;
  o.error = 0.01;
  o.bounds.hmax = 1;
  const MetricField M = hessian_metric(m, d.hessian, o);
  for (const SymTensor3& X : M) {
    CHECK(X.xx() == doctest::Approx(2.0 / 9.0 * 200 / 0.01).epsilon(1e-9));
    CHECK(X.yy() == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(X.zz() == doctest::Approx(1.0).epsilon(1e-9));
    CHECK(std::fabs(X.xy()) < 1e-6);
  }
}

#else

TEST_CASE("expression: without muParser, a clear refusal") {
  CHECK_THROWS_WITH_AS(Expression("x"), doctest::Contains("no expression parser"), ExpressionError);
}

#endif
