#include "options.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace anisurf::python {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

bool is_number(py::handle obj) {
  return !py::isinstance<py::bool_>(obj) && !py::isinstance<py::str>(obj) && !py::isinstance<py::array>(obj) &&
         PyNumber_Check(obj.ptr()) &&
         PyObject_HasAttrString(obj.ptr(), "__float__");
}

// The `norm` keyword: a number >= 1, inf, or the string "inf".
double norm_from(py::object value, const std::string& function) {
  if (value.is_none()) return cycle_metric_defaults().p;
  if (py::isinstance<py::str>(value) && value.cast<std::string>() == "inf") return std::numeric_limits<double>::infinity();
  if (!is_number(value)) throw py::type_error(function + "(): norm expects a number >= 1 or 'inf'");
  const double p = value.cast<double>();
  if (!(p >= 1)) throw py::value_error(function + "(): norm expects a number >= 1 or 'inf', got " + std::to_string(p));
  return p;
}

// hgrad as the command line reads it: a ratio > 1, or -1, 0, 1 for none.
double hgrad_from(Keywords& k, double fallback) {
  const double h = k.take_double("hgrad", fallback);
  if (!(h > 1) && h != -1 && h != 0 && h != 1)
    throw py::value_error(k.function() + "(): hgrad expects a ratio > 1, or -1 (off), got " + std::to_string(h));
  return h > 1 ? h : 0;
}

template <class Enum>
Enum choice(Keywords& k, const char* name, std::initializer_list<std::pair<const char*, Enum>> choices, Enum fallback) {
  const std::string value = k.take_string(name, "");
  if (value.empty()) return fallback;
  std::string names;
  for (const auto& [text, e] : choices) {
    if (value == text) return e;
    names += (names.empty() ? "" : ", ") + std::string(text);
  }
  throw py::value_error(k.function() + "(): " + name + " expects one of " + names + ", got '" + value + "'");
}

}  // namespace

const std::vector<std::string> kTuningKeywords = {"error", "complexity", "target_vertices", "norm",
                                                   "error_constant", "hmin", "hmax", "max_aniso",
                                                   "hausd", "hgrad", "hgrad_space"};
const std::vector<std::string> kSourceKeywords = {"metric", "size", "tensor", "hessian_of", "hessian_of_field",
                                                  "curvature"};
const std::vector<std::string> kRemeshKeywords = {
    "ridge_angle", "detect_ridges", "lmin", "lmax", "curve_turn", "curve_sag", "crease_keep", "repair_quality", "relocate_quality", "strip_width", "free_surface", "rounds", "relax",
    "cycles", "fixed_point", "max_memory", "max_growth", "measure_every_pass", "length", "interpolation", "surface", "weld",
    "threads"};

Keywords::Keywords(const py::kwargs& kwargs, std::string function,
                   std::initializer_list<const std::vector<std::string>*> known)
    : function_(std::move(function)) {
  for (auto item : kwargs) {
    const std::string name = py::str(item.first).cast<std::string>();
    bool found = false;
    for (const std::vector<std::string>* names : known)
      found = found || std::find(names->begin(), names->end(), name) != names->end();
    if (!found) throw py::type_error(function_ + "() got an unexpected keyword argument '" + name + "'");
    left_[item.first] = item.second;
  }
}

bool Keywords::has(const char* name) const {
  return left_.contains(name) && !left_[py::str(name)].is_none();
}

py::object Keywords::take(const char* name) {
  if (!left_.contains(name)) return py::none();
  py::object value = left_[py::str(name)];
  PyDict_DelItemString(left_.ptr(), name);
  return value;
}

double Keywords::take_double(const char* name, double fallback) {
  const py::object v = take(name);
  if (v.is_none()) return fallback;
  if (!is_number(v))
    throw py::type_error(function_ + "(): " + name + " expects a number, got " +
                         py::str(py::type::of(v).attr("__name__")).cast<std::string>());
  return v.cast<double>();
}

int Keywords::take_int(const char* name, int fallback) {
  const double x = take_double(name, fallback);
  if (x != std::floor(x) || std::fabs(x) > 1e6)
    throw py::value_error(function_ + "(): " + name + " expects an integer, got " + std::to_string(x));
  return static_cast<int>(x);
}

bool Keywords::take_bool(const char* name, bool fallback) {
  const py::object v = take(name);
  if (v.is_none()) return fallback;
  if (!py::isinstance<py::bool_>(v)) throw py::type_error(function_ + "(): " + name + " expects True or False");
  return v.cast<bool>();
}

std::string Keywords::take_string(const char* name, const std::string& fallback) {
  const py::object v = take(name);
  if (v.is_none()) return fallback;
  if (!py::isinstance<py::str>(v)) throw py::type_error(function_ + "(): " + name + " expects a string");
  return v.cast<std::string>();
}

