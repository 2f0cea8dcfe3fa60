// A mesh exercising every MeshData part the .msh / VTK formats carry, and the
// exact comparison of a mesh read back (test_io_gmsh.cpp, test_io_vtk_xml.cpp).
#pragma once
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mesh/mesh_data.h"

namespace anisurf::test {

// Two strips of triangles with interleaved refs (0 among them), edges with
// refs, corners with vertex refs, coordinates that need 17 digits, and a
// scalar, a 3-vector and a symmetric tensor field. `corner_refs_only`: vertex
// refs only on the corners (.msh keeps vertex refs through point elements).
inline MeshData roundtrip_mesh(bool corner_refs_only) {
  MeshData d;
  const int nx = 5;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < nx; ++i)
      d.vertices.push_back({i / 3.0 + 1e-17 * i, j * 0.1 - std::ldexp(1.0, -60), std::sin(i + j) * 1e-300});
  for (int i = 0; i + 1 < nx; ++i) {
    d.triangles.push_back({i, i + 1, nx + i});
    d.triangles.push_back({i + 1, nx + i + 1, nx + i});
  }
  d.triangle_refs = {3, 0, 3, 7, -2, 7, 3, 0};
  d.edges = {{0, 1}, {1, 2}, {nx, nx + 1}};
  d.edge_refs = {5, 0, 6};
  d.corners = {0, nx - 1};
  d.vertex_refs.assign(d.vertices.size(), 0);
  d.vertex_refs[0] = 11;
  d.vertex_refs[nx - 1] = 12;
  if (!corner_refs_only) d.vertex_refs[2] = -4;
  const std::size_t nv = d.vertices.size();
  FieldData s{{"pressure p", FieldKind::Scalar, 1}, {}};
  FieldData v{{"velocity", FieldKind::Vector, 3}, {}};
  FieldData m{{"metric", FieldKind::Tensor, 6}, {}};
  for (std::size_t i = 0; i < nv; ++i) {
    const double x = static_cast<double>(i);
    s.values.push_back(1.0 / (x + 3.0));
    v.values.insert(v.values.end(), {x, -x / 7.0, 1e-310});
    m.values.insert(m.values.end(), {100 + x, 0.1 / 3.0, 50.5, -x / 9.0, 0.25, 1e6 + 1.0 / 3.0});
  }
  d.fields = {s, v, m};
  return d;
}

// `back` equals `d` exactly: vertices bit for bit, elements, refs, fields.
inline void check_same_mesh(const MeshData& d, const MeshData& back, bool with_corners) {
  REQUIRE(back.vertices.size() == d.vertices.size());
  for (std::size_t i = 0; i < d.vertices.size(); ++i) {
    CHECK(back.vertices[i].x == d.vertices[i].x);
    CHECK(back.vertices[i].y == d.vertices[i].y);
    CHECK(back.vertices[i].z == d.vertices[i].z);
  }
  CHECK(back.triangles == d.triangles);
  CHECK(back.triangle_refs == d.triangle_refs);
  CHECK(back.edges == d.edges);
  CHECK(back.edge_refs == d.edge_refs);
  CHECK(back.vertex_refs == d.vertex_refs);
  if (with_corners) CHECK(back.corners == d.corners);
  REQUIRE(back.fields.size() == d.fields.size());
  for (std::size_t k = 0; k < d.fields.size(); ++k) {
    CAPTURE(d.fields[k].info.name);
    CHECK(back.fields[k].info.name == d.fields[k].info.name);
    CHECK(back.fields[k].info.kind == d.fields[k].info.kind);
    CHECK(back.fields[k].info.ncomp == d.fields[k].info.ncomp);
    CHECK(back.fields[k].values == d.fields[k].values);
  }
}

}  // namespace anisurf::test
