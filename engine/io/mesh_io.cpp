// Format dispatch from the file extension, and the convenience functions that
// combine reading/writing with build_mesh / to_mesh_data and fields.
#include "io/mesh_io.h"

#include <cctype>
#include <filesystem>
#include <tuple>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/formats.h"

namespace anisurf {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

const char* const kReadable = ".mesh .meshb .obj .off .ply .stl .gltf .glb .msh .vtu .vtp .vtk";
const char* const kWritable = ".mesh .meshb .obj .ply .stl .glb .msh .vtu .vtp .vtk";

enum class SolFormat { Ascii, Binary };

SolFormat sol_format_from_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".sol") return SolFormat::Ascii;
  if (ext == ".solb") return SolFormat::Binary;
  throw IoError(path + ": unknown solution format '" + std::filesystem::path(path).extension().string() +
                "', expected .sol or .solb");
}

bool is_sol_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".sol" || ext == ".solb";
}

}  // namespace

MeshFormat mesh_format_from_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".mesh") return MeshFormat::Medit;
  if (ext == ".meshb") return MeshFormat::MeditBinary;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".gltf") return MeshFormat::Gltf;
  if (ext == ".glb") return MeshFormat::Glb;
  if (ext == ".vtk") return MeshFormat::Vtk;
  if (ext == ".msh") return MeshFormat::Gmsh;
  if (ext == ".vtu") return MeshFormat::Vtu;
  if (ext == ".vtp") return MeshFormat::Vtp;
  const std::string shown = std::filesystem::path(path).extension().string();
  throw IoError(path + ": unknown mesh format " + (shown.empty() ? std::string("(no extension)") : "'" + shown + "'") +
                ", expected one of " + kReadable);
}

bool format_embeds_fields(MeshFormat format) {
  return format == MeshFormat::Gmsh || format == MeshFormat::Vtu || format == MeshFormat::Vtp ||
         format == MeshFormat::Vtk;
}

MeshData read_mesh_data(const std::string& path) {
  switch (mesh_format_from_path(path)) {
    case MeshFormat::Medit: return io::read_medit(path);
    case MeshFormat::MeditBinary: return io::read_medit_binary(path);
    case MeshFormat::Obj: return io::read_obj(path);
    case MeshFormat::Off: return io::read_off(path);
    case MeshFormat::Ply: return io::read_ply(path);
    case MeshFormat::Stl: return io::read_stl(path);
    case MeshFormat::Gltf:
    case MeshFormat::Glb: return io::read_gltf(path);
    case MeshFormat::Vtk: return io::read_vtk(path);
    case MeshFormat::Gmsh: return io::read_gmsh(path);
    case MeshFormat::Vtu:
    case MeshFormat::Vtp: return io::read_vtk_xml(path);
  }
  throw IoError(path + ": unknown mesh format, expected one of " + std::string(kReadable));
}

void write_mesh_data(const std::string& path, const MeshData& data, const WriteOptions& options) {
  switch (mesh_format_from_path(path)) {
    case MeshFormat::Medit: io::write_medit(path, data, options.medit_version); return;
    case MeshFormat::MeditBinary: io::write_medit_binary(path, data); return;
    case MeshFormat::Obj: io::write_obj(path, data); return;
    case MeshFormat::Ply: io::write_ply(path, data, options.binary, options.big_endian); return;
    case MeshFormat::Stl: io::write_stl(path, data, options.binary); return;
    case MeshFormat::Glb: io::write_glb(path, data); return;
    case MeshFormat::Vtk: io::write_vtk(path, data); return;
    case MeshFormat::Gmsh: io::write_gmsh(path, data, options.msh_version, options.binary); return;
    case MeshFormat::Vtu:
    case MeshFormat::Vtp:
      io::write_vtk_xml(path, data, mesh_format_from_path(path) == MeshFormat::Vtp, options.vtk_encoding,
                        options.vtk_compress);
      return;
    case MeshFormat::Off:
    case MeshFormat::Gltf: break;
  }
  throw IoError(path + ": cannot write '" + std::filesystem::path(path).extension().string() + "', expected one of " +
                kWritable);
}

