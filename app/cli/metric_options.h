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

namespace anisurf::cli {

struct MetricSourceOptions {
  std::string size, tensor, hessian_of, sol;
  bool curvature = false;
  double error = std::numeric_limits<double>::quiet_NaN();
  double complexity = std::numeric_limits<double>::quiet_NaN();
  double vertices = std::numeric_limits<double>::quiet_NaN();
  double lp = std::numeric_limits<double>::infinity();  // --norm
  double error_constant = 2.0 / 9.0;
  MetricBounds bounds;
  int source_count() const {
    return !size.empty() + !tensor.empty() + !hessian_of.empty() + curvature + !sol.empty();
  }
  bool has_bounds() const {
    return std::isfinite(bounds.hmax) || bounds.hmin > 0 || std::isfinite(bounds.max_anisotropy);
  }
};

// Takes the source and bound options out of `p` (Mmg's single-dash
// spellings -sol -hmin -hmax accepted too). Throws UsageError on bad values;
// does not require a source (callers decide).
MetricSourceOptions parse_metric_options(ArgParser& p);

// The metric of the source on `mesh` (whose vertex numbering follows
// `report`), clamped to the bounds. `sol_metric`: the metric read from the
// --sol file (used for the --sol source). `hausd` > 0 is the chordal
// deviation of the --curvature source. `what` receives a description.
MetricField build_metric(const SurfaceMesh& mesh, const BuildReport& report, MetricField sol_metric,
                         const MetricSourceOptions& o, double hausd, std::string* what);

}  // namespace anisurf::cli
