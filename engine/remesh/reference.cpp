#include "remesh/reference.h"

#include "metric/surface_metric.h"

#include <cassert>
#include <cmath>

#include "geometry/normals.h"
#include "geometry/parallel_chunks.h"
#include "locate/interpolate.h"
#include "locate/surface_projection.h"
#include "mesh/operators.h"

namespace anisurf::remesh {

namespace {

Vec3 unit_triangle_normal(const SurfaceMesh& mesh, Triangle t) { return normalized(mesh.triangle_normal(t)); }

}  // namespace

PolyhedralSurface::PolyhedralSurface(const SurfaceMesh& mesh) : locator_(mesh) {}
PolyhedralSurface::PolyhedralSurface(Locator locator) : locator_(std::move(locator)) {}

Projection PolyhedralSurface::project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) {
  Projection p;
  p.location = locator_.project(x, hints, constraint);
  p.point = p.location.is_valid() ? p.location.point : x;
  p.normal = p.location.is_valid() ? unit_triangle_normal(locator_.mesh(), p.location.triangle) : Vec3();
  return p;
}

BezierGeometry::BezierGeometry(const SurfaceMesh& mesh, Mode mode) : BezierGeometry(mesh, mode, Locator(mesh)) {}

BezierGeometry::BezierGeometry(const SurfaceMesh& mesh, Mode mode, Locator locator)
    : BezierGeometry(std::make_shared<const BezierSurface>(mesh, compute_frames(mesh)), mode, std::move(locator)) {
  assert(&locator_.mesh() == &mesh);
}

BezierGeometry::BezierGeometry(std::shared_ptr<const BezierSurface> surface, Mode mode, Locator locator)
    : surface_(std::move(surface)),
      locator_(std::move(locator)),
      mode_(mode),
      deviation_(std::make_shared<std::vector<std::atomic<float>>>(static_cast<std::size_t>(surface_->size()))) {}

double BezierGeometry::deviation_bound(Triangle t) {
  if (mode_ != Mode::Parametric || !t.is_valid() || t.idx >= surface_->size()) return INFINITY;
  std::atomic<float>& slot = (*deviation_)[static_cast<std::size_t>(t.idx)];
  if (const float known = slot.load(std::memory_order_relaxed); known > 0) return known;
  const SurfaceMesh& g = mesh();
  const int* v = g.triangle_vertices(t);
  const double d =
      surface_->flat_deviation(t, {g.position(Vertex(v[0])), g.position(Vertex(v[1])), g.position(Vertex(v[2]))});
  if (!(d >= 0)) return INFINITY;
  const float up = std::nextafter(static_cast<float>(d), INFINITY);
  slot.store(up, std::memory_order_relaxed);
  return up;
}

Projection PolyhedralSurface::at(const Location& where) const {
  Projection p;
  p.location = where;
  p.point = where.point;
  p.normal = unit_triangle_normal(locator_.mesh(), where.triangle);
  return p;
}

Projection BezierGeometry::at(const Location& where) const {
  const SurfacePoint s = surface_->evaluate(where.triangle, where.bary);
  Projection p;
  p.location = where;
  p.point = s.position;
  p.normal = s.normal;
  return p;
}

SurfacePoint BezierGeometry::evaluate(Triangle t, const Bary& b) {
  const std::size_t slot = static_cast<std::size_t>(t.idx) % kCachedPatches;
  if (cached_id_plus_one_[slot] != t.idx + 1) {
    cached_patch_[slot] = surface_->patch(t);
    cached_id_plus_one_[slot] = t.idx + 1;
  }
  return BezierSurface::evaluate(cached_patch_[slot], b);
}

Projection BezierGeometry::project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) {
  // Closest point of the G1 surface: Gauss-Newton on the parameters from the
  // polyhedral projection (locate/surface_projection.h).
  const SurfaceEvaluator eval = [this](Triangle t, const std::array<double, 3>& b) {
    const SurfacePoint s = evaluate(t, b);
    return ParametricPoint{s.position, s.d1, s.d2};
  };
  Projection p;
  if (mode_ == Mode::Parametric) {
    p.location = locator_.project(x, hints, constraint);
    if (!p.location.is_valid()) {
      p.point = x;
      return p;
    }
    const SurfacePoint s = evaluate(p.location.triangle, p.location.bary);
    p.point = p.location.constraint == Constraint::Fixed ? p.location.point : s.position;
    p.normal = s.normal;
    return p;
  }
  const SurfaceProjection sp = project_onto_surface(locator_, eval, x, hints, constraint);
  p.location = sp.location;
  if (!p.location.is_valid()) {
    p.point = x;
    return p;
  }
  p.point = sp.point;
  p.normal = evaluate(p.location.triangle, p.location.bary).normal;
  return p;
}