std::vector<FieldData> read_sol(const std::string& path, int n_vertices, int* dimension) {
  return sol_format_from_path(path) == SolFormat::Ascii ? io::read_sol_ascii(path, n_vertices, dimension)
                                                        : io::read_sol_binary(path, n_vertices, dimension);
}

void write_sol(const std::string& path, const std::vector<FieldData>& fields, int n_vertices, int dimension) {
  std::vector<FieldView> views;
  for (const FieldData& f : fields) views.push_back(view_of(f));
  write_sol(path, views, n_vertices, dimension);
}

void write_sol(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension) {
  if (sol_format_from_path(path) == SolFormat::Ascii)
    io::write_sol_ascii(path, fields, n_vertices, dimension);
  else
    io::write_sol_binary(path, fields, n_vertices, dimension);
}

SurfaceMesh load_mesh(const std::string& path, BuildReport* report, const BuildOptions& options) {
  // Fields come only from the mesh file itself (PLY extras ...); a sibling
  // .sol is never loaded implicitly: use read_sol + attach_fields.
  const MeshData data = read_mesh_data(path);
  SurfaceMesh mesh;
  BuildReport r = build_mesh(data, mesh, options, path);
  if (report) *report = std::move(r);
  return mesh;
}

void save_mesh(const std::string& path, const SurfaceMesh& mesh, const WriteOptions& options) {
  if (is_sol_path(path)) {
    write_sol(path, extract_fields(mesh), mesh.n_vertices(), mesh.dimension());
    return;
  }
  write_mesh_data(path, to_mesh_data(mesh), options);
}

void attach_fields(SurfaceMesh& mesh, const std::vector<FieldData>& fields, const BuildReport& report) {
  const auto n_file = static_cast<std::size_t>(report.input_vertices);
  if (report.vertex_origin.size() != static_cast<std::size_t>(mesh.vertex_capacity()))
    throw Error("attach_fields: the build report maps " + std::to_string(report.vertex_origin.size()) +
                " vertices but the mesh has " + std::to_string(mesh.vertex_capacity()) +
                " vertex slots, expected the mesh as built");
  for (const FieldData& f : fields) {
    const auto nc = static_cast<std::size_t>(f.info.ncomp);
    if (nc < 1 || nc > std::tuple_size_v<FieldValue>)
      throw Error("field '" + f.info.name + "' has " + std::to_string(nc) + " components, expected 1..6");
    if (f.values.size() != n_file * nc)
      throw Error("field '" + f.info.name + "' has " + std::to_string(f.values.size() / nc) + " values but the file has " +
                  std::to_string(n_file) + " vertices, expected one value per file vertex");
    Property<FieldValue> p = mesh.get_field(f.info.name);
    if (p) {
      for (const FieldInfo& info : mesh.fields())
        if (info.name == f.info.name && (info.kind != f.info.kind || info.ncomp != f.info.ncomp))
          throw Error("field '" + f.info.name + "' exists on the mesh with another kind or size, expected the same");
    } else {
      p = mesh.add_field(f.info.name, f.info.kind, f.info.ncomp);
    }
    for (std::size_t v = 0; v < report.vertex_origin.size(); ++v) {
      const int origin = report.vertex_origin[v];
      if (origin < 0 || static_cast<std::size_t>(origin) >= n_file) continue;
      FieldValue value{};
      for (std::size_t c = 0; c < nc; ++c) value[c] = f.values[static_cast<std::size_t>(origin) * nc + c];
      p.at(static_cast<int>(v)) = value;
    }
  }
}

std::vector<FieldData> extract_fields(const SurfaceMesh& mesh) {
  std::vector<FieldData> out;
  for (const FieldInfo& info : mesh.fields()) {
    const Property<FieldValue> p = mesh.get_field(info.name);
    if (!p) continue;
    FieldData f;
    f.info = info;
    const auto nc = static_cast<std::size_t>(info.ncomp);
    f.values.reserve(static_cast<std::size_t>(mesh.n_vertices()) * nc);
    for (Vertex v : mesh.vertices()) {
      const FieldValue& value = p[v];
      for (std::size_t c = 0; c < nc; ++c) f.values.push_back(value[c]);
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace anisurf
