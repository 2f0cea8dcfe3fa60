#include "cli/metric_options.h"

#include <cmath>

#include "metric/surface_metric.h"

namespace anisurf::cli {

MetricSourceOptions parse_metric_options(ArgParser& p) {
  MetricSourceOptions o;
  o.size = p.option("--size");
  o.tensor = p.option("--tensor");
  o.hessian_of = p.option("--hessian-of");
  o.hessian_of_field = p.option("--hessian-of-field");
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
  const bool hessian = !o.hessian_of.empty() || !o.hessian_of_field.empty();
  if (hessian && (!std::isnan(o.error) + !std::isnan(o.complexity) + !std::isnan(o.vertices)) != 1)
    throw UsageError{"--hessian-of needs exactly one of --error EPS, --complexity C, --vertices N"};
  if (!hessian && (!std::isnan(o.error) || !std::isnan(o.complexity) || !std::isnan(o.vertices)))
    throw UsageError{"--error, --complexity and --vertices go with --hessian-of or --hessian-of-field"};
  if (o.bounds.hmin < 0 || !(o.bounds.hmax > 0) || o.bounds.hmin > o.bounds.hmax || !(o.bounds.max_anisotropy >= 1))
    throw UsageError{"bounds: need 0 <= hmin <= hmax and --max-aniso >= 1"};
  if (norm_p == "inf") o.lp = std::numeric_limits<double>::infinity();
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

MetricRecipe metric_recipe(const MetricSourceOptions& o, MetricField sol_metric, double hausd, double hgrad) {
  using S = MetricRecipe::Source;
  MetricRecipe r;
  if (!o.size.empty()) {
    r.source = S::Size;
    r.expression = o.size;
  } else if (!o.tensor.empty()) {
    r.source = S::Tensor;
    r.expression = o.tensor;
  } else if (!o.hessian_of.empty()) {
    r.source = S::Hessian;
    r.expression = o.hessian_of;
  } else if (!o.hessian_of_field.empty()) {
    r.source = S::HessianField;
    r.field = o.hessian_of_field;
  } else if (o.curvature) {
    r.source = S::Curvature;
  } else {
    r.source = S::Given;
    r.given = std::move(sol_metric);
  }
  if (r.is_hessian()) {
    if (!std::isnan(o.error)) r.error = o.error;
    if (!std::isnan(o.complexity)) r.complexity = o.complexity;
    if (!std::isnan(o.vertices)) r.vertices = o.vertices;
    if (!(r.error > 0) && !(r.complexity > 0) && !(r.vertices > 0))
      throw UsageError{"the error, the complexity or the vertex count must be > 0"};
  }
  r.lp = o.lp;
  r.error_constant = o.error_constant;
  r.bounds = o.bounds;
  r.hausd = hausd > 0 ? hausd : 0;
  r.hgrad = hgrad > 1 ? hgrad : 0;
  return r;
}

}  // namespace anisurf::cli
