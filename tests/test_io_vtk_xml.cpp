// VTK XML (.vtu, .vtp) reader and writer, and the legacy .vtk reader: exact
// round trips in every encoding (ascii, inline base64, appended raw and
// base64, each with and without zlib), the samples of tests/data (written by
// hand or by fmt_generate_vtk.py from the format description: big-endian,
// UInt32 headers, zlib blocks, appended raw, legacy BINARY) and the cells and
// arrays the readers skip.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.h"
#include "io/mesh_io.h"
#include "test_io_roundtrip.h"
#include "test_util.h"

using namespace anisurf;

namespace {

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool has_warning(const MeshData& d, const std::string& text) {
  for (const auto& w : d.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("vtk xml: exact round trips of .vtu and .vtp in every encoding, with and without zlib") {
  const auto dir = test::temp_dir("vtk_xml_roundtrip");
  const MeshData d = test::roundtrip_mesh(false);
  const std::pair<VtkXmlEncoding, const char*> encodings[] = {{VtkXmlEncoding::Ascii, "ascii"},
                                                              {VtkXmlEncoding::Binary, "binary"},
                                                              {VtkXmlEncoding::Appended, "appended"},
                                                              {VtkXmlEncoding::AppendedBase64, "appended_b64"}};
  for (const char* ext : {".vtu", ".vtp"})
    for (const auto& [encoding, name] : encodings)
      for (bool zlib : {false, true}) {
        if (zlib && encoding == VtkXmlEncoding::Ascii) continue;
        const std::string file = std::string(name) + (zlib ? "_z" : "") + ext;
        CAPTURE(file);
        WriteOptions o;
        o.vtk_encoding = encoding;
        o.vtk_compress = zlib;
        const std::string path = (dir / file).string();
        write_mesh_data(path, d, o);
        const std::string text = file_text(path);
        CHECK((text.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos) == zlib);
        CHECK((text.find("<AppendedData") != std::string::npos) ==
              (encoding == VtkXmlEncoding::Appended || encoding == VtkXmlEncoding::AppendedBase64));
        const MeshData back = read_mesh_data(path);
        test::check_same_mesh(d, back, false);
        CHECK(back.corners.empty());  // VTK has no corners
        CHECK(back.warnings.empty());
      }
}

TEST_CASE("vtk xml: the writer's default is appended raw data, written through a temporary file") {
  const auto dir = test::temp_dir("vtk_xml_default");
  const std::string path = (dir / "m.vtu").string();
  write_mesh_data(path, test::roundtrip_mesh(false));
  const std::string text = file_text(path);
  CHECK(text.find("<AppendedData encoding=\"raw\">") != std::string::npos);
  CHECK(text.find("header_type=\"UInt64\"") != std::string::npos);
  CHECK(text.find("Name=\"medit:ref\"") != std::string::npos);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
}

TEST_CASE("vtk xml: hand-written ascii .vtu (Float32 scalars, VTK-order 6-tensor, gmsh:physical, skipped vertex cell)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_vtk_ascii.vtu"));
  REQUIRE(d.vertices.size() == 4);
  CHECK(d.vertices[3].z == 0.125);
  CHECK(d.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}});
  CHECK(d.triangle_refs == std::vector<int>{8, 9});
  CHECK(d.edges == std::vector<std::array<int, 2>>{{3, 0}});
  CHECK(d.edge_refs == std::vector<int>{5});
  CHECK(d.vertex_refs == std::vector<int>{1, 0, 0, 4});
  CHECK(has_warning(d, "skipped 1 cells of VTK type 1"));
  REQUIRE(d.fields.size() == 2);
  CHECK(d.fields[0].info.name == "u");
  CHECK(d.fields[0].values == std::vector<double>{0.5, 1.5, 2.5, 3.5});
  CHECK(d.fields[1].info.kind == FieldKind::Tensor);
  // XX YY ZZ XY YZ XZ = 1 2 3 4 5 6 -> m11 m12 m22 m13 m23 m33 = 1 4 2 6 5 3.
  CHECK(std::vector<double>(d.fields[1].values.begin(), d.fields[1].values.begin() + 6) ==
        std::vector<double>{1, 4, 2, 6, 5, 3});
}

