// The G1 Bezier surface of engine/geometry (report section 3) as a drawable
// structure: each mesh triangle sampled k x k (per-triangle vertices with the
// surface's own normals), the images of the mesh edges (patch boundaries),
// the Clough-Tocher control net (31 points per triangle), and the deviation
// between the mesh and the surface as a scalar quantity.
#pragma once
#include <optional>
#include <string>

#include "geometry/bezier_surface.h"
#include "mesh/surface_mesh.h"
#include "render/scene.h"

namespace anisurf::render {

namespace quantity {
// Vertex: |B_t(b) - (b0 v0 + b1 v1 + b2 v2)|, the distance from the flat
// triangle to the G1 surface at the same barycentric coordinates.
inline constexpr const char* kDeviation = "deviation";
}  // namespace quantity

struct BezierStructureOptions {
  int k = 4;                  // samples per triangle edge (k^2 sub-triangles)
  bool patch_edges = true;    // curves: the mesh edges mapped onto the surface
  bool control_net = false;   // curves + markers: the control net (enabled flag)
  // The control net of at most this many patches (0: every patch): about
  // 80 segments and 28 points each, a net of every patch of a large surface
  // is millions of lines. The patches nearest to net_centre (their
  // centroids), else every n-th patch.
  int net_max_patches = 0;
  std::optional<glm::vec3> net_centre;
};

// How many patches the control net shows, of how many.
struct BezierNetInfo {
  int shown = 0, patches = 0;
};

// Builds the structure named `name` for `surface` (built over `mesh`);
// `info` (optional) receives the patches of the control net. Throws Error for
// k < 1 or a surface built over another mesh.
SurfaceStructure make_bezier_structure(const SurfaceMesh& mesh, const BezierSurface& surface, const std::string& name,
                                       const BezierStructureOptions& options = {}, BezierNetInfo* info = nullptr);

// The edges of the control net of one triangle's 31 points: 3 quartic
// Clough-Tocher subtriangles, 30 segments each, shared segments once
// (pairs of indices into BezierSurface::Patch). Exposed for tests.
const std::vector<std::array<int, 2>>& control_net_edges();

}  // namespace anisurf::render
