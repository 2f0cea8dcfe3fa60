// Distance from a surface mesh (an adapted T_1) to a reference surface mesh
// (the input T_G), sampled where ../shared/bench/surfdist.py samples it: at
// the vertices, at the edge midpoints and at the triangle centroids of the
// mesh. Each sample's distance is the exact distance to the closest point of
// the reference triangles (Locator::project: a local descent certified by the
// vertex clearances, or the tree search), not to the nearest reference
// vertex. The vertices are located first, each starting from the result of
// the neighbour that reached it (topological propagation); a midpoint or a
// centroid then starts from the results of its vertices, so most searches
// take a step or two.
#pragma once
#include <vector>

#include "core/vec3.h"
#include "locate/locator.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

// Maximum and mean over one kind of sample, and where the maximum is.
struct DistanceStats {
  int count = 0;           // samples measured
  double max = 0;          // largest distance (0 with no sample)
  double mean = 0;         // mean distance (0 with no sample)
  Vec3 worst;              // the sample point at the largest distance
  Vec3 worst_closest;      // its closest point on the reference
  int worst_element = -1;  // vertex slot, canonical corner of the edge, or triangle slot (-1: none)
};

// Which kind of sample a maximum belongs to.
enum class DistanceSample { Vertex, Midpoint, Centroid };
const char* distance_sample_name(DistanceSample s);  // "vertex", "edge midpoint", "triangle centroid"

struct SurfaceDistance {
  // Per vertex slot of the mesh: the distance to the reference (NaN for a
  // deleted slot). What the editor colours.
  std::vector<double> vertex;
  DistanceStats vertices, midpoints, centroids;
  double reference_diagonal = 0;  // bounding box diagonal of the reference

  // The largest of the three maxima and the kind of sample it comes from.
  double max() const;
  DistanceSample worst_sample() const;
  const DistanceStats& stats(DistanceSample s) const;
  // `d` as a percentage of the reference's bounding box diagonal (0 when the
  // diagonal is 0).
  double percent(double d) const { return reference_diagonal > 0 ? 100.0 * d / reference_diagonal : 0.0; }
};

struct SurfaceDistanceOptions {
  bool midpoints = true;  // measure the edge midpoints
  bool centroids = true;  // measure the triangle centroids
  int threads = 0;        // worker threads for the midpoints and centroids (0: the hardware's)
};

// A locator over `reference` for surface_distance(): its triangles only (the
// feature curves and corners, which a distance does not use, are not built).
Locator distance_locator(const SurfaceMesh& reference);

// Distance from `mesh` to the reference surface of `reference` (a locator
// over it; copied per thread, so it is not changed). The result does not
// depend on the number of threads. Throws Error when the reference has no
// triangle.
SurfaceDistance surface_distance(const SurfaceMesh& mesh, const Locator& reference,
                                 const SurfaceDistanceOptions& options = {});

// The same, building distance_locator(reference) first (its search
// structures: about as long as measuring a mesh of the same size).
SurfaceDistance surface_distance(const SurfaceMesh& mesh, const SurfaceMesh& reference,
                                 const SurfaceDistanceOptions& options = {});

}  // namespace anisurf
