// Metric fields on surface meshes: .sol fields to metrics with vertex-naming
// errors, tangent restriction, complexity, and gradation on the bench sphere.
#include <doctest/doctest.h>

#include <chrono>
#include <random>

#include "io/mesh_io.h"
#include "metric/metric_field.h"
#include "metric/surface_metric.h"
#include "test_util.h"

using namespace anisurf;

namespace {

struct Loaded {
  SurfaceMesh mesh;
  BuildReport report;
};

Loaded load(const std::string& mesh_path, const std::string& sol_path) {
  Loaded l;
  l.mesh = load_mesh(mesh_path, &l.report);
  if (!sol_path.empty()) attach_fields(l.mesh, read_sol(sol_path, l.report.input_vertices), l.report);
  return l;
}

double mesh_area(const SurfaceMesh& m) {
  double a = 0;
  for (int t = 0; t < m.triangle_capacity(); ++t)
    if (!m.is_deleted(Triangle(t))) a += m.triangle_area(Triangle(t));
  return a;
}

// Two triangles of the unit square z = 0, with a field set by the caller.
SurfaceMesh unit_square() {
  SurfaceMesh m;
  Vertex a = m.add_vertex(Vec3(0, 0, 0)), b = m.add_vertex(Vec3(1, 0, 0)), c = m.add_vertex(Vec3(1, 1, 0)),
         d = m.add_vertex(Vec3(0, 1, 0));
  m.add_triangle(a, b, c);
  m.add_triangle(a, c, d);
  return m;
}

}  // namespace

TEST_CASE("surface metric: tangent frames and restriction to the tangent plane") {
  std::mt19937 rng(31);
  std::normal_distribution<double> g;
  for (int k = 0; k < 100; ++k) {
    const Vec3 n = normalized(Vec3(g(rng), g(rng), g(rng)));
    const auto f = tangent_frame(n);
    CHECK(std::fabs(dot(f[0], n)) < 1e-15);
    CHECK(std::fabs(dot(f[1], n)) < 1e-15);
    CHECK(std::fabs(dot(f[0], f[1])) < 1e-15);
    CHECK(norm(cross(f[0], f[1]) - n) < 1e-15);
    const SymTensor3 M(3, 0.5, 2, 0.1, -0.3, 1);
    const SymTensor2 T = restrict_to_tangent(M, n);
    // u^T T u = U^T M U for U = x t1 + y t2.
    const double x = g(rng), y = g(rng);
    CHECK(quad(T, x, y) == doctest::Approx(quad(M, x * f[0] + y * f[1])).epsilon(1e-14));
    // Isotropic metrics restrict to isotropic ones.
    const SymTensor2 I = restrict_to_tangent(isotropic_metric(0.1), n);
    CHECK(I.m[0] == doctest::Approx(100).epsilon(1e-14));
    CHECK(std::fabs(I.m[1]) < 1e-12);
    CHECK(I.m[2] == doctest::Approx(100).epsilon(1e-14));
    // extend_from_tangent is a right inverse, with the given normal eigenvalue.
    const SymTensor3 E = extend_from_tangent(T, f[0], f[1], 7.0);
    const SymTensor2 back = restrict_to_tangent(E, f[0], f[1]);
    for (int i = 0; i < 3; ++i) CHECK(back.m[i] == doctest::Approx(T.m[i]).epsilon(1e-13));
    CHECK(quad(E, n) == doctest::Approx(7.0).epsilon(1e-13));
    CHECK(norm(E * n - 7.0 * n) < 1e-12);
  }
  // diag(a, b, c) on the plane z = 0 is diag(a, b).
  const SymTensor2 T = restrict_to_tangent(SymTensor3::diagonal(4, 9, 100), Vec3(1, 0, 0), Vec3(0, 1, 0));
  CHECK(det(T) == doctest::Approx(36));
}

TEST_CASE("surface metric: complexity and predicted vertex count, closed forms") {
  SurfaceMesh m = unit_square();
  MetricField M(m.vertex_capacity(), SymTensor3::diagonal(4444.4, 1, 1));
  CHECK(metric_complexity(m, M) == doctest::Approx(std::sqrt(4444.4)).epsilon(1e-14));
  // The z eigenvalue does not matter on a flat z = 0 surface.
  MetricField N(m.vertex_capacity(), SymTensor3::diagonal(4444.4, 1, 1e6));
  CHECK(metric_complexity(m, N) == doctest::Approx(std::sqrt(4444.4)).epsilon(1e-14));
  CHECK(predicted_vertex_count(complexity_for_vertices(1234)) == doctest::Approx(1234));
}

