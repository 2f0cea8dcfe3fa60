#include "cli/metric_options.h"

#include <cmath>

#include "metric/expression.h"
#include "metric/hessian.h"
#include "metric/surface_metric.h"

namespace anisurf::cli {

MetricSourceOptions parse_metric_options(ArgParser& p) {
  MetricSourceOptions o;
  o.size = p.option("--size");
  o.tensor = p.option("--tensor");
  o.hessian_of = p.option("--hessian-of");
  o.sol = p.option("--sol", "-sol");
  o.curvature = p.flag("--curvature");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  o.error = p.option_double("--error", nan);
  o.complexity = p.option_double("--complexity", nan);
  o.vertices = p.option_double("--vertices", nan);
  const std::string norm_p = p.option("--norm");
  o.error_constant = p.option_double("--error-constant", 2.0 / 9.0);
  o.bounds.hmin = p.option_double("--hmin", nan);
  if (std::isnan(o.bounds.hmin)) o.bounds.hmin = p.option_double("-hmin", 0.0);
  o.bounds.hmax = p.option_double("--hmax", nan);
  if (std::isnan(o.bounds.hmax)) o.bounds.hmax = p.option_double("-hmax", std::numeric_limits<double>::infinity());
  o.bounds.max_anisotropy = p.option_double("--max-aniso", std::numeric_limits<double>::infinity());
  if (!o.hessian_of.empty() && (!std::isnan(o.error) + !std::isnan(o.complexity) + !std::isnan(o.vertices)) != 1)
    throw UsageError{"--hessian-of needs exactly one of --error EPS, --complexity C, --vertices N"};
  if (o.bounds.hmin < 0 || !(o.bounds.hmax > 0) || o.bounds.hmin > o.bounds.hmax || !(o.bounds.max_anisotropy >= 1))
    throw UsageError{"bounds: need 0 <= hmin <= hmax and --max-aniso >= 1"};
  if (!norm_p.empty() && norm_p != "inf") {
    try {
      o.lp = std::stod(norm_p);
    } catch (const std::exception&) {
      throw UsageError{"--norm expects a number >= 1 or inf"};
    }
    if (!(o.lp >= 1)) throw UsageError{"--norm expects a number >= 1 or inf"};
  }
  return o;
}

MetricField build_metric(const SurfaceMesh& mesh, const BuildReport& report, MetricField sol_metric,
                         const MetricSourceOptions& o, double hausd, std::string* what) {
  const std::vector<int>& origin = report.vertex_origin;
  MetricField M;
  std::string w;
  if (!o.size.empty()) {
    M = metric_from_size_expression(mesh, o.size, origin);
    w = "size " + o.size;
  } else if (!o.tensor.empty()) {
    M = metric_from_tensor_expression(mesh, o.tensor, origin);
    w = "tensor " + o.tensor;
  } else if (!o.hessian_of.empty()) {
    const RecoveredDerivatives d = recover_derivatives(mesh, evaluate_at_vertices(mesh, o.hessian_of, origin));
    HessianMetricOptions h;
    h.p = o.lp;
    h.error_constant = o.error_constant;
    h.bounds = o.bounds;
    if (!std::isnan(o.error)) h.error = o.error;
    if (!std::isnan(o.complexity)) h.target_vertices = predicted_vertex_count(o.complexity);
    if (!std::isnan(o.vertices)) h.target_vertices = o.vertices;
    if (!(h.error > 0) && !(h.target_vertices > 0)) throw UsageError{"the error or the complexity must be > 0"};
    M = hessian_metric(mesh, d.hessian, h);
    w = "Hessian of " + o.hessian_of;
  } else if (o.curvature) {
    M = curvature_metric(mesh, hausd, o.bounds);
    w = "curvature, hausd " + std::to_string(hausd);
  } else {
    M = std::move(sol_metric);
    w = "from " + o.sol;
  }
  if (o.has_bounds()) clamp_metric_field(mesh, M, o.bounds);
  if (what) *what = w;
  return M;
}

}  // namespace anisurf::cli
