// A finer mesh sampled on the smooth surface: every triangle split into k^2
// (report section 3.1: "subdividing each triangle into 4, 9, 16, ...").
#pragma once
#include "geometry/bezier_surface.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

// Splits each triangle of `mesh` into k^2 triangles (k >= 1) whose vertices
// lie on `surface` (built over the same mesh). Points on a mesh edge are
// shared by both triangles. Kept: the sub-edges of a tagged or referenced
// edge carry its tags and reference (feature edges stay feature edges), new
// vertices on such an edge take its reference and its kRidge / kRequired
// tags, the original vertices keep their tags and references, triangles keep
// their reference and tags. Fields and other vertex properties are not
// carried over. Throws Error for k < 1.
SurfaceMesh sample_surface(const SurfaceMesh& mesh, const BezierSurface& surface, int k);

}  // namespace anisurf
