// Throughput of the metric kernels: edge lengths (eq. 6, eq. 7), metric
// interpolation (linear, Remark 2's inverse, linear size, log-Euclidean),
// eigen-decompositions (Jacobi against Eigen's solvers), intersections; with
// MESH SOL also the gradation and the quality measure on that mesh; with
// --geometric MESH the steps of the geometric metric (adapt --curvature
// --hausd D) on that mesh, each timed apart (best of REPEATS runs).
//   usage: bench_metric [MESH SOL [RATIO]]
//          bench_metric --geometric MESH [HAUSD [REPEATS]]   (HAUSD default: 0.001 x diagonal)
#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "geometry/features.h"
#include "io/mesh_io.h"
#include "metric/gradation.h"
#include "metric/length.h"
#include "metric/hessian.h"
#include "metric/mesh_quality.h"
#include "metric/metric_field.h"
#include "metric/recipe.h"
#include "metric/surface_metric.h"

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

// Best wall time of `repeats` calls of f.
template <class F>
double best_seconds(int repeats, F f) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    const double t0 = now();
    f();
    best = std::fmin(best, now() - t0);
  }
  return best;
}

// The steps of build_metric for --curvature --hausd D (gradation 1.3), and
// the hausd intersection another source goes through, timed one by one.
int bench_geometric_metric(const std::string& path, double hausd, int repeats) {
  BuildReport r;
  SurfaceMesh mesh = load_mesh(path, &r);
  // The feature curves split the curvature fits (adapt tags them first too).
  detect_features(mesh);
  const double diagonal = mesh.bbox().diagonal();
  if (!(hausd > 0)) hausd = 1e-3 * diagonal;
  std::printf("%s: %d vertices, %d triangles, hausd %g (%.2g x diagonal), best of %d\n", path.c_str(),
              mesh.n_vertices(), mesh.n_triangles(), hausd, hausd / diagonal, repeats);
  auto step = [](const char* name, double seconds) { std::printf("  %-40s %8.4f s\n", name, seconds); };

  std::vector<Vec3> normals;
  step("fitted normals", best_seconds(repeats, [&] { normals = fitted_normals(mesh); }));
  std::vector<SymTensor3> II;
  step("curvature (normals + 2nd form fit)", best_seconds(repeats, [&] { II = recover_curvature(mesh); }));
  MetricField curvature;
  step("curvature metric (all of it)", best_seconds(repeats, [&] { curvature = curvature_metric(mesh, hausd); }));
  MetricField intersected;
  step("hausd intersection (iso diagonal/60)", best_seconds(repeats, [&] {
         intersected.assign(curvature.size(), isotropic_metric(diagonal / 60));
         for (Vertex v : mesh.vertices()) intersected[v.idx] = intersect(intersected[v.idx], curvature[v.idx]);
       }));
  MetricField graded;
  GradationReport gr;
  step("gradation 1.3", best_seconds(repeats, [&] {
         graded = curvature;
         gr = gradate_metric(mesh, graded, GradationOptions{});
       }));
  std::printf("  %-40s %lld edge checks, %lld updates at %d vertices, %s\n", "", gr.edge_checks, gr.updates,
              gr.vertices_changed, gr.converged ? "converged" : "NOT converged");
  double predicted = 0;
  step("predicted vertices", best_seconds(repeats, [&] { predicted = predicted_vertices(mesh, graded); }));
  MetricRecipe recipe;
  recipe.source = MetricRecipe::Source::Curvature;
  recipe.hausd = hausd;
  MetricResult built;
  step("build_metric (curvature, hausd, hgrad 1.3)",
       best_seconds(repeats, [&] { built = build_metric(mesh, recipe, r.vertex_origin); }));
  std::printf("  predicted vertices: curvature %.0f, graded %.0f, build_metric %.0f\n",
              predicted_vertices(mesh, curvature), predicted, built.predicted_vertices);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::string(argv[1]) == "--geometric")
    return bench_geometric_metric(argv[2], argc >= 4 ? std::stod(argv[3]) : 0.0, argc >= 5 ? std::stoi(argv[4]) : 3);
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
