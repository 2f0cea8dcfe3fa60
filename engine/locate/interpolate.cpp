#include "locate/interpolate.h"

#include <cassert>

#include "core/error.h"

namespace anisurf {

namespace {

template <class T, class Combine>
T combine3(const SurfaceMesh& mesh, const Location& loc, const Property<T>& f, Combine&& axpy) {
  assert(loc.is_valid() && f.is_valid());
  T out{};
  for (int k = 0; k < 3; ++k) axpy(out, loc.bary[k], f[mesh.vertex(loc.triangle, k)]);
  return out;
}

}  // namespace

double interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<double>& f) {
  return combine3(mesh, loc, f, [](double& out, double w, double v) { out += w * v; });
}

Vec3 interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<Vec3>& f) {
  return combine3(mesh, loc, f, [](Vec3& out, double w, const Vec3& v) { out += w * v; });
}

FieldValue interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<FieldValue>& f) {
  return combine3(mesh, loc, f, [](FieldValue& out, double w, const FieldValue& v) {
    for (std::size_t i = 0; i < out.size(); ++i) out[i] += w * v[i];
  });
}

FieldValue interpolate_field(const SurfaceMesh& mesh, const Location& loc, const std::string& name) {
  const Property<FieldValue> f = mesh.get_field(name);
  if (!f) throw Error("interpolation: the mesh has no field '" + name + "'");
  return interpolate(mesh, loc, f);
}

SymTensor3 interpolate_metric(const SurfaceMesh& mesh, const MetricField& metric, const Location& loc,
                              MetricInterpolation how) {
  assert(loc.is_valid());
  std::array<SymTensor3, 3> M;
  for (int k = 0; k < 3; ++k) M[k] = metric[static_cast<std::size_t>(mesh.vertex(loc.triangle, k).idx)];
  return interpolate_metric(M, loc.bary, how);
}

}  // namespace anisurf
