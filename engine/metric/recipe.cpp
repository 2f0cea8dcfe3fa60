#include "metric/recipe.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "geometry/parallel_chunks.h"
#include "metric/expression.h"
#include "metric/surface_metric.h"

namespace anisurf {

namespace {

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// The scalar field `name` of the mesh, one value per vertex slot.
std::vector<double> scalar_field_values(const SurfaceMesh& mesh, const std::string& name) {
  const FieldInfo* info = nullptr;
  for (const FieldInfo& f : mesh.fields())
    if (f.name == name) info = &f;
  if (!info) throw MetricError("no solution field named '" + name + "' on the mesh");
  if (info->kind != FieldKind::Scalar)
    throw MetricError("the solution field '" + name + "' is not scalar: its Hessian is not defined");
  const Property<FieldValue> p = mesh.get_field(name);
  std::vector<double> f(static_cast<std::size_t>(mesh.vertex_capacity()), 0.0);
  for (Vertex v : mesh.vertices()) f[v.idx] = p[v][0];
  return f;
}

// The metric of the source alone (Hessian sources: with `hessian_scale`
// times the recipe's target; the tangent Hessians in *hessian).
MetricField source_metric(const SurfaceMesh& mesh, MetricRecipe& r, const std::vector<int>& origin,
                          const std::vector<SymTensor3>& hessian, double target_vertices) {
  using S = MetricRecipe::Source;
  switch (r.source) {
    case S::Given:
      if (r.given.size() != static_cast<std::size_t>(mesh.vertex_capacity()))
        throw MetricError("the given metric has " + std::to_string(r.given.size()) + " values for " +
                          std::to_string(mesh.vertex_capacity()) + " vertex slots");
      return std::move(r.given);  // used once: only Hessian sources are rescaled
    case S::Iso:
      return MetricField(static_cast<std::size_t>(mesh.vertex_capacity()), isotropic_metric(r.iso));
    case S::Size:
      return metric_from_size_expression(mesh, r.expression, origin);
    case S::Tensor:
      return metric_from_tensor_expression(mesh, r.expression, origin);
    case S::Hessian:
    case S::HessianField: {
      HessianMetricOptions h;
      h.p = r.lp;
      h.error_constant = r.error_constant;
      h.bounds = r.bounds;
      if (target_vertices > 0)
        h.target_vertices = target_vertices;
      else
        h.error = r.error;
      return hessian_metric(mesh, hessian, h);
    }
    case S::Curvature:
      return curvature_metric(mesh, r.hausd, r.bounds);
  }
  return {};
}

std::string source_description(const MetricRecipe& r) {
  using S = MetricRecipe::Source;
  std::string w;
  switch (r.source) {
    case S::Given: w = "given"; break;
    case S::Iso: w = "iso " + number(r.iso); break;
    case S::Size: w = "size " + r.expression; break;
    case S::Tensor: w = "tensor " + r.expression; break;
    case S::Hessian: w = "Hessian of " + r.expression; break;
    case S::HessianField: w = "Hessian of the field " + r.field; break;
    case S::Curvature: w = "curvature, hausd " + number(r.hausd); break;
  }
  if (r.is_hessian()) {
    if (r.vertices > 0)
      w += ", " + number(r.vertices) + " vertices";
    else if (r.complexity > 0)
      w += ", complexity " + number(r.complexity);
    else
      w += ", error " + number(r.error);
    if (std::isfinite(r.lp)) w += " in L^" + number(r.lp);
  }
  return w;
}

bool has_bounds(const MetricBounds& b) {
  return std::isfinite(b.hmax) || b.hmin > 0 || std::isfinite(b.max_anisotropy);
}

// Bounds, hausd intersection and gradation applied to a source metric.
GradationReport finish_metric(const SurfaceMesh& mesh, const MetricRecipe& r, MetricField& M,
                              const MetricField& deviation_metric) {
  if (has_bounds(r.bounds)) clamp_metric_field(mesh, M, r.bounds);
  if (!deviation_metric.empty()) {
    const int n = mesh.vertex_capacity();
    run_chunks(n, chunk_count(n, 8192), [&](int, int begin, int end) {
      for (int i = begin; i < end; ++i)
        if (!mesh.is_deleted(Vertex(i))) M[i] = intersect(M[i], deviation_metric[i]);
    });
  }
  if (!(r.hgrad > 1)) return {};
  GradationOptions g;
  g.ratio = r.hgrad;
  g.space = r.hgrad_space;
  return gradate_metric(mesh, M, g);
}

}  // namespace

void check_recipe(const MetricRecipe& r) {
  using S = MetricRecipe::Source;
  if (r.bounds.hmin < 0 || !(r.bounds.hmax > 0) || r.bounds.hmin > r.bounds.hmax || !(r.bounds.max_anisotropy >= 1))
    throw MetricError("bounds: need 0 <= hmin <= hmax and a maximum anisotropy >= 1");
  if (r.source == S::Iso && !(r.iso > 0 && std::isfinite(r.iso)))
    throw MetricError("the isotropic size must be a finite number > 0");
  if ((r.source == S::Size || r.source == S::Tensor || r.source == S::Hessian) && r.expression.empty())
    throw MetricError("the metric source needs an expression");
  if (r.source == S::HessianField && r.field.empty()) throw MetricError("the Hessian source needs a field name");
  if (r.source == S::Curvature && !(r.hausd > 0 && std::isfinite(r.hausd)))
    throw MetricError("the curvature metric needs a chordal deviation hausd > 0");
  if (r.is_hessian()) {
    const int targets = (r.error > 0) + (r.complexity > 0) + (r.vertices > 0);
    if (targets != 1) throw MetricError("the Hessian metric needs exactly one target > 0: error, complexity or vertices");
    if (!(r.lp >= 1)) throw MetricError("the norm of the error needs p >= 1");
    if (!(r.error_constant > 0)) throw MetricError("the error constant must be > 0");
  }
  if (r.hausd < 0 || !std::isfinite(r.hausd)) throw MetricError("hausd must be a finite number >= 0");
  if (!std::isfinite(r.hgrad)) throw MetricError("the gradation ratio must be finite");
}

std::vector<SymTensor3> recipe_hessian(const SurfaceMesh& mesh, const MetricRecipe& r,
                                       const std::vector<int>& origin) {
  if (r.source == MetricRecipe::Source::Hessian) return hessian_of_expression(mesh, r.expression, origin);
  return recover_derivatives(mesh, scalar_field_values(mesh, r.field)).hessian;
}

MetricResult build_metric(const SurfaceMesh& mesh, MetricRecipe r, const std::vector<int>& origin) {
  check_recipe(r);
  MetricResult out;
  if (r.is_hessian()) out.hessian = recipe_hessian(mesh, r, origin);
  MetricField deviation;
  if (r.hausd > 0 && r.source != MetricRecipe::Source::Curvature) deviation = curvature_metric(mesh, r.hausd, r.bounds, r.deviation_fit);

  const double target = r.vertices > 0 ? r.vertices : r.complexity > 0 ? predicted_vertex_count(r.complexity) : 0;
  double asked = target;  // the vertex count asked of the Hessian metric
  for (int step = 0;; ++step) {
    MetricField M = source_metric(mesh, r, origin, out.hessian, asked);
    out.gradation = finish_metric(mesh, r, M, deviation);
    out.complexity = metric_complexity(mesh, M);
    const double predicted = predicted_vertices(mesh, M, out.complexity);
    out.metric = std::move(M);
    out.predicted_vertices = predicted;
    out.scaling_steps = step;
    if (!(target > 0) || std::abs(predicted - target) <= 0.01 * target || step >= 12 || !(predicted > 0)) break;
    // Bounds and gradation add (or remove) vertices the Hessian metric did
    // not count: ask again for the target scaled by what they changed.
    asked *= target / predicted;
  }
  check_metric_field(mesh, out.metric, origin);
  out.description = source_description(r);
  if (has_bounds(r.bounds)) out.description += ", bounded";
  if (!deviation.empty()) out.description += ", intersected with hausd " + number(r.hausd);
  if (r.hgrad > 1) out.description += ", graded " + number(r.hgrad);
  return out;
}

double estimated_interpolation_error(const SurfaceMesh& mesh, const std::vector<SymTensor3>& hessian, double lp) {
  double sum = 0, worst = 0;
  for (Triangle t : mesh.triangles()) {
    const int* v = mesh.triangle_vertices(t);
    SymTensor3 H{};
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 6; ++i) H.m[i] += hessian[v[k]].m[i] / 3.0;
    const Vec3 p[3] = {mesh.position(Vertex(v[0])), mesh.position(Vertex(v[1])), mesh.position(Vertex(v[2]))};
    double e = 0;
    for (int k = 0; k < 3; ++k) e = std::max(e, std::abs(quad(H, p[(k + 1) % 3] - p[k])) / 8.0);
    worst = std::max(worst, e);
    if (std::isfinite(lp)) sum += 0.5 * norm(cross(p[1] - p[0], p[2] - p[0])) * std::pow(e, lp);
  }
  return std::isfinite(lp) ? std::pow(sum, 1.0 / lp) : worst;
}

}  // namespace anisurf