void Keywords::finish() const {
  for (auto item : left_)
    throw py::type_error(function_ + "() got an unexpected keyword argument '" + py::str(item.first).cast<std::string>() +
                         "'");
}

void metric_tuning_from(Keywords& k, MetricRecipe& r, double default_hgrad) {
  const double error = k.take_double("error", kNan);
  const double complexity = k.take_double("complexity", kNan);
  const double vertices = k.take_double("target_vertices", kNan);
  const int targets = !std::isnan(error) + !std::isnan(complexity) + !std::isnan(vertices);
  if (r.is_hessian() && targets != 1)
    throw py::value_error(k.function() + "(): the Hessian metric needs exactly one of error, complexity, target_vertices");
  if (!r.is_hessian() && targets > 0)
    throw py::value_error(k.function() + "(): error, complexity and target_vertices go with a Hessian source");
  if (!std::isnan(error)) r.error = error;
  if (!std::isnan(complexity)) r.complexity = complexity;
  if (!std::isnan(vertices)) r.vertices = vertices;
  if (r.is_hessian() && !(r.error > 0) && !(r.complexity > 0) && !(r.vertices > 0))
    throw py::value_error(k.function() + "(): the error, the complexity or the vertex count must be > 0");
  r.lp = norm_from(k.take("norm"), k.function());
  r.error_constant = k.take_double("error_constant", 2.0 / 9.0);
  r.bounds.hmin = k.take_double("hmin", 0.0);
  r.bounds.hmax = k.take_double("hmax", std::numeric_limits<double>::infinity());
  r.bounds.max_anisotropy = k.take_double("max_aniso", std::numeric_limits<double>::infinity());
  if (r.bounds.hmin < 0 || !(r.bounds.hmax > 0) || r.bounds.hmin > r.bounds.hmax || !(r.bounds.max_anisotropy >= 1))
    throw py::value_error(k.function() + "(): bounds: need 0 <= hmin <= hmax and max_aniso >= 1");
  const double hausd = k.take_double("hausd", 0.0);
  if (r.source == MetricRecipe::Source::Curvature && !(hausd > 0))
    throw py::value_error(k.function() + "(): the curvature metric needs hausd > 0");
  r.hausd = hausd > 0 ? hausd : 0;
  r.hgrad = hgrad_from(k, default_hgrad);
  r.hgrad_space = choice(k, "hgrad_space", {{"metric", GradationSpace::Metric}, {"physical", GradationSpace::Physical}},
                         GradationSpace::Metric);
}

MetricSource metric_source_from(Keywords& k, double default_hgrad) {
  using S = MetricRecipe::Source;
  MetricSource out;
  MetricRecipe& r = out.recipe;
  const char* sources[] = {"metric", "size", "tensor", "hessian_of", "hessian_of_field", "curvature"};
  std::string given;
  int count = 0;
  for (const char* s : sources) {
    const bool named = std::string(s) == "curvature" ? k.has(s) && py::bool_(k.take("curvature")) : k.has(s);
    if (!named) continue;
    given += (count++ ? " and " : "") + std::string(s);
    if (std::string(s) == "curvature") r.source = S::Curvature;
  }
  if (count > 1)
    throw py::value_error(k.function() + "(): give one metric source (metric, size, tensor, hessian_of, "
                          "hessian_of_field or curvature), got " + given);
  if (k.has("metric")) {
    r.source = S::Given;
    out.metric_array = k.take("metric");
  } else if (k.has("size")) {
    const py::object size = k.take("size");
    if (py::isinstance<py::str>(size)) {
      r.source = S::Size;  // an expression h(x, y, z)
      r.expression = size.cast<std::string>();
    } else if (is_number(size)) {
      r.source = S::Iso;
      r.iso = size.cast<double>();
      if (!(r.iso > 0) || !std::isfinite(r.iso))
        throw py::value_error(k.function() + "(): size expects a finite number > 0 or an expression");
    } else {
      throw py::type_error(k.function() + "(): size expects a number or an expression string");
    }
  } else if (k.has("tensor")) {
    r.source = S::Tensor;
    r.expression = k.take_string("tensor", "");
  } else if (k.has("hessian_of")) {
    r.source = S::Hessian;
    r.expression = k.take_string("hessian_of", "");
  } else if (k.has("hessian_of_field")) {
    r.source = S::HessianField;
    r.field = k.take_string("hessian_of_field", "");
  } else if (count == 0) {
    // No source: the curvature metric of hausd (as `anisurf adapt --hausd D`).
    if (!k.has("hausd"))
      throw py::value_error(k.function() + "(): give a metric source (metric, size, tensor, hessian_of, "
                            "hessian_of_field, curvature) or hausd");
    r.source = S::Curvature;
  }
  for (const char* s : sources) k.take(s);  // None values of the others
  metric_tuning_from(k, r, default_hgrad);
  return out;
}

