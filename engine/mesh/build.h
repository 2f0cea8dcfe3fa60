// Building a SurfaceMesh from file-level data (a triangle soup with tags), and
// the way back. What is repaired and what is refused:
//  - repaired, with a count in the report: identical positions merged for
//    formats with split vertices (optionally welded within a tolerance
//    relative to the bounding box),
//    triangles with a repeated vertex dropped, duplicated triangles dropped,
//    unreferenced vertices dropped, components oriented consistently (triangles
//    flipped), edges shared by more than two triangles cut (tagged
//    kNonManifold), non-manifold vertices split into one copy per fan.
//  - reported only: zero-area triangles, several components, open boundaries.
//  - refused (TopologyError): no triangle, ids out of range, non-finite
//    coordinates.
#pragma once
#include <string>
#include <vector>

#include "mesh/mesh_data.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

struct BuildOptions {
  // Merge coincident positions: Auto merges for formats that store split
  // vertices (STL, glTF: a copy per triangle or per normal) or when a welding
  // tolerance is set; Always merges for every format; Never keeps every vertex.
  // (Other formats may hold stray duplicates: they are counted in
  // BuildReport::unique_positions but kept apart, since merging them usually
  // makes pinch points that would have to be split again.)
  enum class Merge { Auto, Always, Never } merge = Merge::Auto;
  // Welding tolerance relative to the bounding box diagonal: 0 merges only
  // identical positions (the counts users expect); a small value such as 1e-9
  // also welds the near-coincident vertices of CAD exports and closes their
  // cracks (featuretype.STL: 576 boundary edges -> 0).
  double merge_tolerance = 0;
  bool orient = true;              // orient each component consistently
  bool drop_unreferenced = true;   // drop vertices that no triangle uses
  bool drop_duplicate_triangles = true;
};

struct BuildReport {
  int input_vertices = 0;
  int input_triangles = 0;
  int unique_positions = 0;         // distinct positions among the file's vertices
  int merged_vertices = 0;          // removed by merging coincident positions
  int unreferenced_vertices = 0;    // dropped
  int degenerate_triangles = 0;     // repeated vertex id: dropped
  int duplicate_triangles = 0;      // same vertex set as another: dropped
  int zero_area_triangles = 0;      // kept, reported
  int flipped_triangles = 0;        // re-oriented
  int non_manifold_edges = 0;       // cut
  int non_manifold_vertices = 0;    // split
  int non_orientable_components = 0;  // could not be oriented consistently (cut)
  int dropped_edges = 0;            // Edges entries that are not mesh edges
  std::vector<std::string> warnings;  // reader warnings + repair messages

  // For each mesh vertex (after build, compact numbering) the index of the
  // file vertex it came from.
  std::vector<int> vertex_origin;
  // For each file vertex, the mesh vertex it became (-1 if dropped; for a
  // split vertex, one of its copies).
  std::vector<int> vertex_map;
  // For each mesh triangle, the file triangle it came from.
  std::vector<int> triangle_origin;

  bool repaired() const;
  std::vector<std::string> repair_messages() const;  // one line per repair kind
};

// Builds `mesh` from `data` (replacing its content). Throws TopologyError
// naming `source` on refused input. Tags: file Ridges/Corners/Required* and
// references become mesh tags; NormalAtVertices / TangentAtVertices become
// vertex properties "normal" / "tangent" (Vec3) with the flag property
// "has_normal" / "has_tangent"; fields become mesh fields.
BuildReport build_mesh(const MeshData& data, SurfaceMesh& mesh, const BuildOptions& options = {},
                       const std::string& source = "mesh");

// Flattens a mesh (compact numbering of live elements) back to file-level data:
// every tagged or listed edge goes to Edges, tags to their sections.
MeshData to_mesh_data(const SurfaceMesh& mesh);
// The same, consuming the mesh: the positions move into the data when the
// mesh has no deleted vertex (its slots are the file's numbering), and the
// mesh is left empty, its memory freed, before the data is returned.
MeshData to_mesh_data(SurfaceMesh&& mesh);

}  // namespace anisurf
