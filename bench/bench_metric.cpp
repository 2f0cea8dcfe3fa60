// Throughput of the metric kernels: edge lengths (eq. 6, eq. 7), metric
// interpolation (linear, Remark 2's inverse, linear size, log-Euclidean),
// eigen-decompositions (Jacobi against Eigen's solvers), intersections; with
// MESH SOL also the gradation and the quality measure on that mesh.
//   usage: bench_metric [MESH SOL [RATIO]]
#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "io/mesh_io.h"
#include "metric/gradation.h"
#include "metric/length.h"
#include "metric/mesh_quality.h"
#include "metric/metric_field.h"

using namespace anisurf;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Runs f(i) for i in [0, n) repeatedly for at least min_seconds; returns calls per second.
template <class F>
double rate(F f, int n, double min_seconds = 0.5) {
  long long calls = 0;
  const double t0 = now();
  double t = t0;
  do {
    for (int i = 0; i < n; ++i) f(i);
    calls += n;
    t = now();
  } while (t - t0 < min_seconds);
  return calls / (t - t0);
}

volatile double g_sink = 0;

}  // namespace

int main(int argc, char** argv) {
  const int n = 1 << 14;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> lh(std::log(1e-3), 0.0);
  std::normal_distribution<double> g;
  std::vector<SymTensor3> M(n);
  std::vector<Vec3> e(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 a = normalized(Vec3(g(rng), g(rng), g(rng)));
    const Vec3 b = normalized(cross(a, Vec3(g(rng), g(rng), g(rng))));
    M[i] = metric_from_sizes({std::exp(lh(rng)), std::exp(lh(rng)), std::exp(lh(rng))}, {a, b, cross(a, b)});
    e[i] = 0.05 * Vec3(g(rng), g(rng), g(rng));
  }
  auto nx = [n](int i) { return (i * 7919 + 1) & (n - 1); };

  std::printf("%-44s %12s\n", "kernel (random anisotropic metrics)", "per second");
  auto report = [](const char* name, double r) { std::printf("%-44s %12.3e\n", name, r); };
  double s = 0;
  report("edge length eq. 6 (metric linear)", rate([&](int i) { s += edge_length(M[i], M[nx(i)], e[i], LengthFormula::LinearMetric); }, n));
  report("edge length eq. 7 (size linear)", rate([&](int i) { s += edge_length(M[i], M[nx(i)], e[i], LengthFormula::LinearSize); }, n));
  report("edge length, adaptive quadrature (1e-8)",
         rate([&](int i) { s += integrated_edge_length(M[i], M[nx(i)], e[i], MetricInterpolation::Linear, 1e-8); }, n));
  const std::array<double, 3> w = {0.2, 0.3, 0.5};
  const struct {
    const char* name;
    MetricInterpolation how;
  } schemes[] = {{"interpolation in a triangle: linear", MetricInterpolation::Linear},
                 {"interpolation in a triangle: inverse (Rk 2)", MetricInterpolation::Inverse},
                 {"interpolation in a triangle: linear size", MetricInterpolation::LinearSize},
                 {"interpolation in a triangle: log-Euclidean", MetricInterpolation::LogEuclidean}};
  for (const auto& sc : schemes)
    report(sc.name, rate([&](int i) { s += interpolate_metric({M[i], M[nx(i)], M[nx(nx(i))]}, w, sc.how).m[0]; }, n));
  report("eigen-decomposition: Jacobi (ours)", rate([&](int i) { s += eigen_decompose(M[i]).values[0]; }, n));
  std::vector<Eigen::Matrix3d> E(n);
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) E[i](r, c) = M[i](r, c);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  report("eigen-decomposition: Eigen compute()", rate([&](int i) { es.compute(E[i]); s += es.eigenvalues()(0); }, n));
  report("eigen-decomposition: Eigen computeDirect()",
         rate([&](int i) { es.computeDirect(E[i]); s += es.eigenvalues()(0); }, n));
  report("intersection (simultaneous reduction)", rate([&](int i) { s += intersect(M[i], M[nx(i)]).m[0]; }, n));
  g_sink = s;

  if (argc >= 3) {
    const double t0 = now();
    BuildReport r;
    SurfaceMesh mesh = load_mesh(argv[1], &r);
    attach_fields(mesh, read_sol(argv[2], r.input_vertices), r);
    MetricField field = metric_from_field(mesh, {}, r.vertex_origin);
    const double t1 = now();
    std::printf("\n%s: %d vertices, %d triangles, loaded in %.2f s\n", argv[1], mesh.n_vertices(), mesh.n_triangles(),
                t1 - t0);
    const MeshQuality q = measure_mesh_quality(mesh, field);
    const double t2 = now();
    std::printf("quality measure: %.3f s (%.3e edges/s), %.2f %% in band\n", t2 - t1, q.edges / (t2 - t1),
                100 * q.in_band_share);
    GradationOptions o;
    o.ratio = argc >= 4 ? std::stod(argv[3]) : 1.3;
    const GradationReport gr = gradate_metric(mesh, field, o);
    const double t3 = now();
    std::printf("gradation ratio %.2f: %.3f s, %lld edge checks, %lld updates at %d vertices, %s\n", o.ratio, t3 - t2,
                gr.edge_checks, gr.updates, gr.vertices_changed, gr.converged ? "converged" : "NOT converged");
    MetricField again = field;
    const GradationReport g2 = gradate_metric(mesh, again, o);
    std::printf("second gradation (idempotence): %.3f s, %lld updates\n", now() - t3, g2.updates);
  }
  return 0;
}
