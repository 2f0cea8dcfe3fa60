// anisurf.metric.*: the engine's metric recipes (metric/recipe.h) on numpy
// arrays, as `anisurf metric` builds them; anisurf.quality: eq. 17 and the
// edge lengths in a metric.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "arrays.h"
#include "bindings.h"
#include "geometry/features.h"
#include "mesh/build.h"
#include "mesh_object.h"
#include "metric/quality.h"
#include "metric/recipe.h"
#include "options.h"

namespace anisurf::python {

namespace {

// The field a `values` array becomes for the HessianField source.
const char* const kValuesField = "values";

// The recipe's metric on the mesh of (vertices, triangles), one row per
// input vertex (a vertex no triangle uses: NaN).
py::array_t<double> metric_on_arrays(py::handle vertices, py::handle triangles, MetricRecipe recipe,
                                     py::handle values) {
  MeshData data = data_from_arrays(vertices, triangles, py::none());
  if (!values.is_none()) {
    FieldData f;
    f.info = FieldInfo{kValuesField, FieldKind::Scalar, 1};
    f.values = doubles_from(values, data.vertices.size(), "values");
    data.fields.push_back(std::move(f));
  }
  const std::size_t n = data.vertices.size();
  std::vector<SymTensor3> out(n);
  {
    py::gil_scoped_release release;
    SurfaceMesh mesh;
    const BuildReport report = build_mesh(data, mesh, {}, "metric arrays");
    // The curvature metric is fitted per smooth sector between the feature
    // curves: tag them as adapt does.
    if (recipe.source == MetricRecipe::Source::Curvature || recipe.hausd > 0) detect_features(mesh);
    const MetricResult built = build_metric(mesh, std::move(recipe), report.vertex_origin);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < n; ++i) {
      const int v = report.vertex_map[i];
      out[i] = v >= 0 ? built.metric[static_cast<std::size_t>(v)] : SymTensor3(nan, nan, nan, nan, nan, nan);
    }
  }
  return tensors_array(std::move(out));
}

// A builder: `source` set on the recipe, the other keywords read as tuning.
py::array_t<double> build(py::handle vertices, py::handle triangles, const char* function, const py::kwargs& kwargs,
                          MetricRecipe recipe, py::handle values = py::none()) {
  Keywords k(kwargs, function, {&kTuningKeywords});
  metric_tuning_from(k, recipe, 0);
  k.finish();
  return metric_on_arrays(vertices, triangles, std::move(recipe), values);
}

MetricRecipe source_recipe(MetricRecipe::Source source, const std::string& expression = {}) {
  MetricRecipe r;
  r.source = source;
  r.expression = expression;
  return r;
}

py::array_t<double> iso(py::handle vertices, py::handle triangles, py::object size, const py::kwargs& kwargs) {
  if (py::isinstance<py::str>(size))
    return build(vertices, triangles, "iso", kwargs, source_recipe(MetricRecipe::Source::Size, size.cast<std::string>()));
  MetricRecipe r = source_recipe(MetricRecipe::Source::Iso);
  r.iso = size.cast<double>();
  return build(vertices, triangles, "iso", kwargs, std::move(r));
}

py::array_t<double> tensor(py::handle vertices, py::handle triangles, const std::string& expression,
                           const py::kwargs& kwargs) {
  return build(vertices, triangles, "tensor", kwargs, source_recipe(MetricRecipe::Source::Tensor, expression));
}

py::array_t<double> hessian(py::handle vertices, py::handle triangles, py::handle values, const py::kwargs& kwargs) {
  MetricRecipe r = source_recipe(MetricRecipe::Source::HessianField);
  r.field = kValuesField;
  return build(vertices, triangles, "hessian", kwargs, std::move(r), values);
}

py::array_t<double> hessian_of(py::handle vertices, py::handle triangles, const std::string& expression,
                               const py::kwargs& kwargs) {
  return build(vertices, triangles, "hessian_of", kwargs, source_recipe(MetricRecipe::Source::Hessian, expression));
}

py::array_t<double> curvature(py::handle vertices, py::handle triangles, const py::kwargs& kwargs) {
  return build(vertices, triangles, "curvature", kwargs, source_recipe(MetricRecipe::Source::Curvature));
}

// anisurf.quality: eq. 17 per triangle and the length of every edge in the
// vertex metrics (eq. 6, or eq. 7 with length='log'), in the input's order.
py::dict quality(py::handle vertices, py::handle triangles, py::handle metric, const std::string& length) {
  if (length != "linear" && length != "log")
    throw py::value_error("quality(): length expects 'linear' or 'log', got '" + length + "'");
  const LengthFormula formula = length == "log" ? LengthFormula::LinearSize : LengthFormula::LinearMetric;
  const MeshData data = data_from_arrays(vertices, triangles, py::none());
  const std::vector<SymTensor3> M = tensors_from(metric, data.vertices.size(), "metric");
  for (std::size_t i = 0; i < M.size(); ++i) check_metric(M[i], static_cast<int>(i));
  std::vector<double> q(data.triangles.size()), lengths;
  std::vector<std::array<int, 2>> edges;
  {
    py::gil_scoped_release release;
    const auto& p = data.vertices;
    for (std::size_t t = 0; t < data.triangles.size(); ++t) {
      const auto& v = data.triangles[t];
      q[t] = triangle_quality({p[v[0]], p[v[1]], p[v[2]]}, {M[v[0]], M[v[1]], M[v[2]]}, formula);
      for (int k = 0; k < 3; ++k) edges.push_back({std::min(v[k], v[(k + 1) % 3]), std::max(v[k], v[(k + 1) % 3])});
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    lengths.reserve(edges.size());
    for (const auto& [a, b] : edges) lengths.push_back(edge_length(M[a], M[b], p[b] - p[a], formula));
  }
  py::dict d;
  const auto in_band = std::count_if(lengths.begin(), lengths.end(), [](double l) {
    return l >= kLengthBins[2] && l <= kLengthBins[5];
  });
  d["in_band_pct"] = lengths.empty() ? 0.0 : 100.0 * static_cast<double>(in_band) / static_cast<double>(lengths.size());
  d["quality"] = double_array(std::move(q));
  d["edges"] = edges_array(std::move(edges));
  d["lengths"] = double_array(std::move(lengths));
  return d;
}

const char* kTuningDoc = R"doc(
Keywords (as `anisurf metric`): hmin=0, hmax=inf, max_aniso=inf; hausd=
(intersected with the curvature metric of that chordal deviation); hgrad=
(gradation ratio > 1; off by default), hgrad_space='metric' | 'physical'.
Hessian sources: one of error=, complexity=, target_vertices=; norm=2 (>= 1
or 'inf'), error_constant=2/9.
Returns (N, 6) float64 tensors (m11 m12 m22 m13 m23 m33), one row per input
vertex (NaN rows for vertices no triangle uses).)doc";

std::string doc(const char* head) { return std::string(head) + kTuningDoc; }

}  // namespace

