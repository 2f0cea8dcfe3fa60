// anisurf.adapt: remesh::adapt on numpy arrays, the GIL released while the
// engine runs.
#include "bindings.h"

#include <pybind11/stl.h>

#include <cmath>

#include "arrays.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "mesh_object.h"
#include "metric/mesh_quality.h"
#include "options.h"
#include "remesh/adapt.h"

namespace anisurf::python {

namespace {

// The field that carries a `metric` array through build_mesh's renumbering.
const char* const kMetricField = "anisurf:metric";

struct Result : Mesh {
  py::object metric;  // (N, 6) at the output vertices
  py::list reports;   // one dict per cycle, with its passes
  py::dict quality;
  py::dict lengths;
  bool fixed_point = false;
  std::string surface;
  double protection_hausd = 0;
  double size_protection = 0;
  double seconds = 0;
};

// Everything the engine returns, gathered without the GIL.
struct EngineRun {
  remesh::AdaptResult result;
  MeshData output;
  MeshQuality measured;
};

// The state of T_1 a PassReport records (sizes, lengths, quality).
py::dict state_dict(const remesh::PassReport& r) {
  py::dict d;
  d["vertices"] = r.vertices;
  d["triangles"] = r.triangles;
  d["measured"] = r.measured;
  if (!r.measured) return d;
  d["edges"] = r.edges;
  d["in_band_pct"] = 100.0 * r.in_band_share;
  d["length_min"] = r.length_min;
  d["length_max"] = r.length_max;
  d["q_min"] = r.q_min;
  d["q_mean"] = r.q_mean;
  d["histogram"] = py::list(py::cast(std::vector<int>(r.histogram.begin(), r.histogram.end())));
  return d;
}

py::dict pass_dict(const remesh::PassReport& r) {
  py::dict d = state_dict(r);
  d["pass"] = std::string(remesh::pass_name(r.kind));
  d["round"] = r.round;
  d["splits"] = r.splits;
  d["collapses"] = r.collapses;
  d["swaps"] = r.swaps;
  d["moves"] = r.moves;
  d["removed_vertices"] = r.removed_vertices;
  d["bound_splits"] = r.bound_splits;
  d["beyond_bound"] = r.beyond_bound;
  d["crease_splits"] = r.crease_splits;
  d["seconds"] = r.seconds;
  d["region"] = r.region;  // threads: the region the pass ran on (the band last); -1: the whole mesh
  return d;
}

py::dict cycle_dict(const remesh::CycleReport& c) {
  py::dict d = state_dict(c.final);
  d["cycle"] = c.cycle;
  d["metric"] = c.metric;
  d["complexity"] = c.complexity;
  d["predicted_vertices"] = c.predicted_vertices;
  d["inverted_before"] = c.inverted_before;
  d["inverted_after"] = c.inverted_after;
  d["error_estimate"] = std::isnan(c.error_estimate) ? py::object(py::none()) : py::object(py::float_(c.error_estimate));
  d["setup_seconds"] = c.setup_seconds;
  d["remesh_seconds"] = c.remesh_seconds;
  d["initial"] = state_dict(c.initial);
  py::list passes;
  for (const remesh::PassReport& p : c.passes) passes.append(pass_dict(p));
  d["passes"] = passes;
  return d;
}

py::dict quality_dict(const MeshQuality& q, int inverted) {
  py::dict d;
  d["q_min"] = q.q_min;
  d["q_mean"] = q.q_mean;
  d["qc_min"] = q.qc_min;
  d["qc_mean"] = q.qc_mean;
  d["mean_ratio_min"] = q.mean_ratio_min;
  d["mean_ratio_mean"] = q.mean_ratio_mean;
  d["inverted"] = inverted;
  d["complexity"] = q.complexity;
  d["predicted_vertices"] = q.predicted_vertices;
  return d;
}

py::dict lengths_dict(const MeshQuality& q) {
  py::dict d;
  d["edges"] = q.edges;
  d["min"] = q.length_min;
  d["mean"] = q.length_mean;
  d["max"] = q.length_max;
  d["in_band_pct"] = 100.0 * q.in_band_share;
  d["histogram"] = py::cast(std::vector<int>(q.histogram.begin(), q.histogram.end()));
  d["bins"] = py::cast(std::vector<double>(kLengthBins.begin(), kLengthBins.end()));
  return d;
}

// Builds T_0 (and T_G), reads a given metric through the build's
// renumbering, adapts and measures; no Python object is touched.
EngineRun run_engine(const MeshData& data, const MeshData* geometry_data, const BuildOptions& build,
                     remesh::AdaptOptions options, bool given_metric) {
  remesh::AdaptInput input;
  const BuildReport report = build_mesh(data, input.mesh, build, "adapt() arrays");
  input.vertex_origin = report.vertex_origin;
  if (given_metric) {
    options.metric.given = metric_from_field(input.mesh, kMetricField, report.vertex_origin);
    input.mesh.remove_field(kMetricField);
  }
  SurfaceMesh geometry;
  if (geometry_data) {
    build_mesh(*geometry_data, geometry, build, "adapt() geometry");
    input.geometry = &geometry;
  }
  MeshQualityOptions measure;
  measure.length = options.length;
  EngineRun run;
  run.result = remesh::adapt(std::move(input), std::move(options));
  run.output = to_mesh_data(run.result.mesh);
  run.measured = measure_mesh_quality(run.result.mesh, run.result.metric, measure);
  return run;
}

Result result_from(EngineRun run) {
  Result r;
  const int inverted = run.result.cycles.empty() ? 0 : run.result.cycles.back().inverted_after;
  fill_mesh(r, std::move(run.output));
  // The metric by slot, as the output's vertices (compact, in slot order).
  const SurfaceMesh& t1 = run.result.mesh;
  if (t1.has_garbage()) {
    MetricField live;
    for (Vertex v : t1.vertices()) live.push_back(run.result.metric[v.idx]);
    run.result.metric = std::move(live);
  }
  r.metric = tensors_array(std::move(run.result.metric));
  for (const remesh::CycleReport& c : run.result.cycles) r.reports.append(cycle_dict(c));
  r.quality = quality_dict(run.measured, inverted);
  r.lengths = lengths_dict(run.measured);
  r.fixed_point = run.result.fixed_point;
  r.surface = run.result.surface;
  r.protection_hausd = run.result.protection_hausd;
  r.size_protection = run.result.size_protection;
  r.seconds = run.result.seconds;
  return r;
}

Result adapt(py::object vertices, py::object triangles, const py::kwargs& kwargs) {
  static const std::vector<std::string> data_keywords = {"fields", "refs", "geometry"};
  Keywords k(kwargs, "adapt", {&data_keywords, &kSourceKeywords, &kTuningKeywords, &kRemeshKeywords});
  const py::object fields = k.take("fields");
  const py::object refs = k.take("refs");
  const py::object geometry = k.take("geometry");
  const bool hausd_given = k.has("hausd");
  MetricSource source = metric_source_from(k, 1.3);
  remesh::AdaptOptions options;
  adapt_options_from(k, options);
  if (hausd_given && !(source.recipe.hausd > 0)) options.protect_fraction = 0;  // hausd=0: no geometry protection
  const BuildOptions build = build_options_from(k);
  k.finish();

  MeshData data = data_from_arguments(vertices, triangles, fields, "adapt");
  if (!refs.is_none()) {
    if (py::isinstance<Mesh>(vertices)) throw py::type_error("adapt(): refs go with arrays; a Mesh has its own");
    data.triangle_refs = ints_from(refs, static_cast<long long>(data.triangles.size()), -1, "refs");
  }
  for (const FieldData& f : data.fields)
    if (f.info.name == kMetricField) throw py::value_error(std::string("adapt(): the field name ") + kMetricField + " is reserved");
  const bool given_metric = !source.metric_array.is_none();
  if (given_metric) data.fields.push_back(metric_field_from(kMetricField, source.metric_array, data.vertices.size()));
  MeshData geometry_data;
  if (!geometry.is_none()) {
    if (py::isinstance<py::tuple>(geometry) && py::len(geometry) == 2)
      geometry_data = data_from_arrays(geometry.cast<py::tuple>()[0], geometry.cast<py::tuple>()[1], py::none());
    else if (py::isinstance<Mesh>(geometry))
      geometry_data = data_from_mesh(geometry.cast<const Mesh&>());
    else
      throw py::type_error("adapt(): geometry expects a Mesh or a (vertices, triangles) tuple");
  }
  options.metric = std::move(source.recipe);

  EngineRun run;
  {
    py::gil_scoped_release release;
    run = run_engine(data, geometry.is_none() ? nullptr : &geometry_data, build, std::move(options), given_metric);
  }
  return result_from(std::move(run));
}

const char* kAdaptDoc = R"doc(
adapt(vertices, triangles=None, **options) -> Result

Adapts a surface mesh to a metric with the engine's pipeline (the same as
`anisurf adapt`: every keyword is the command line's flag with `_` for `-`
and the same default). `vertices` (N, 3) float64 and `triangles` (M, 3)
integers, or a Mesh (from load() or a previous Result) with triangles
omitted. The GIL is released while the engine runs.

Metric source (one; none with hausd: the curvature metric of hausd):
  metric=      (N, 6) tensors (m11 m12 m22 m13 m23 m33), (N, 3, 3) symmetric
               matrices or (N,) isotropic sizes, on the input vertices (-sol)
  size=        a number (isotropic size) or an expression h(x, y, z) (--size)
  tensor=      'm11, m12, m22, m13, m23, m33' expressions (--tensor)
  hessian_of=  expression of x, y, z whose Hessian drives the metric (--hessian-of)
  hessian_of_field=  name of a scalar field of `fields` (--hessian-of-field)
  curvature=True     principal curvatures for hausd (--curvature)
Hessian target (one): error=, complexity=, target_vertices= (--vertices);
  norm=2 (a number >= 1 or 'inf'), error_constant=2/9.
Bounds: hmin=0, hmax=inf, max_aniso=inf. hausd= chordal deviation
  (intersected with the curvature metric; new vertices stay within hausd/5;
  edge midpoints and centroids farther are split onto the input). Without
  hausd, a metric=, tensor= or Hessian source gets hausd = diagonal / 1000
  (geometry protection: Result.protection_hausd); size= or iso= has its
  midpoints and centroids farther than 0.1 x the size split onto the input
  (Result.size_protection); hausd=0: none.
  hgrad=1.3 (-1: off), hgrad_space='metric' | 'physical'.
Remeshing: lmin=0.72, lmax=1.4, ridge_angle=45 (--ar), detect_ridges=True
  (False: --nr), curve_turn=25, curve_sag=0.1, crease_keep=0.6, repair_quality=0.8, relocate_quality=0.9, strip_width=0.5, free_surface=False, rounds=30,
  relax=0, cycles=1, fixed_point=0.02, max_memory=0 (MB), length='linear' |
  'log', interpolation='size' | 'linear' | 'inverse' | 'log', surface='auto'
  (g1, or polyhedral for a coarsening whose G1 surface lies within 0.05 h
  of the facets) | 'g1' |
  'g1-closest' | 'polyhedral', weld=None (merge vertices within weld x the
  bounding-box diagonal), geometry=None (a Mesh or (vertices, triangles): the
  surface to project onto), measure_every_pass=False (report every pass's
  state, not only each round's last), threads=0 (all cores: regions remeshed
  at once, then the band around their borders; the output depends on the
  count; 1: serial).
Data: fields= dict name -> (N,), (N, 3) or (N, 6) arrays, interpolated onto
  the output (section 6); refs= (M,) triangle references.

Result: a Mesh (vertices, triangles, refs, fields interpolated ...) with
  metric (N, 6) at the output vertices; reports: one dict per cycle (cycle,
  metric, vertices, triangles, in_band_pct, q_min, q_mean, predicted_vertices,
  error_estimate, inverted_after, initial, passes: one dict per pass);
  quality: dict (q_min, q_mean of eq. 17, qc_*, mean_ratio_*, inverted,
  complexity, predicted_vertices); lengths: dict (min, mean, max,
  in_band_pct, histogram over bins); fixed_point, surface, protection_hausd,
  size_protection (size= / iso=: edge midpoints and centroids farther from
  the input than this fraction of the size were split onto it), seconds.
An unknown keyword raises TypeError; bad arrays ValueError; the engine's
refusals anisurf.Error subclasses (MetricError, ExpressionError,
TopologyError: also ValueError; IoError: also OSError) with its message.)doc";

}  // namespace

void bind_adapt(py::module_& m) {
  py::class_<Result, Mesh>(m, "Result", "The adapted mesh of adapt(): a Mesh with metric, reports, quality, lengths.")
      .def_readonly("metric", &Result::metric)
      .def_readonly("reports", &Result::reports)
      .def_readonly("quality", &Result::quality)
      .def_readonly("lengths", &Result::lengths)
      .def_readonly("fixed_point", &Result::fixed_point)
      .def_readonly("surface", &Result::surface)
      .def_readonly("protection_hausd", &Result::protection_hausd)
      .def_readonly("size_protection", &Result::size_protection)
      .def_readonly("seconds", &Result::seconds);
  m.def("adapt", &adapt, py::arg("vertices"), py::arg("triangles") = py::none(), kAdaptDoc);
}

}  // namespace anisurf::python
