// A metric field on a mesh: one SymTensor3 per vertex slot (indexed by
// Vertex::idx), read from the mesh's .sol fields, checked, graded, written
// back.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "metric/gradation.h"
#include "metric/metric.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

using MetricField = std::vector<SymTensor3>;

// The vertex metrics from a mesh field: a symmetric tensor (6 components in
// the .sol order, or 3 for a planar mesh: m11 m12 m22 with m33 = 1, as
// eval.py reads them) or a scalar size h (eq. 3). `name` empty: the first
// tensor field, else the first scalar field. Throws MetricError when there is
// no such field or when a metric is not finite / not SPD, naming the vertex
// (1-based file numbering through `vertex_origin` if given, see BuildReport).
MetricField metric_from_field(const SurfaceMesh& mesh, const std::string& name = {},
                              const std::vector<int>& vertex_origin = {});
// The field of a mesh read from a format with fields inside (.msh, .vtu ...)
// that is its metric: "metric" (the name anisurf writes), else the first
// tensor field; empty when there is none.
std::string embedded_metric_name(const SurfaceMesh& mesh);
// Throws MetricError naming the first vertex whose metric is not finite / SPD.
void check_metric_field(const SurfaceMesh& mesh, const MetricField& metric, const std::vector<int>& vertex_origin = {});
// Stores the metric as a 6-component tensor field `name` (replacing its values).
void set_metric_field(SurfaceMesh& mesh, const MetricField& metric, const std::string& name = "metric");

// Each edge of the mesh once (vertex indices), and the positions by slot.
std::vector<std::array<int, 2>> mesh_edges(const SurfaceMesh& mesh);
std::vector<Vec3> vertex_positions(const SurfaceMesh& mesh);

// Gradation along the edges of the mesh (see gradation.h).
GradationReport gradate_metric(const SurfaceMesh& mesh, MetricField& metric, const GradationOptions& options = {});
// clamp_metric at every live vertex.
void clamp_metric_field(const SurfaceMesh& mesh, MetricField& metric, const MetricBounds& bounds);

}  // namespace anisurf