TEST_CASE("vtk xml: generated big-endian zlib .vtp (UInt32 headers, polyline split, quad skipped)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_vtk_zlib_be.vtp"));
  REQUIRE(d.vertices.size() == 5);
  CHECK(d.vertices[4].z == 1.0 / 3.0);
  CHECK(d.triangles == std::vector<std::array<int, 3>>{{0, 1, 4}});
  CHECK(d.edges == std::vector<std::array<int, 2>>{{0, 1}, {1, 2}});
  // Cell order Lines then Polys: refs 4 (polyline), 6 (triangle), 0 (quad).
  CHECK(d.edge_refs == std::vector<int>{4, 4});
  CHECK(d.triangle_refs == std::vector<int>{6});
  CHECK(has_warning(d, "skipped 1 polygons of 4 vertices"));
  REQUIRE(d.fields.size() == 1);
  CHECK(d.fields[0].info.kind == FieldKind::Vector);
  CHECK(d.fields[0].values[14] == 14);
}

TEST_CASE("vtk xml: generated appended raw .vtu (UInt64 headers, Float32 points, 3x3 tensor, UInt16 refs)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_vtk_appended.vtu"));
  REQUIRE(d.vertices.size() == 4);
  CHECK(d.triangles.size() == 2);
  CHECK(d.triangle_refs == std::vector<int>{3, 65535});
  REQUIRE(d.fields.size() == 1);
  CHECK(d.fields[0].info.ncomp == 6);
  CHECK(std::vector<double>(d.fields[0].values.begin() + 18, d.fields[0].values.end()) ==
        std::vector<double>{2, 1, 2, 0, 0, 2});
}

TEST_CASE("legacy vtk: the writer's files read back exactly (refs, edges, fields, blanks in names become '_')") {
  const auto dir = test::temp_dir("vtk_legacy_roundtrip");
  MeshData d = test::roundtrip_mesh(false);
  const std::string path = (dir / "m.vtk").string();
  write_mesh_data(path, d);
  const MeshData back = read_mesh_data(path);
  d.fields[0].info.name = "pressure_p";
  test::check_same_mesh(d, back, false);
}

TEST_CASE("legacy vtk: hand-written UNSTRUCTURED_GRID (quad skipped, CellEntityIds, TENSORS, FIELD)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_legacy_ug.vtk"));
  REQUIRE(d.vertices.size() == 5);
  CHECK(d.triangles == std::vector<std::array<int, 3>>{{0, 1, 4}, {1, 2, 4}});
  CHECK(d.triangle_refs == std::vector<int>{1, 2});
  CHECK(d.edges == std::vector<std::array<int, 2>>{{3, 0}});
  CHECK(d.edge_refs == std::vector<int>{4});
  CHECK(has_warning(d, "skipped 1 cells of VTK type 9"));
  REQUIRE(d.fields.size() == 3);
  CHECK(d.fields[0].info.name == "h");
  CHECK(d.fields[1].info.kind == FieldKind::Tensor);
  CHECK(std::vector<double>(d.fields[1].values.begin() + 24, d.fields[1].values.end()) ==
        std::vector<double>{4, 1, 5, 0, 0, 6});
  CHECK(d.fields[2].info.name == "grad");
  CHECK(d.fields[2].info.kind == FieldKind::Vector);
  CHECK(d.fields[2].values[12] == 7);
}

TEST_CASE("legacy vtk: generated BINARY POLYDATA (big-endian)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_legacy_bin.vtk"));
  REQUIRE(d.vertices.size() == 4);
  CHECK(d.edges == std::vector<std::array<int, 2>>{{0, 1}});
  CHECK(d.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}});
  CHECK(d.edge_refs == std::vector<int>{1});
  CHECK(d.triangle_refs == std::vector<int>{2, 3});
  CHECK(d.vertex_refs == std::vector<int>{0, 5, 0, 0});
  REQUIRE(d.fields.size() == 1);
  CHECK(d.fields[0].values[11] == 11);
}
