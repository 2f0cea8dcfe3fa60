// Gmsh .msh reader and writer: exact round trips in the four layouts (2.2
// and 4.1, ASCII and binary), the hand-written samples of tests/data
// (fmt_gmsh22.msh, fmt_gmsh41.msh, written from the format specification) and
// the handling of non-symmetric tensors and skipped elements.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "io/mesh_io.h"
#include "test_io_roundtrip.h"
#include "test_util.h"

using namespace anisurf;

TEST_CASE("gmsh: exact round trips in 2.2 and 4.1, ASCII and binary") {
  const auto dir = test::temp_dir("gmsh_roundtrip");
  const MeshData d = test::roundtrip_mesh(true);
  for (int version : {22, 41})
    for (bool binary : {false, true}) {
      CAPTURE(version);
      CAPTURE(binary);
      WriteOptions o;
      o.msh_version = version;
      o.binary = binary;
      std::string file = version == 41 ? "m41" : "m22";
      file += binary ? "b.msh" : "a.msh";
      const std::string path = (dir / file).string();
      write_mesh_data(path, d, o);
      std::ifstream in(path, std::ios::binary);
      std::string head;
      std::getline(in, head);
      std::getline(in, head);
      CHECK(head == std::string(version == 41 ? "4.1" : "2.2") + (binary ? " 1 8" : " 0 8"));
      const MeshData back = read_mesh_data(path);
      test::check_same_mesh(d, back, true);
      CHECK(back.warnings.empty());
    }
}

TEST_CASE("gmsh: a mesh without refs, corners or fields round trips, and isolated vertices keep their place") {
  const auto dir = test::temp_dir("gmsh_plain");
  MeshData d;
  d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {1, 1, 0}};
  d.triangles = {{0, 1, 2}, {1, 4, 2}};
  for (int version : {22, 41}) {
    WriteOptions o;
    o.msh_version = version;
    o.binary = false;
    const std::string path = (dir / (version == 41 ? "p41.msh" : "p22.msh")).string();
    write_mesh_data(path, d, o);
    const MeshData back = read_mesh_data(path);
    CHECK(back.vertices.size() == 5);
    CHECK(back.vertices[3].x == 5);
    CHECK(back.triangles == d.triangles);
    CHECK(back.triangle_refs == std::vector<int>{0, 0});
    CHECK(back.fields.empty());
  }
}

TEST_CASE("gmsh: hand-written 2.2 sample (physical tags, a skipped quad, scalar and vector $NodeData)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_gmsh22.msh"));
  REQUIRE(d.vertices.size() == 5);
  // Nodes are ordered by tag (the file lists them 5, 1, 2, 3, 4).
  CHECK(d.vertices[0].x == 0);
  CHECK(d.vertices[4].x == 0.5);
  CHECK(d.vertices[4].z == 0.25);
  REQUIRE(d.triangles.size() == 2);
  CHECK(d.triangles[0] == std::array<int, 3>{0, 1, 4});
  CHECK(d.triangles[1] == std::array<int, 3>{1, 2, 4});
  CHECK(d.triangle_refs == std::vector<int>{10, 20});
  REQUIRE(d.edges.size() == 1);
  CHECK(d.edges[0] == std::array<int, 2>{0, 1});
  CHECK(d.edge_refs == std::vector<int>{3});
  CHECK(d.corners == std::vector<int>{0});
  CHECK(d.vertex_refs == std::vector<int>{7, 0, 0, 0, 0});
  REQUIRE(d.warnings.size() == 1);
  CHECK(d.warnings[0].find("skipped 1 quadrangles (type 3)") != std::string::npos);
  REQUIRE(d.fields.size() == 2);
  CHECK(d.fields[0].info.name == "temperature");
  CHECK(d.fields[0].info.kind == FieldKind::Scalar);
  CHECK(d.fields[0].values == std::vector<double>{1, 2, 3, 4, 5});
  CHECK(d.fields[1].info.name == "velocity");
  CHECK(d.fields[1].info.kind == FieldKind::Vector);
  CHECK(d.fields[1].info.ncomp == 3);
  CHECK(d.fields[1].values[3 * 4 + 2] == -1.5);
}

TEST_CASE("gmsh: hand-written 4.1 sample (entities, parametric nodes, tensor $NodeData made symmetric)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_gmsh41.msh"));
  REQUIRE(d.vertices.size() == 4);
  CHECK(d.vertices[3].y == 1);
  REQUIRE(d.triangles.size() == 2);
  CHECK(d.triangle_refs == std::vector<int>{100, 200});
  CHECK(d.edges.size() == 1);
  CHECK(d.edge_refs == std::vector<int>{0});
  REQUIRE(d.fields.size() == 1);
  const FieldData& m = d.fields[0];
  CHECK(m.info.name == "metric");
  CHECK(m.info.kind == FieldKind::Tensor);
  CHECK(m.info.ncomp == 6);
  // Node 1: 3x3 row-major 1 2 3 / 2 4 5 / 3 5 6 -> m11 m12 m22 m13 m23 m33.
  CHECK(std::vector<double>(m.values.begin(), m.values.begin() + 6) == std::vector<double>{1, 2, 4, 3, 5, 6});
  // Node 2 is not symmetric (xy 1, yx 3): averaged, with a warning.
  CHECK(m.values[6 + 1] == 2);
  bool warned = false;
  for (const auto& w : d.warnings) warned |= w.find("1 non-symmetric 3x3 tensors made symmetric") != std::string::npos;
  CHECK(warned);
  // The built mesh takes the tensor as a field the metric code reads.
  SurfaceMesh mesh = load_mesh(test::data_file("fmt_gmsh41.msh"));
  REQUIRE(mesh.fields().size() == 1);
  CHECK(mesh.fields()[0].kind == FieldKind::Tensor);
}

TEST_CASE("gmsh: writing refuses fields without a MSH layout and unknown versions") {
  const auto dir = test::temp_dir("gmsh_refuse");
  MeshData d = test::roundtrip_mesh(true);
  WriteOptions o;
  o.msh_version = 30;
  CHECK_THROWS_WITH_AS(write_mesh_data((dir / "v.msh").string(), d, o), doctest::Contains("expected 4.1 or 2.2"),
                       IoError);
  FieldData rgba;
  rgba.info = FieldInfo{"rgba", FieldKind::Scalar, 4};
  rgba.values.assign(4 * d.vertices.size(), 0.5);
  d.fields.push_back(rgba);
  CHECK_THROWS_WITH_AS(write_mesh_data((dir / "f.msh").string(), d), doctest::Contains("field 'rgba'"), IoError);
  CHECK_FALSE(std::filesystem::exists(dir / "f.msh"));
}
