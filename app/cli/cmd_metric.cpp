// `anisurf metric` (build a metric field) and `anisurf quality` (measure a
// mesh against one).
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "cli/cli.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "metric/mesh_quality.h"
#include "metric/metric_field.h"

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

struct LoadedMetric {
  SurfaceMesh mesh;
  BuildReport report;
  MetricField metric;
  bool scalar = false;  // the .sol held a size, not a tensor
};

LoadedMetric load_mesh_and_metric(const std::string& mesh_path, const std::string& sol_path) {
  LoadedMetric l;
  l.mesh = load_mesh(mesh_path, &l.report);
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

}  // namespace

Command quality_command() {
  return {"quality", "measure a mesh against a metric: edge lengths, c_K (eq. 17), mean ratio", kQualityHelp,
          run_quality};
}

}  // namespace anisurf::cli
