// Topological and geometric summary of a mesh (what `anisurf info` prints).
#pragma once
#include "core/vec3.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

struct MeshStats {
  int vertices = 0;
  int triangles = 0;
  int edges = 0;
  int boundary_edges = 0;
  int boundary_loops = 0;
  int components = 0;
  int euler_characteristic = 0;  // V - E + F
  int ridge_edges = 0;
  int required_edges = 0;
  int listed_edges = 0;
  int corner_vertices = 0;
  int required_vertices = 0;
  int required_triangles = 0;
  int non_manifold_edges = 0;  // cut edges (tagged kNonManifold)
  int vertex_refs = 0;         // distinct non-zero vertex references
  int triangle_refs = 0;       // distinct non-zero triangle references
  int edge_refs = 0;           // distinct non-zero edge references
  BBox bbox;
  double area = 0;
  double min_edge = 0, max_edge = 0, mean_edge = 0;
  double min_angle_deg = 0;  // smallest triangle angle
};

// Counts everything above in O(V + T).
MeshStats compute_stats(const SurfaceMesh& mesh);

}  // namespace anisurf
