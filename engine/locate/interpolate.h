// Values of vertex fields at a located point (report section 4: "the metric at
// a given point x"): linear interpolation in the triangle of a Location with
// its barycentric coordinates; metrics through the metric module's own
// interpolation laws.
#pragma once
#include <string>

#include "locate/location.h"
#include "mesh/properties.h"
#include "mesh/surface_mesh.h"
#include "metric/length.h"
#include "metric/metric_field.h"

namespace anisurf {

// sum_k bary[k] f(vertex(triangle, k)). Pre: loc.is_valid(), the property
// belongs to the mesh the location refers to.
double interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<double>& f);
Vec3 interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<Vec3>& f);
// Component-wise, all 6 components (a .sol field: scalar, vector or tensor).
FieldValue interpolate(const SurfaceMesh& mesh, const Location& loc, const Property<FieldValue>& f);
// The mesh field `name` (see SurfaceMesh::fields()); throws Error naming it
// when the mesh has no such field.
FieldValue interpolate_field(const SurfaceMesh& mesh, const Location& loc, const std::string& name);

// The metric at the located point from the vertex metrics (indexed by vertex
// slot), interpolated as `how` (section 2.2, Remark 2).
SymTensor3 interpolate_metric(const SurfaceMesh& mesh, const MetricField& metric, const Location& loc,
                              MetricInterpolation how);

}  // namespace anisurf
