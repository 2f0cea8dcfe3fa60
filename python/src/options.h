// Keyword options of anisurf.adapt and anisurf.metric.* as the engine's
// structs, with the names, defaults and checks of the command line's flags
// (app/cli/cmd_adapt.cpp, app/cli/metric_options.cpp): `anisurf.adapt(...,
// size=0.05)` is `anisurf adapt ... --size 0.05`.
#pragma once
#include <pybind11/pybind11.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "mesh/build.h"
#include "metric/recipe.h"
#include "remesh/adapt.h"

namespace anisurf::python {

namespace py = pybind11;

// The keyword names of the metric tuning (metric_tuning_from), of the
// metric sources (metric_source_from) and of the remeshing
// (adapt_options_from, build_options_from).
extern const std::vector<std::string> kTuningKeywords, kSourceKeywords, kRemeshKeywords;

// The keyword arguments of one call, taken one by one. None stands for "not
// given". The constructor raises TypeError naming a keyword none of the
// `known` lists holds (before any other check, as Python does); finish()
// raises it for a keyword no one took.
class Keywords {
 public:
  Keywords(const py::kwargs& kwargs, std::string function, std::initializer_list<const std::vector<std::string>*> known);

  bool has(const char* name) const;
  py::object take(const char* name);  // None when absent
  double take_double(const char* name, double fallback);
  int take_int(const char* name, int fallback);
  bool take_bool(const char* name, bool fallback);
  std::string take_string(const char* name, const std::string& fallback);
  // Raises TypeError for the first keyword left.
  void finish() const;
  const std::string& function() const { return function_; }

 private:
  py::dict left_;
  std::string function_;
};

// Which metric source a call names, the array of a given metric aside.
struct MetricSource {
  MetricRecipe recipe;
  py::object metric_array = py::none();  // the `metric` keyword, when it is the source
};

// The recipe of the metric keywords: the source (metric, size, tensor,
// hessian_of, hessian_of_field, curvature; none: the curvature of hausd), the
// Hessian target (error, complexity, target_vertices; norm, error_constant),
// the bounds (hmin, hmax, max_aniso), hausd, hgrad (default_hgrad when
// absent; <= 1: none) and hgrad_space.
MetricSource metric_source_from(Keywords& k, double default_hgrad);
// Only the Hessian target, bounds, hausd and gradation keywords, on a recipe
// whose source is set (the anisurf.metric builders).
void metric_tuning_from(Keywords& k, MetricRecipe& recipe, double default_hgrad);

// The remeshing keywords (ridge_angle, detect_ridges, lmin, lmax, curve_turn,
// curve_sag, free_surface, rounds, relax, cycles, fixed_point, max_memory,
// length, interpolation, surface, measure_every_pass) on AdaptOptions.
void adapt_options_from(Keywords& k, remesh::AdaptOptions& options);
// The `weld` keyword (None: identical positions of split formats only).
BuildOptions build_options_from(Keywords& k);

}  // namespace anisurf::python
