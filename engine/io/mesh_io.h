// Reading and writing surface meshes and per-vertex fields in every supported
// format, chosen from the file extension.
//   read:  .mesh .meshb (Medit), .obj, .off, .ply, .stl, .gltf, .glb,
//          .msh (Gmsh 2.2 / 4.1), .vtu .vtp (VTK XML), .vtk (legacy VTK)
//   write: .mesh .meshb, .obj, .ply, .stl, .glb, .msh, .vtu .vtp, .vtk
//   fields: .sol / .solb (Medit SolAtVertices: scalar, vector, tensor);
//           embedded in .msh ($NodeData), .vtu .vtp .vtk (point data) and .ply
#pragma once
#include <string>
#include <vector>

#include "mesh/build.h"
#include "mesh/mesh_data.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

enum class MeshFormat { Medit, MeditBinary, Obj, Off, Ply, Stl, Gltf, Glb, Vtk, Gmsh, Vtu, Vtp };

// True for the formats that carry per-vertex fields inside the mesh file
// (.msh .vtu .vtp .vtk); Medit keeps them in a .sol beside the mesh.
bool format_embeds_fields(MeshFormat format);

// How VTK XML data arrays are stored: text, inline base64 ("binary"), or
// appended after the XML as raw bytes or as base64.
enum class VtkXmlEncoding { Ascii, Binary, Appended, AppendedBase64 };

// Format from the extension (case-insensitive); throws IoError naming the
// path and the supported extensions otherwise.
MeshFormat mesh_format_from_path(const std::string& path);

struct WriteOptions {
  bool binary = true;      // PLY / STL / .msh: binary (true) or ASCII
  bool big_endian = false; // PLY binary byte order
  int medit_version = 2;   // .mesh: 1 (float precision) or 2 (double)
  int msh_version = 41;    // .msh: 41 (4.1) or 22 (2.2)
  VtkXmlEncoding vtk_encoding = VtkXmlEncoding::Appended;  // .vtu .vtp
  bool vtk_compress = false;  // .vtu .vtp binary data zlib-compressed
};

// Reads file-level data (no repair yet). Throws IoError with file and line.
MeshData read_mesh_data(const std::string& path);
// Writes file-level data through a temporary file renamed on success.
void write_mesh_data(const std::string& path, const MeshData& data, const WriteOptions& options = {});

// Reads the fields of a .sol/.solb file. `n_vertices` (if >= 0) must match the
// file's vertex count; `dimension` receives the file's dimension.
std::vector<FieldData> read_sol(const std::string& path, int n_vertices = -1, int* dimension = nullptr);
// Writes fields (each values.size() == n_vertices * ncomp) as SolAtVertices.
void write_sol(const std::string& path, const std::vector<FieldData>& fields, int n_vertices, int dimension = 3);
// The same from views of the values (no copy: a metric field's tensors).
void write_sol(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension = 3);

// Convenience: read + build_mesh (+ fields of an optional .sol mapped through
// the build's vertex map).
SurfaceMesh load_mesh(const std::string& path, BuildReport* report = nullptr, const BuildOptions& options = {});
// Convenience: to_mesh_data + write_mesh_data.
void save_mesh(const std::string& path, const SurfaceMesh& mesh, const WriteOptions& options = {});

// Attaches fields read from a .sol (numbered like the file's vertices) to a
// built mesh, through report.vertex_origin.
void attach_fields(SurfaceMesh& mesh, const std::vector<FieldData>& fields, const BuildReport& report);
// Extracts the mesh's fields (compact vertex numbering, like to_mesh_data).
std::vector<FieldData> extract_fields(const SurfaceMesh& mesh);

}  // namespace anisurf