ControlSpace::ControlSpace(const SurfaceMesh& mesh, MetricField metric, bool same_as_geometry,
                           MetricInterpolation interpolation, const std::string& metric_field_name,
                           double complexity)
    : mesh_(mesh), interpolation_(interpolation) {
  assert(static_cast<int>(metric.size()) >= mesh.vertex_capacity());
  complexity_ = std::isnan(complexity) ? metric_complexity(mesh, metric) : complexity;
  if (interpolation_ != MetricInterpolation::Linear) {
    const int n = static_cast<int>(metric.size());
    run_chunks(n, chunk_count(n, 16384), [&](int, int begin, int end) {
      for (int i = begin; i < end; ++i) metric[i] = to_interpolation_space(metric[i], interpolation_);
    });
  }
  target_ = std::make_shared<const MetricField>(std::move(metric));
  if (!same_as_geometry) locator_ = std::make_unique<Locator>(mesh);
  for (const FieldInfo& f : mesh.fields()) {
    if (f.name == metric_field_name) continue;
    infos_.push_back(f);
    fields_.push_back(mesh.get_field(f.name));
  }
}

void ControlSpace::set_relaxation(double t) {
  if (t >= 1) {
    MetricField().swap(relaxed_);
    return;
  }
  if (relaxed_.empty()) relaxed_.assign(target_->size(), SymTensor3::identity());
  if (implied_.empty()) {
    implied_.assign(target_->size(), SymTensor3::identity());
    for (Vertex v : mesh_.vertices()) {
      if (mesh_.is_isolated(v)) continue;
      double sum = 0;
      int n = 0;
      for (Vertex w : mesh_.ring_vertices(v)) {
        sum += norm(mesh_.position(w) - mesh_.position(v));
        ++n;
      }
      if (n > 0 && sum > 0) implied_[v.idx] = isotropic_metric(sum / n);
    }
  }
  for (Vertex v : mesh_.vertices()) {
    if (mesh_.is_isolated(v)) continue;
    const int i = v.idx;
    const SymTensor3 target = from_interpolation_space((*target_)[i], interpolation_);
    relaxed_[i] = to_interpolation_space(tensor_exp((1 - t) * tensor_log(implied_[i]) + t * tensor_log(target)),
                                         interpolation_);
  }
}

namespace {

MetricField from_space(const MetricField& X, MetricInterpolation how) {
  MetricField m(X.size());
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = from_interpolation_space(X[i], how);
  return m;
}

}  // namespace

MetricField ControlSpace::metric() const { return from_space(in_use(), interpolation_); }

MetricField ControlSpace::target_metric() const { return from_space(*target_, interpolation_); }

double ControlSpace::target_complexity() const { return complexity_; }

bool ControlSpace::is_isotropic() const {
  const MetricField& X = in_use();
  for (Vertex v : mesh_.vertices())
    if (static_cast<std::size_t>(v.idx) < X.size() && !anisurf::is_isotropic(X[static_cast<std::size_t>(v.idx)]))
      return false;
  return true;
}

ControlSpace::ControlSpace(const ControlSpace& o)
    : mesh_(o.mesh_),
      interpolation_(o.interpolation_),
      target_(o.target_),
      complexity_(o.complexity_),
      relaxed_(o.relaxed_),
      implied_(o.implied_),
      locator_(o.locator_ ? std::make_unique<Locator>(*o.locator_) : nullptr),
      infos_(o.infos_),
      fields_(o.fields_) {}

std::unique_ptr<ControlSpace> ControlSpace::copy_for_thread() const {
  return std::unique_ptr<ControlSpace>(new ControlSpace(*this));
}

Location ControlSpace::locate(const Vec3& x, Hint hint, const Location& on_geometry) {
  if (!locator_) return on_geometry;
  return locator_->project(x, hint, Constraint::Free);
}

SymTensor3 ControlSpace::metric_at(const Location& where) const {
  const Triangle t = where.triangle;
  const MetricField& X = in_use();
  const SymTensor3& X0 = X[mesh_.vertex(t, 0).idx];
  const SymTensor3& X1 = X[mesh_.vertex(t, 1).idx];
  const SymTensor3& X2 = X[mesh_.vertex(t, 2).idx];
  const std::array<double, 3>& w = where.bary;
  if (interpolation_ == MetricInterpolation::Linear) return w[0] * X0 + w[1] * X1 + w[2] * X2;
  SymTensor3 sum;
  sum += w[0] * X0;
  sum += w[1] * X1;
  sum += w[2] * X2;
  return from_interpolation_space(sum, interpolation_);
}

ControlValues ControlSpace::values_at(const Location& where) const {
  ControlValues out;
  out.metric = metric_at(where);
  out.fields.resize(fields_.size());
  for (std::size_t f = 0; f < fields_.size(); ++f) {
    out.fields[f] = interpolate(mesh_, where, fields_[f]);
  }
  return out;
}

}  // namespace anisurf::remesh