void bind_metric(py::module_& metric) {
  metric.doc() = "Metric builders on numpy arrays (the engine's recipes, as `anisurf metric`).";
  metric.def("iso", &iso, py::arg("vertices"), py::arg("triangles"), py::arg("size"),
             doc("iso(vertices, triangles, size, **keywords)\n\nIsotropic metric of a size: a number, or an "
                 "expression h(x, y, z) (--size).\n").c_str());
  metric.def("tensor", &tensor, py::arg("vertices"), py::arg("triangles"), py::arg("expression"),
             doc("tensor(vertices, triangles, expression, **keywords)\n\nMetric of six expressions "
                 "'m11, m12, m22, m13, m23, m33' (--tensor).\n").c_str());
  metric.def("hessian", &hessian, py::arg("vertices"), py::arg("triangles"), py::arg("values"),
             doc("hessian(vertices, triangles, values, error=..., **keywords)\n\nL^p-optimal metric of the "
                 "Hessian recovered from the (N,) vertex values of a field (--hessian-of-field).\n").c_str());
  metric.def("hessian_of", &hessian_of, py::arg("vertices"), py::arg("triangles"), py::arg("expression"),
             doc("hessian_of(vertices, triangles, expression, error=..., **keywords)\n\nL^p-optimal metric of "
                 "the Hessian of an expression f(x, y, z) (--hessian-of).\n").c_str());
  metric.def("curvature", &curvature, py::arg("vertices"), py::arg("triangles"),
             doc("curvature(vertices, triangles, hausd=..., **keywords)\n\nGeometric metric: sizes "
                 "sqrt(8 hausd / |kappa_i|) along the principal directions (--curvature).\n").c_str());
}

void bind_quality(py::module_& m) {
  m.def("quality", &quality, py::arg("vertices"), py::arg("triangles"), py::arg("metric"),
        py::arg("length") = "linear", R"doc(
quality(vertices, triangles, metric, length='linear') -> dict

Measures a mesh in a metric ((N, 6), (N, 3, 3) or (N,) sizes at its
vertices): 'quality' (M,) eq. 17 per triangle (1: equilateral in the metric,
0: degenerate), 'edges' (E, 2) every edge once (sorted), 'lengths' (E,) their
lengths in the metric (eq. 6; length='log': eq. 7), 'in_band_pct' the share
of edges with lengths in [1/sqrt2, sqrt2].)doc");
}

}  // namespace anisurf::python