TEST_CASE("surface metric: fields from the bench .sol files") {
  ANISURF_REQUIRE_SHARED(mesh_path, "bench/inputs/sphere20k.mesh");
  const std::string iso = anisurf::test::shared_file("bench/inputs/sphere20k_iso.sol");
  Loaded l = load(mesh_path, iso);
  const MetricField M = metric_from_field(l.mesh, {}, l.report.vertex_origin);
  CHECK(M.size() == static_cast<size_t>(l.mesh.vertex_capacity()));
  CHECK(M[0] == isotropic_metric(0.05));
  // C = area / h^2 for an isotropic metric.
  const double C = metric_complexity(l.mesh, M);
  CHECK(C == doctest::Approx(mesh_area(l.mesh) / 0.0025).epsilon(1e-12));
  MESSAGE("sphere20k iso 0.05: complexity " << C << ", predicted vertices " << predicted_vertex_count(C)
                                            << " (mmgs: 6300)");
  // A broken field names the vertex.
  Property<FieldValue> p = l.mesh.get_field(l.mesh.fields()[0].name);
  p.at(17)[0] = -1.0;
  try {
    metric_from_field(l.mesh, {}, l.report.vertex_origin);
    FAIL("no exception");
  } catch (const MetricError& e) {
    CHECK(std::string(e.what()).find("vertex " + std::to_string(l.report.vertex_origin[17] + 1)) != std::string::npos);
  }
  l.mesh.add_field("t", FieldKind::Tensor, 6);
  l.mesh.get_field("t").at(5) = {1, 2, 1, 0, 0, 1};
  CHECK_THROWS_WITH_AS(metric_from_field(l.mesh, "t", l.report.vertex_origin),
                       doctest::Contains("not positive definite"), MetricError);
  CHECK_THROWS_AS(metric_from_field(l.mesh, "nope"), MetricError);
}

TEST_CASE("gradation on sphere20k with the band metric: bounded, monotone, idempotent, converged") {
  ANISURF_REQUIRE_SHARED(mesh_path, "bench/inputs/sphere20k.mesh");
  Loaded l = load(mesh_path, anisurf::test::shared_file("bench/inputs/sphere20k_band.sol"));
  const MetricField original = metric_from_field(l.mesh);
  const auto edges = mesh_edges(l.mesh);
  const auto pos = vertex_positions(l.mesh);
  CHECK(edges.size() == 30720);
  for (GradationSpace space : {GradationSpace::Metric, GradationSpace::Physical}) {
    GradationOptions o;
    o.ratio = 1.3;
    o.space = space;
    o.measure_excess = true;
    MetricField M = original;
    const auto t0 = std::chrono::steady_clock::now();
    const GradationReport r = gradate_metric(l.mesh, M, o);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE(std::string(space == GradationSpace::Metric ? "metric" : "physical")
            << " space: " << r.updates << " updates, " << r.vertices_changed << " vertices changed, excess before "
            << r.max_excess_before << ", " << sec << " s");
    CHECK(r.converged);
    CHECK(r.updates > 0);
    CHECK(r.max_excess_before > 5);  // the band's jump of 10 in z
    double worst_excess = 0, worst_growth = 0;
    for (const auto& e : edges)
      worst_excess = std::max(worst_excess, edge_gradation_excess(M[e[0]], M[e[1]], pos[e[1]] - pos[e[0]], o));
    for (size_t i = 0; i < M.size(); ++i) worst_growth = std::max(worst_growth, generalized_eigenvalues(original[i], M[i])[2]);
    CHECK(worst_excess <= 1 + 1.01 * o.tolerance);
    CHECK(worst_growth <= 1 + 1e-12);  // no size increased
    // Metric space, checked independently: along each edge direction u the
    // size ratio is within 1 + l ln(ratio).
    if (space == GradationSpace::Metric) {
      double worst = 0;
      for (const auto& e : edges)
        for (int s = 0; s < 2; ++s) {
          const int p = e[s], q = e[1 - s];
          const Vec3 d = pos[q] - pos[p];
          const double bound = 1 + metric_length(M[p], d) * std::log(o.ratio);
          for (const Vec3& u : {normalized(d), Vec3(0, 0, 1), normalized(cross(d, pos[p]))})
            worst = std::max(worst, std::sqrt(quad(M[p], u) / quad(M[q], u)) / bound);
        }
      CHECK(worst <= 1 + 1.01 * o.tolerance);
    }
    MetricField again = M;
    CHECK(gradate_metric(l.mesh, again, o).updates == 0);
    CHECK(again == M);
  }
}
