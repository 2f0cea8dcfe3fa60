// The metric options shared by `anisurf metric` and `anisurf adapt`: one
// source (--size, --tensor, --hessian-of with --error/--complexity/--vertices,
// --curvature, --sol) and the bounds (--hmin, --hmax, --max-aniso), parsed
// once and turned into a metric field on a mesh the same way.
#pragma once
#include <limits>
#include <string>

#include "cli/cli.h"
#include "metric/metric.h"
#include "metric/metric_field.h"
#include "mesh/build.h"
#include "metric/recipe.h"

namespace anisurf::cli {

struct MetricSourceOptions {
  std::string size, tensor, hessian_of, hessian_of_field, sol;
  bool curvature = false;
  double error = std::numeric_limits<double>::quiet_NaN();
  double complexity = std::numeric_limits<double>::quiet_NaN();
  double vertices = std::numeric_limits<double>::quiet_NaN();
  double lp = 2;  // --norm (MetricRecipe's default)
  double error_constant = 2.0 / 9.0;
  MetricBounds bounds;
  int source_count() const {
    return !size.empty() + !tensor.empty() + !hessian_of.empty() + !hessian_of_field.empty() + curvature + !sol.empty();
  }
  bool has_bounds() const {
    return std::isfinite(bounds.hmax) || bounds.hmin > 0 || std::isfinite(bounds.max_anisotropy);
  }
};

// Takes the source and bound options out of `p` (Mmg's single-dash
// spellings -sol -hmin -hmax accepted too). Throws UsageError on bad values;
// does not require a source (callers decide).
MetricSourceOptions parse_metric_options(ArgParser& p);

// The engine's recipe (metric/recipe.h) for these options: `sol_metric` is
// the metric read from the --sol file (the Given source), `hausd` > 0 the
// chordal deviation (the Curvature source's, or intersected with the
// others'), `hgrad` > 1 the gradation ratio (else none).
MetricRecipe metric_recipe(const MetricSourceOptions& o, MetricField sol_metric, double hausd, double hgrad);

}  // namespace anisurf::cli