void adapt_options_from(Keywords& k, remesh::AdaptOptions& o) {
  o.features.ridge_angle_deg = k.take_double("ridge_angle", 45.0);
  o.features.detect_ridges = k.take_bool("detect_ridges", true);
  o.remesh.op.lmin = k.take_double("lmin", o.remesh.op.lmin);
  o.remesh.op.lmax = k.take_double("lmax", o.remesh.op.lmax);
  o.remesh.op.max_curve_turn_deg = k.take_double("curve_turn", o.remesh.op.max_curve_turn_deg);
  o.remesh.op.curve_sag = k.take_double("curve_sag", o.remesh.op.curve_sag);
  o.remesh.crease_keep = k.take_double("crease_keep", o.remesh.crease_keep);
  o.remesh.repair_quality = k.take_double("repair_quality", o.remesh.repair_quality);
  o.remesh.relocate_quality = k.take_double("relocate_quality", o.remesh.relocate_quality);
  o.remesh.op.strip_width = k.take_double("strip_width", o.remesh.op.strip_width);
  if (k.take_bool("free_surface", false)) o.input_bound.enabled = false;
  o.remesh.max_rounds = k.take_int("rounds", o.remesh.max_rounds);
  o.remesh.relaxation_stages = k.take_int("relax", 0);
  o.cycles = k.take_int("cycles", 1);
  o.fixed_point = k.take_double("fixed_point", o.fixed_point);
  const double max_memory_mb = k.take_double("max_memory", 0);
  if (!(max_memory_mb >= 0)) throw py::value_error(k.function() + "(): max_memory expects megabytes >= 0");
  o.memory_limit = max_memory_mb * 1e6;
  o.max_growth = k.take_double("max_growth", o.max_growth);
  if (!(o.max_growth >= 0) || !std::isfinite(o.max_growth))
    throw py::value_error(k.function() + "(): max_growth expects a factor >= 0 (0: no limit)");
  o.remesh.measure_every_pass = k.take_bool("measure_every_pass", false);
  o.threads = k.take_int("threads", 0);
  if (o.threads < 0 || o.threads > 1024) throw py::value_error(k.function() + "(): threads expects 0 (all cores) to 1024");
  if (!(o.remesh.op.lmin > 0) || !(o.remesh.op.lmax > o.remesh.op.lmin))
    throw py::value_error(k.function() + "(): need 0 < lmin < lmax");
  if (!(o.remesh.op.max_curve_turn_deg > 0) || !(o.remesh.op.curve_sag > 0))
    throw py::value_error(k.function() + "(): curve_turn and curve_sag expect numbers > 0");
  if (!(o.remesh.crease_keep >= 0) || !(o.remesh.crease_keep <= 1))
    throw py::value_error(k.function() + "(): crease_keep expects a share in [0, 1] (0: off)");
  if (!(o.remesh.repair_quality >= 0) || !(o.remesh.repair_quality <= 1))
    throw py::value_error(k.function() + "(): repair_quality expects a quality in [0, 1] (0: off)");
  if (!(o.remesh.relocate_quality >= 0) || !(o.remesh.relocate_quality <= 1))
    throw py::value_error(k.function() + "(): relocate_quality expects a quality in [0, 1] (0: off)");
  if (!(o.remesh.op.strip_width >= 0))
    throw py::value_error(k.function() + "(): strip_width expects a metric length >= 0 (0: off)");
  if (o.remesh.max_rounds < 1 || o.cycles < 1 || o.remesh.relaxation_stages < 0)
    throw py::value_error(k.function() + "(): need rounds >= 1, cycles >= 1 and relax >= 0");
  if (!(o.fixed_point >= 0)) throw py::value_error(k.function() + "(): fixed_point expects a share >= 0");
  o.length = choice(k, "length", {{"linear", LengthFormula::LinearMetric}, {"log", LengthFormula::LinearSize}},
                    o.length);
  o.interpolation = choice(k, "interpolation",
                           {{"size", MetricInterpolation::LinearSize},
                            {"linear", MetricInterpolation::Linear},
                            {"inverse", MetricInterpolation::Inverse},
                            {"log", MetricInterpolation::LogEuclidean}},
                           o.interpolation);
  o.surface = choice(k, "surface",
                     {{"auto", remesh::SurfaceKind::Auto},
                      {"g1", remesh::SurfaceKind::G1},
                      {"g1-closest", remesh::SurfaceKind::G1Closest},
                      {"polyhedral", remesh::SurfaceKind::Polyhedral}},
                     o.surface);
}

BuildOptions build_options_from(Keywords& k) {
  BuildOptions o;
  const double weld = k.take_double("weld", kNan);
  if (std::isnan(weld)) return o;
  if (!(weld >= 0 && weld < 0.1))
    throw py::value_error(k.function() + "(): weld expects a tolerance relative to the bounding box in [0, 0.1)");
  o.merge = BuildOptions::Merge::Always;
  o.merge_tolerance = weld;
  return o;
}

}  // namespace anisurf::python
