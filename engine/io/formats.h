// Per-format readers and writers (internal to engine/io; use mesh_io.h).
#pragma once
#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace anisurf::io {

MeshData read_medit(const std::string& path);          // .mesh (ASCII)
MeshData read_medit_binary(const std::string& path);   // .meshb
void write_medit(const std::string& path, const MeshData& data, int version);
void write_medit_binary(const std::string& path, const MeshData& data);

std::vector<FieldData> read_sol_ascii(const std::string& path, int n_vertices, int* dimension);
std::vector<FieldData> read_sol_binary(const std::string& path, int n_vertices, int* dimension);
void write_sol_ascii(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension);
void write_sol_binary(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension);

MeshData read_obj(const std::string& path);
void write_obj(const std::string& path, const MeshData& data);
MeshData read_off(const std::string& path);
MeshData read_ply(const std::string& path);
void write_ply(const std::string& path, const MeshData& data, bool binary, bool big_endian);
MeshData read_stl(const std::string& path);
void write_stl(const std::string& path, const MeshData& data, bool binary);
MeshData read_gltf(const std::string& path);  // .gltf and .glb
void write_glb(const std::string& path, const MeshData& data);
void write_vtk(const std::string& path, const MeshData& data);
MeshData read_vtk(const std::string& path);  // legacy .vtk, ASCII or BINARY
MeshData read_gmsh(const std::string& path);  // .msh 2.2 / 4.1, ASCII or binary
// version 41 (4.1) or 22 (2.2).
void write_gmsh(const std::string& path, const MeshData& data, int version, bool binary);
MeshData read_vtk_xml(const std::string& path);  // .vtu and .vtp
void write_vtk_xml(const std::string& path, const MeshData& data, bool poly, VtkXmlEncoding encoding, bool compress);

}  // namespace anisurf::io
