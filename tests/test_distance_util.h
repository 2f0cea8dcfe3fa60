// The distance of an adapted mesh to its input, measured as
// ../shared/bench/surfdist.py measures it: at the output's vertices, edge
// midpoints and triangle centroids, to the input's triangles.
#pragma once
#include <algorithm>

#include "locate/locator.h"
#include "mesh/surface_mesh.h"

namespace anisurf::test {

// Largest distance from the vertices, edge midpoints and triangle centroids
// of `out` to the triangles of `in`.
inline double max_distance_to_input(const SurfaceMesh& out, const SurfaceMesh& in) {
  Locator locator(in);
  double worst = 0;
  auto at = [&](const Vec3& x) { worst = std::max(worst, locator.project(x).distance); };
  for (Vertex v : out.vertices()) at(out.position(v));
  for (Corner c : out.edges()) at(0.5 * (out.position(out.edge_from(c)) + out.position(out.edge_to(c))));
  for (Triangle t : out.triangles())
    at((out.position(out.vertex(t, 0)) + out.position(out.vertex(t, 1)) + out.position(out.vertex(t, 2))) / 3.0);
  return worst;
}

}  // namespace anisurf::test
