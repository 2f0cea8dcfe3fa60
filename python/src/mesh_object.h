// anisurf.Mesh: a surface mesh as numpy arrays (the file-level data of
// mesh/mesh_data.h, 0-based), and the way to and from the engine's MeshData.
#pragma once
#include <pybind11/pybind11.h>

#include <string>

#include "mesh/mesh_data.h"

namespace anisurf::python {

namespace py = pybind11;

struct Mesh {
  py::object vertices;            // (N, 3) float64
  py::object triangles;           // (M, 3) int32 (any integer array accepted)
  py::object refs;                // (M,) triangle references
  py::object vertex_refs;         // (N,)
  py::dict fields;                // name -> (N,), (N, 2|3) or (N, 6) float64
  py::object edges;               // (K, 2) listed edges (Medit Edges)
  py::object edge_refs;           // (K,)
  py::object ridges;              // indices into edges
  py::object corners;             // vertex indices
  py::object required_vertices;   // vertex indices
  py::object required_edges;      // indices into edges
  py::object required_triangles;  // triangle indices
  virtual ~Mesh() = default;
};

// The arrays of `data`, its vectors moved into them.
void fill_mesh(Mesh& mesh, MeshData data);
Mesh mesh_from_data(MeshData data);
// The MeshData of a Mesh, checked (shapes, index ranges).
MeshData data_from_mesh(const Mesh& mesh);
// The MeshData of (vertices, triangles[, refs]) arrays, checked.
MeshData data_from_arrays(py::handle vertices, py::handle triangles, py::handle refs);
// `mesh_or_vertices` is a Mesh (then `triangles` must be None) or the
// vertices of (vertices, triangles); `fields` (a dict or None) is added,
// replacing the fields of the same name.
MeshData data_from_arguments(py::handle mesh_or_vertices, py::handle triangles, py::handle fields,
                             const char* function);
// Adds or replaces the fields of the dict `fields` (None: nothing).
void set_fields(MeshData& data, py::handle fields);

// Registers anisurf.Mesh, anisurf.load and anisurf.save.
void bind_mesh(py::module_& m);

}  // namespace anisurf::python
