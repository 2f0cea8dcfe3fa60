// Level of detail for large surfaces: a decimated proxy drawn while the
// camera moves. Vertex clustering: the vertices falling into one cell of a
// uniform grid and facing the same way (the nearest of the six axis
// directions to their normal) merge into one (their mean, which stays inside
// the cell);
// triangles whose corners land in fewer than three cells vanish, and
// triangles landing on the same three cells are kept once. The proxy keeps,
// per triangle and per vertex, one element of the full mesh it stands for, so
// that colour quantities can be read through it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/scene.h"

namespace anisurf::render {

struct ProxyMesh {
  TriangleSet geometry;                       // corner normals: the cluster's area-weighted normal
  std::vector<std::uint32_t> source_triangle;  // per proxy triangle: a full triangle that made it
  std::vector<std::uint32_t> source_vertex;    // per proxy vertex: a full vertex of its cell
  float cell_size = 0;                         // edge of the grid's cubic cells
};

// Clusters the vertices of `full` into cubic cells of edge `cell_size` (> 0).
ProxyMesh cluster_vertices(const TriangleSet& full, float cell_size);

// A proxy with at most `max_triangles` triangles: the cell size starts from
// the surface's area (about max_triangles / 2 cells on it) and grows until the
// clustered mesh fits.
ProxyMesh make_proxy(const TriangleSet& full, std::size_t max_triangles);

// The structure drawn in place of `full` while the camera moves: the proxy's
// geometry, and the quantities of `full` read through the proxy's sources
// (vertex values of the source vertex, triangle and edge values, labels and
// corner categories of the source triangle; highlighted when the source is).
// Curves, markers and glyphs are not copied (the renderer draws the full
// structure's).
SurfaceStructure proxy_structure(const SurfaceStructure& full, const ProxyMesh& proxy);

}  // namespace anisurf::render
