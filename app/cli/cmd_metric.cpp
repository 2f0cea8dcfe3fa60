// `anisurf metric` (build a metric field) and `anisurf quality` (measure a
// mesh against one).
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli/cli.h"
#include "cli/metric_options.h"
#include "core/error.h"
#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "metric/expression.h"
#include "metric/hessian.h"
#include "metric/mesh_quality.h"
#include "metric/metric_field.h"
#include "metric/surface_metric.h"

namespace anisurf::cli {

namespace {

const char* kQualityHelp =
    "usage: anisurf quality MESH --sol SOL [--length auto|eq6|eq7] [--json]\n"
    "\n"
    "Measures MESH against the metric of SOL (a tensor m11 m12 m22 m13 m23 m33 per\n"
    "vertex, or a size h): edge lengths in the metric (min, mean, max, share in\n"
    "[1/sqrt2, sqrt2], histogram), the quality c_K of the report's eq. 17 from those\n"
    "lengths (q) and in the metric at each centroid (qc), the mean ratio at the\n"
    "centroid, and the vertex count the metric predicts (2 C / sqrt3, C the integral\n"
    "of sqrt(det M) over the surface). 1 is ideal for every quality measure.\n"
    "\n"
    "options:\n"
    "  --sol SOL        the metric (required)\n"
    "  --length F       edge length formula: eq6 (metric coefficients linear along the\n"
    "                   edge, report eq. 6), eq7 (size linear, Remark 2), or auto\n"
    "                   (default: eq7 for a size field, eq6 for a tensor field; the\n"
    "                   choices of bench/eval.py)\n"
    "  --json           print one JSON object\n"
    "\n"
    "example: anisurf quality out.mesh --sol out.sol --json\n";

const char* kMetricHelp =
    "usage: anisurf metric MESH SOURCE [BOUNDS] [--hgrad R] [--weld TOL] -o OUT.sol\n"
    "\n"
    "Builds a metric field on the vertices of MESH (the control space of the report's\n"
    "section 2) and writes it as a .sol of symmetric tensors m11 m12 m22 m13 m23 m33,\n"
    "numbered like the vertices of MESH (welded vertices share one value). Expressions use muParser syntax in x, y, z\n"
    "(+ - * / ^, sqrt, exp, log, sin, min, max, pi ...).\n"
    "\n"
    "SOURCE (exactly one):\n"
    "  --size EXPR           isotropic size h(x,y,z) > 0 (eq. 3: M = h^-2 I)\n"
    "  --tensor EXPR         the 6 components 'm11, m12, m22, m13, m23, m33' (SPD)\n"
    "  --hessian-of EXPR     metric of the P1 interpolation error of f(x,y,z): the\n"
    "                        Hessian of the expression (exact where f is smooth at the\n"
    "                        edges' scale, recovered from the vertex values near jumps\n"
    "                        and kinks), then, with |H| in the tangent plane,\n"
    "      --error EPS         the L^p-optimal metric of Loseille & Alauzet for the\n"
    "                          error EPS (p = inf: M = c/EPS |H|), or\n"
    "      --complexity C      the L^p-optimal metric of complexity C (integral of\n"
    "                          sqrt det M; about 2C/sqrt3 vertices), or\n"
    "      --vertices N        the same for N vertices (after bounds and gradation)\n"
    "      --norm P            p >= 1 or 'inf' (default 2: the L2 error the report's\n"
    "                          section 7.1 measures; settles adaptation cycles)\n"
    "      --error-constant c  c of the estimate (default 2/9, BAMG's)\n"
    "  --curvature --hausd D geometric metric: sizes sqrt(8 D / |kappa_i|) along the\n"
    "                        principal directions (chordal deviation D)\n"
    "  --sol FILE            a metric (tensor) or size (scalar) from a .sol\n"
    "\n"
    "BOUNDS and gradation (applied in this order: clamp, gradation):\n"
    "  --hmin A --hmax B     sizes clamped into [A, B]; for --hessian-of and --curvature\n"
    "                        hmax defaults to the bounding-box diagonal\n"
    "  --max-aniso K         largest ratio of sizes at a vertex\n"
    "  --hausd D             with another source: intersected with the curvature\n"
    "                        metric of D (Mmg's -hausd), before the gradation\n"
    "  --hgrad R             anisotropic gradation: sizes grow by at most about R per\n"
    "                        unit metric length along edges (Mmg's -hgrad; off by default;\n"
    "                        -1: off)\n"
    "  --hgrad-space S       metric (default) or physical growth law\n"
    "  --weld TOL            merge the vertices closer than TOL x the bounding box\n"
    "                        diagonal before building the metric, in every format (0:\n"
    "                        identical positions; a soup of triangles becomes one\n"
    "                        surface, as with `anisurf adapt --weld`)\n"
    "  -o OUT.sol            output (required)\n"
    "\n"
    "examples:\n"
    "  anisurf metric square3d.mesh --hessian-of \"100*x^2\" --error 0.01 --hmax 1 -o sq.sol\n"
    "  anisurf metric sphere.mesh --sol band.sol --hgrad 1.3 -o graded.sol\n";

struct LoadedMetric {
  SurfaceMesh mesh;
  BuildReport report;
  MetricField metric;
  bool scalar = false;  // the .sol held a size, not a tensor
};

// The smallest and largest sizes of the field over the mesh's vertices
// (parallel chunks of the vertex slots).
std::pair<double, double> size_range(const SurfaceMesh& mesh, const MetricField& M) {
  const int n = mesh.vertex_capacity();
  const int chunks = chunk_count(n, 8192);
  std::vector<std::pair<double, double>> ranges(static_cast<std::size_t>(chunks), {INFINITY, 0.0});
  run_chunks(n, chunks, [&](int chunk, int begin, int end) {
    auto& [lo, hi] = ranges[static_cast<std::size_t>(chunk)];
    for (int i = begin; i < end; ++i) {
      if (mesh.is_deleted(Vertex(i))) continue;
      const SymEigen3 e = eigen_decompose(M[i]);
      lo = std::min(lo, 1 / std::sqrt(e.values[2]));
      hi = std::max(hi, 1 / std::sqrt(e.values[0]));
    }
  });
  std::pair<double, double> out{INFINITY, 0.0};
  for (const auto& [lo, hi] : ranges) out = {std::min(out.first, lo), std::max(out.second, hi)};
  return out;
}

LoadedMetric load_mesh_and_metric(const std::string& mesh_path, const std::string& sol_path,
                                  const BuildOptions& build = {}) {
  LoadedMetric l;
  l.mesh = load_mesh(mesh_path, &l.report, build);
  if (!sol_path.empty()) {
    const auto fields = read_sol(sol_path, l.report.input_vertices);
    attach_fields(l.mesh, fields, l.report);
    bool tensor = false;
    for (const auto& f : fields) tensor = tensor || f.info.kind == FieldKind::Tensor;
    l.scalar = !tensor;
    try {
      l.metric = metric_from_field(l.mesh, {}, l.report.vertex_origin);
    } catch (const MetricError& e) {
      throw MetricError(sol_path + ": " + e.what());
    }
  }
  return l;
}

std::string bin_label(std::size_t i) {
  char buf[64];
  const double lo = i == 0 ? 0.0 : kLengthBins[i - 1], hi = kLengthBins[i];
  std::snprintf(buf, sizeof buf, "%.2f-%.2f", lo, hi);
  return buf;
}

int run_quality(const std::vector<std::string>& args) {
  ArgParser p(args);
  const bool json = p.flag("--json");
  const std::string sol = p.option("--sol");
  const std::string length = p.option("--length");
  const auto pos = p.positionals();
  if (pos.size() != 1) throw UsageError{"expected one MESH"};
  if (sol.empty()) throw UsageError{"--sol SOL is required"};
  if (!length.empty() && length != "auto" && length != "eq6" && length != "eq7")
    throw UsageError{"--length expects auto, eq6 or eq7, got '" + length + "'"};
  const LoadedMetric l = load_mesh_and_metric(pos[0], sol);
  MeshQualityOptions o;
  const bool eq7 = length == "eq7" || ((length.empty() || length == "auto") && l.scalar);
  o.length = eq7 ? LengthFormula::LinearSize : LengthFormula::LinearMetric;
  const MeshQuality q = measure_mesh_quality(l.mesh, l.metric, o);

  if (json) {
    nlohmann::json j;
    j["mesh"] = pos[0];
    j["sol"] = sol;
    j["length_formula"] = eq7 ? "eq7" : "eq6";
    j["nv"] = q.vertices;
    j["nt"] = q.triangles;
    j["ne"] = q.edges;
    j["len_min"] = q.length_min;
    j["len_mean"] = q.length_mean;
    j["len_max"] = q.length_max;
    j["len_in_range_pct"] = 100.0 * q.in_band_share;
    nlohmann::json hist = nlohmann::json::object();
    for (std::size_t i = 0; i < q.histogram.size(); ++i)
      hist[bin_label(i)] = q.edges ? 100.0 * q.histogram[i] / q.edges : 0.0;
    j["len_hist_pct"] = hist;
    j["q_min"] = q.q_min;
    j["q_mean"] = q.q_mean;
    j["qc_min"] = q.qc_min;
    j["qc_mean"] = q.qc_mean;
    j["mean_ratio_min"] = q.mean_ratio_min;
    j["mean_ratio_mean"] = q.mean_ratio_mean;
    j["complexity"] = q.complexity;
    j["predicted_vertices"] = q.predicted_vertices;
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("mesh                %s\nmetric              %s (%s lengths)\n", pos[0].c_str(), sol.c_str(),
              eq7 ? "eq. 7, size linear" : "eq. 6, metric linear");
  std::printf("vertices            %d\ntriangles           %d\nedges               %d\n", q.vertices, q.triangles,
              q.edges);
  std::printf("edge length         min %.4f  mean %.4f  max %.4f\n", q.length_min, q.length_mean, q.length_max);
  std::printf("in [0.71, 1.41]     %.2f %%\n", 100.0 * q.in_band_share);
  std::printf("histogram\n");
  for (std::size_t i = 0; i < q.histogram.size(); ++i)
    std::printf("  %-12s %8d  %6.2f %%\n", bin_label(i).c_str(), q.histogram[i],
                q.edges ? 100.0 * q.histogram[i] / q.edges : 0.0);
  std::printf("c_K (eq. 17)        min %.4f  mean %.4f\n", q.q_min, q.q_mean);
  std::printf("c_K at centroid     min %.4f  mean %.4f\n", q.qc_min, q.qc_mean);
  std::printf("mean ratio          min %.4f  mean %.4f\n", q.mean_ratio_min, q.mean_ratio_mean);
  std::printf("complexity          %.1f  (predicted vertices %.0f)\n", q.complexity, q.predicted_vertices);
  return 0;
}

int run_metric(const std::vector<std::string>& args) {
  ArgParser p(args);
  const MetricSourceOptions mo = parse_metric_options(p);
  const std::string out = p.option("-o", "--output");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double hausd = p.option_double("--hausd", nan);
  double hgrad = p.option_double("--hgrad", nan);
  const std::string hgrad_space = p.option("--hgrad-space");
  const BuildOptions build = weld_build_options(p);
  const auto pos = p.positionals();
  if (pos.size() != 1) throw UsageError{"expected one MESH"};
  if (out.empty()) throw UsageError{"-o OUT.sol is required"};
  if (mo.source_count() != 1)
    throw UsageError{"give exactly one source: --size, --tensor, --hessian-of, --curvature or --sol"};
  if (mo.curvature && !(hausd > 0)) throw UsageError{"--curvature needs --hausd D with D > 0"};
  GradationOptions grad;
  // -1, 0 or 1 turn the gradation off, as in `anisurf adapt` and Mmg.
  if (hgrad == -1 || hgrad == 0 || hgrad == 1) hgrad = nan;
  if (!std::isnan(hgrad)) {
    if (!(hgrad > 1)) throw UsageError{"--hgrad expects a ratio > 1, or -1 (off)"};
    grad.ratio = hgrad;
  }
  if (!hgrad_space.empty() && hgrad_space != "metric" && hgrad_space != "physical")
    throw UsageError{"--hgrad-space expects metric or physical"};
  grad.space = hgrad_space == "physical" ? GradationSpace::Physical : GradationSpace::Metric;

  if (!mo.hessian_of_field.empty())
    throw UsageError{"--hessian-of-field is an option of `anisurf adapt` (with --interpolate F.sol)"};
  const auto t0 = std::chrono::steady_clock::now();
  LoadedMetric l = load_mesh_and_metric(pos[0], mo.sol, build);
  // The curvature metric is fitted per smooth sector between the feature
  // curves: tag them as `adapt` does (default ridge angle).
  if (mo.curvature || hausd > 0) detect_features(l.mesh);
  const SurfaceMesh& mesh = l.mesh;
  MetricRecipe recipe = metric_recipe(mo, std::move(l.metric), hausd, std::isnan(hgrad) ? 0 : hgrad);
  recipe.hgrad_space = grad.space;
  MetricResult built = build_metric(mesh, recipe, l.report.vertex_origin);
  const MetricField& M = built.metric;
  const std::string what = built.description;
  const GradationReport& gr = built.gradation;
  if (!std::isnan(hgrad) && !gr.converged) std::cerr << "anisurf metric: warning: gradation stopped at its update cap\n";

  // Back to the numbering of the file's vertices.
  const int n_file = l.report.input_vertices;
  const bool planar = mesh.dimension() == 2;
  const double fallback_h = mesh.bbox().diagonal();
  FieldData f;
  f.info = FieldInfo{"metric", FieldKind::Tensor, planar ? 3 : 6};
  f.values.reserve(static_cast<std::size_t>(n_file) * f.info.ncomp);
  for (int i = 0; i < n_file; ++i) {
    const int v = i < static_cast<int>(l.report.vertex_map.size()) ? l.report.vertex_map[i] : -1;
    const SymTensor3 T = v >= 0 ? M[v] : isotropic_metric(fallback_h > 0 ? fallback_h : 1.0);  // dropped vertex
    f.values.insert(f.values.end(), T.m.begin(), T.m.begin() + f.info.ncomp);
  }
  write_sol(out, {f}, n_file, planar ? 2 : 3);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const auto [hmin_out, hmax_out] = size_range(mesh, M);
  std::printf("metric      %s\n", what.c_str());
  std::printf("vertices    %d\n", mesh.n_vertices());
  std::printf("sizes       %.6g .. %.6g\n", hmin_out, hmax_out);
  // build_metric measured the field it returns.
  std::printf("complexity  %.6g  (predicted vertices %.0f)\n", built.complexity, built.predicted_vertices);
  if (!std::isnan(hgrad))
    std::printf("gradation   ratio %g (%s space): %lld updates at %d vertices, %s\n", grad.ratio,
                grad.space == GradationSpace::Metric ? "metric" : "physical", gr.updates, gr.vertices_changed,
                gr.converged ? "converged" : "NOT converged");
  std::printf("written     %s (%.3f s)\n", out.c_str(), seconds);
  return 0;
}

}  // namespace

Command metric_command() {
  return {"metric", "build a metric field (size, tensor, Hessian of f, curvature, .sol) with bounds and gradation",
          kMetricHelp, run_metric};
}

Command quality_command() {
  return {"quality", "measure a mesh against a metric: edge lengths, c_K (eq. 17), mean ratio", kQualityHelp,
          run_quality};
}

}  // namespace anisurf::cli
