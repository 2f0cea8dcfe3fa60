// File-level description of a surface mesh: the flat arrays every reader
// produces and every writer consumes (0-based ids). build_mesh() turns it into
// a SurfaceMesh (merging, orienting, repairing); to_mesh_data() goes back.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "mesh/properties.h"

namespace anisurf {

// One per-vertex field: values has n_vertices * info.ncomp entries.
struct FieldData {
  FieldInfo info;
  std::vector<double> values;
};

// A per-vertex field read in place (a writer's input, no copy): `size`
// doubles from `values`, n_vertices * info.ncomp of them.
struct FieldView {
  FieldInfo info;
  const double* values = nullptr;
  std::size_t size = 0;
};
inline FieldView view_of(const FieldData& f) { return {f.info, f.values.data(), f.values.size()}; }

struct MeshData {
  int dimension = 3;  // 2 for planar Medit meshes (z = 0)
  int version = 2;    // Medit MeshVersionFormatted (1: float, 2: double)

  std::vector<Vec3> vertices;
  std::vector<int> vertex_refs;  // empty or one per vertex

  std::vector<std::array<int, 3>> triangles;
  std::vector<int> triangle_refs;  // empty or one per triangle

  std::vector<std::array<int, 2>> edges;  // Medit Edges
  std::vector<int> edge_refs;             // empty or one per edge

  std::vector<int> corners;             // vertex ids
  std::vector<int> ridges;              // ids into edges
  std::vector<int> required_vertices;   // vertex ids
  std::vector<int> required_edges;      // ids into edges
  std::vector<int> required_triangles;  // triangle ids

  std::vector<Vec3> normals;                         // Medit Normals
  std::vector<std::array<int, 2>> normal_at_vertex;  // (vertex, normal id)
  std::vector<Vec3> tangents;                        // Medit Tangents
  std::vector<std::array<int, 2>> tangent_at_vertex; // (vertex, tangent id)

  std::vector<FieldData> fields;  // per-vertex fields (.sol, PLY/VTK extras)

  // True for formats that store split vertices (STL, glTF): build_mesh then
  // merges coincident positions.
  bool split_vertices = false;
  // Non-fatal remarks of the reader (skipped sections, ignored attributes).
  std::vector<std::string> warnings;
};

}  // namespace anisurf
