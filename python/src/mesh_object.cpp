#include "mesh_object.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>

#include "arrays.h"
#include "io/mesh_io.h"
#include "mesh/build.h"

namespace anisurf::python {

namespace {

bool is_none_or_empty(py::handle obj) {
  if (obj.is_none()) return true;
  return py::len(obj) == 0;
}

bool is_sol_path(std::string path) {
  std::transform(path.begin(), path.end(), path.begin(), [](unsigned char c) { return std::tolower(c); });
  auto ends_with = [&](const std::string& s) { return path.size() >= s.size() && path.rfind(s) == path.size() - s.size(); };
  return ends_with(".sol") || ends_with(".solb");
}

// The optional index lists of a Mesh (tags), checked against their ranges.
void read_tags(const Mesh& mesh, MeshData& d) {
  const long long nv = static_cast<long long>(d.vertices.size());
  if (!is_none_or_empty(mesh.edges)) d.edges = index_rows_from<2>(mesh.edges, nv, "edges");
  const long long ne = static_cast<long long>(d.edges.size());
  if (!is_none_or_empty(mesh.edge_refs)) d.edge_refs = ints_from(mesh.edge_refs, ne, -1, "edge_refs");
  if (!is_none_or_empty(mesh.ridges)) d.ridges = ints_from(mesh.ridges, -1, ne, "ridges");
  if (!is_none_or_empty(mesh.required_edges)) d.required_edges = ints_from(mesh.required_edges, -1, ne, "required_edges");
  if (!is_none_or_empty(mesh.corners)) d.corners = ints_from(mesh.corners, -1, nv, "corners");
  if (!is_none_or_empty(mesh.required_vertices))
    d.required_vertices = ints_from(mesh.required_vertices, -1, nv, "required_vertices");
  if (!is_none_or_empty(mesh.required_triangles))
    d.required_triangles =
        ints_from(mesh.required_triangles, -1, static_cast<long long>(d.triangles.size()), "required_triangles");
  if (!is_none_or_empty(mesh.vertex_refs)) d.vertex_refs = ints_from(mesh.vertex_refs, nv, -1, "vertex_refs");
}

std::string mesh_repr(py::handle self) {
  const Mesh& m = self.cast<const Mesh&>();
  std::string fields;
  for (auto item : m.fields) fields += (fields.empty() ? "" : ", ") + py::str(item.first).cast<std::string>();
  const std::string type = py::str(py::type::of(self).attr("__name__")).cast<std::string>();
  return "<anisurf." + type + ": " + std::to_string(py::len(m.vertices)) + " vertices, " +
         std::to_string(py::len(m.triangles)) + " triangles" + (fields.empty() ? "" : ", fields: " + fields) + ">";
}

// anisurf.load: the file's mesh, built (merged, oriented, repaired) unless
// build is False; the fields of `sol` attached.
Mesh load(const std::string& path, const std::string& sol, bool build, double weld) {
  MeshData data;
  {
    py::gil_scoped_release release;
    data = read_mesh_data(path);
    if (!sol.empty()) {
      std::vector<FieldData> fields = read_sol(sol, static_cast<int>(data.vertices.size()));
      for (FieldData& f : fields) data.fields.push_back(std::move(f));
    }
    if (build) {
      BuildOptions options;
      if (weld >= 0) {
        options.merge = BuildOptions::Merge::Always;
        options.merge_tolerance = weld;
      }
      SurfaceMesh mesh;
      build_mesh(data, mesh, options, path);
      data = to_mesh_data(mesh);
    }
  }
  return mesh_from_data(std::move(data));
}

// anisurf.save: the mesh (by its extension), or its fields for .sol/.solb.
void save(py::handle mesh, const std::string& path, py::handle fields, bool binary) {
  MeshData data;
  if (py::isinstance<Mesh>(mesh)) {
    data = data_from_mesh(mesh.cast<const Mesh&>());
  } else if (py::isinstance<py::tuple>(mesh) || py::isinstance<py::list>(mesh)) {
    const py::sequence s = mesh.cast<py::sequence>();
    if (s.size() != 2 && s.size() != 3)
      throw py::type_error("save() expects a Mesh or a (vertices, triangles[, refs]) tuple");
    data = data_from_arrays(s[0], s[1], s.size() == 3 ? py::object(s[2]) : py::none());
  } else {
    throw py::type_error("save() expects a Mesh or a (vertices, triangles[, refs]) tuple");
  }
  set_fields(data, fields);
  const bool sol = is_sol_path(path);
  if (sol && data.fields.empty()) throw py::value_error("save(): no field to write to " + path);
  py::gil_scoped_release release;
  if (sol) {
    write_sol(path, data.fields, static_cast<int>(data.vertices.size()), data.dimension);
    return;
  }
  WriteOptions options;
  options.binary = binary;
  write_mesh_data(path, data, options);
}

}  // namespace

void fill_mesh(Mesh& m, MeshData d) {
  const auto nv = d.vertices.size();
  const auto nt = d.triangles.size();
  m.vertices = positions_array(std::move(d.vertices));
  m.triangles = triangles_array(std::move(d.triangles));
  if (d.triangle_refs.size() != nt) d.triangle_refs.assign(nt, 0);
  if (d.vertex_refs.size() != nv) d.vertex_refs.assign(nv, 0);
  m.refs = int_array(std::move(d.triangle_refs));
  m.vertex_refs = int_array(std::move(d.vertex_refs));
  if (d.edge_refs.size() != d.edges.size()) d.edge_refs.assign(d.edges.size(), 0);
  m.edges = edges_array(std::move(d.edges));
  m.edge_refs = int_array(std::move(d.edge_refs));
  m.ridges = int_array(std::move(d.ridges));
  m.corners = int_array(std::move(d.corners));
  m.required_vertices = int_array(std::move(d.required_vertices));
  m.required_edges = int_array(std::move(d.required_edges));
  m.required_triangles = int_array(std::move(d.required_triangles));
  m.fields = py::dict();
  for (FieldData& f : d.fields) {
    const std::string name = f.info.name;
    m.fields[py::str(name)] = field_array(std::move(f));
  }
}

Mesh mesh_from_data(MeshData data) {
  Mesh m;
  fill_mesh(m, std::move(data));
  return m;
}

MeshData data_from_arrays(py::handle vertices, py::handle triangles, py::handle refs) {
  MeshData d;
  d.vertices = positions_from(vertices, "vertices");
  d.triangles = index_rows_from<3>(triangles, static_cast<long long>(d.vertices.size()), "triangles");
  if (!is_none_or_empty(refs)) d.triangle_refs = ints_from(refs, static_cast<long long>(d.triangles.size()), -1, "refs");
  return d;
}

MeshData data_from_mesh(const Mesh& mesh) {
  MeshData d = data_from_arrays(mesh.vertices, mesh.triangles, mesh.refs);
  read_tags(mesh, d);
  set_fields(d, mesh.fields);
  return d;
}

void set_fields(MeshData& data, py::handle fields) {
  if (fields.is_none()) return;
  if (!py::isinstance<py::dict>(fields)) throw py::type_error("fields must be a dict name -> array");
  for (auto item : fields.cast<py::dict>()) {
    if (!py::isinstance<py::str>(item.first)) throw py::type_error("fields: the names must be strings");
    FieldData f = field_from(item.first.cast<std::string>(), item.second, data.vertices.size());
    auto same = std::find_if(data.fields.begin(), data.fields.end(),
                             [&](const FieldData& g) { return g.info.name == f.info.name; });
    if (same != data.fields.end())
      *same = std::move(f);
    else
      data.fields.push_back(std::move(f));
  }
}

MeshData data_from_arguments(py::handle mesh_or_vertices, py::handle triangles, py::handle fields,
                             const char* function) {
  MeshData d;
  if (py::isinstance<Mesh>(mesh_or_vertices)) {
    if (!triangles.is_none())
      throw py::type_error(std::string(function) + "(): give a Mesh alone or vertices and triangles, not both");
    d = data_from_mesh(mesh_or_vertices.cast<const Mesh&>());
  } else {
    if (triangles.is_none())
      throw py::type_error(std::string(function) + "(): missing the triangles (or give a Mesh)");
    d = data_from_arrays(mesh_or_vertices, triangles, py::none());
  }
  set_fields(d, fields);
  return d;
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", R"doc(
A surface mesh as numpy arrays (0-based indices).

Attributes: vertices (N, 3) float64; triangles (M, 3) int32; refs (M,)
triangle references; vertex_refs (N,); fields: dict name -> (N,) scalars,
(N, 3) vectors or (N, 6) symmetric tensors (m11 m12 m22 m13 m23 m33, the .sol
order); the tags of Medit files: edges (K, 2), edge_refs (K,), ridges and
required_edges (indices into edges), corners and required_vertices (vertex
indices), required_triangles. Every attribute may be replaced by another array.

Mesh(vertices, triangles, refs=None, fields=None) checks and copies the arrays.)doc")
      .def(py::init([](py::handle vertices, py::handle triangles, py::handle refs, py::handle fields) {
             MeshData d = data_from_arrays(vertices, triangles, refs);
             set_fields(d, fields);
             return mesh_from_data(std::move(d));
           }),
           py::arg("vertices"), py::arg("triangles"), py::arg("refs") = py::none(), py::arg("fields") = py::none())
      .def_readwrite("vertices", &Mesh::vertices)
      .def_readwrite("triangles", &Mesh::triangles)
      .def_readwrite("refs", &Mesh::refs)
      .def_readwrite("vertex_refs", &Mesh::vertex_refs)
      .def_readwrite("fields", &Mesh::fields)
      .def_readwrite("edges", &Mesh::edges)
      .def_readwrite("edge_refs", &Mesh::edge_refs)
      .def_readwrite("ridges", &Mesh::ridges)
      .def_readwrite("corners", &Mesh::corners)
      .def_readwrite("required_vertices", &Mesh::required_vertices)
      .def_readwrite("required_edges", &Mesh::required_edges)
      .def_readwrite("required_triangles", &Mesh::required_triangles)
      .def("__repr__", &mesh_repr);

  m.def("load", &load, py::arg("path"), py::arg("sol") = "", py::arg("build") = true, py::arg("weld") = -1.0,
        R"doc(
load(path, sol="", build=True, weld=-1) -> Mesh

Reads a mesh in any format anisurf reads (.mesh .meshb .obj .off .ply .stl
.gltf .glb ...), with the fields of the .sol/.solb file `sol` (numbered like
the file's vertices). build=True (default) returns the mesh as the command
line works on it: coincident vertices of STL/glTF merged (weld >= 0: also
those within weld x the bounding-box diagonal), components oriented,
degenerate and duplicate triangles and unused vertices dropped; build=False
returns the file's data as is. Raises anisurf.IoError (file and line) on a
broken file.)doc");
  m.def("save", &save, py::arg("mesh"), py::arg("path"), py::arg("fields") = py::none(), py::arg("binary") = true,
        R"doc(
save(mesh, path, fields=None, binary=True)

Writes `mesh` (a Mesh, an adapt() Result, or a (vertices, triangles[, refs])
tuple) in the format of the extension (.mesh .meshb .obj .ply .stl .glb .vtk
.msh .vtu .vtp; binary: PLY, STL and .msh; .msh/.vtu/.vtp/.vtk hold the fields), or, for .sol/.solb, its fields (SolAtVertices). `fields`
(dict name -> array) adds to or replaces the mesh's fields, e.g.
save(result, "out.sol", fields={"metric": result.metric}).)doc");
}

}  // namespace anisurf::python
