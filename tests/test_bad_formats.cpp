// Broken OBJ / OFF / PLY / STL / glTF / Gmsh / VTK files (tests/data/bad/
// bad_{obj,off,ply,stl,gltf,msh,vtu,vtp,vtk}_*): read_mesh_data refuses each
// with an IoError that names the file, the place (line for text, byte for
// binary) and what was expected. The binary ones come from
// tests/data/fmt_generate.py and tests/data/fmt_generate_vtk.py.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/mesh_io.h"
#include "test_util.h"

using namespace anisurf;

namespace {

struct BadCase {
  const char* file;
  const char* where;     // ":<line>:" for text files, "byte <n>" for binary ones
  const char* expected;  // what the message says was expected
};

const BadCase kBad[] = {
    {"bad_obj_index_range.obj", ":5:", "expected 1..3"},
    {"bad_obj_index_zero.obj", ":4:", "indices start at 1"},
    {"bad_obj_non_numeric.obj", ":3:", "expected vertex y coordinate, found 'abc'"},
    {"bad_obj_nan.obj", ":3:", "not a finite number"},
    {"bad_obj_face_short.obj", ":4:", "expected at least 3"},
    {"bad_obj_negative_range.obj", ":4:", "expected -3..-1"},
    {"bad_off_header.off", ":1:", "expected OFF header"},
    {"bad_off_few_vertices.off", ":8:", "expected more face lines"},
    {"bad_off_face_count.off", ":7:", "has 2 vertices, expected at least 3"},
    {"bad_off_index_range.off", ":6:", "vertex index 3 out of range, expected 0..2"},
    {"bad_off_huge_count.off", ":2:", "vertex count 2000000000 impossible"},
    {"bad_ply_truncated.ply", "byte 527", "truncated file, expected face vertex index"},
    {"bad_ply_unknown_format.ply", ":2:", "expected format ascii, binary_little_endian or binary_big_endian"},
    {"bad_ply_no_indices.ply", ":7:", "expected 'property list uchar int vertex_indices'"},
    {"bad_ply_index_range.ply", ":14:", "vertex index 7 out of range, expected 0..2"},
    {"bad_ply_missing_faces.ply", ":13:", "unexpected end of file, expected list count"},
    {"bad_ply_huge_count.ply", ":3:", "announces 2000000000 entries"},
    {"bad_stl_truncated.stl", "byte 80", "expected 184 bytes"},
    {"bad_stl_missing_endloop.stl", ":7:", "expected 'endloop'"},
    {"bad_stl_missing_vertex.stl", ":6:", "expected 'vertex'"},
    {"bad_gltf_json.gltf", "line 4", "expected ']'"},
    {"bad_gltf_accessor_range.gltf", "accessor 0", "exceed buffer view 0"},
    {"bad_gltf_truncated.glb", "byte 8", "expected the whole file"},
    {"bad_gltf_version.glb", "byte 4", "expected 2"},
    {"bad_msh_version.msh", ":2:", "expected MSH version 2.2 or 4.1, found '3.0'"},
    {"bad_msh_node_tag.msh", "element 2", "node tag 9 not in $Nodes"},
    {"bad_msh_nan.msh", ":11:", "node y coordinate is not a finite number"},
    {"bad_msh_missing_end.msh", ":9:", "expected '$EndNodes', found '4'"},
    {"bad_msh_truncated.msh", "byte 55", "node count 3 impossible"},
    {"bad_msh_huge_count.msh", ":6:", "node count 2000000000 impossible"},
    {"bad_vtu_appended_size.vtu", ":15:", "data array 'connectivity' of 56 bytes, expected 48"},
    {"bad_vtu_index_range.vtu", ":9:", "point id 7 out of range, expected 0..2"},
    {"bad_vtu_xml.vtu", ":7:", "expected </Points>, found </Cells>"},
    {"bad_vtu_zlib_block.vtu", ":7:", "zlib block 0 is corrupt"},
    {"bad_vtp_huge_count.vtp", ":4:", "NumberOfPoints 2000000000000 impossible"},
    {"bad_vtp_offsets.vtp", ":10:", "Polys offset 6 of cell 0 out of order"},
    {"bad_vtk_huge_count.vtk", ":5:", "point coordinate count 6000000000 impossible"},
    {"bad_vtk_index_range.vtk", ":8:", "POLYGONS: point id 3 out of range, expected 0..2"},
    {"bad_vtk_keyword.vtk", ":7:", "expected a legacy VTK keyword"},
    {"bad_vtk_truncated.vtk", "byte 137", "cell entry count 3 impossible"},
};

}  // namespace

TEST_CASE("bad formats: each broken OBJ/OFF/PLY/STL/glTF/MSH/VTK file gives an IoError with file, place and expectation") {
  for (const BadCase& c : kBad) {
    const std::string file = c.file;
    CAPTURE(file);
    const std::string path = test::data_file(std::string("bad/") + c.file);
    REQUIRE(std::filesystem::exists(path));
    std::string message;
    try {
      read_mesh_data(path);
    } catch (const IoError& e) {
      message = e.what();
    }
    CAPTURE(message);
    REQUIRE_FALSE(message.empty());  // threw an IoError (anything else fails the test)
    CHECK(message.find(c.file) != std::string::npos);
    CHECK(message.find(c.where) != std::string::npos);
    CHECK(message.find(c.expected) != std::string::npos);
  }
}

TEST_CASE("bad formats: every bad_{obj,off,ply,stl,gltf,msh,vtu,vtp,vtk}_* file is covered by the table") {
  const std::string dir = test::data_file("bad");
  int found = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    bool ours = false;
    for (const char* prefix :
         {"bad_obj_", "bad_off_", "bad_ply_", "bad_stl_", "bad_gltf_", "bad_msh_", "bad_vtu_", "bad_vtp_", "bad_vtk_"})
      ours |= name.rfind(prefix, 0) == 0;
    if (!ours) continue;
    ++found;
    bool listed = false;
    for (const BadCase& c : kBad) listed |= name == c.file;
    CAPTURE(name);
    CHECK(listed);
  }
  CHECK(found == static_cast<int>(sizeof kBad / sizeof kBad[0]));
}

TEST_CASE("bad formats: truncating a good binary file at any byte never crashes") {
  // Every prefix of a small binary PLY and GLB either reads or throws IoError.
  for (std::string good : {"fmt_be.ply", "fmt_triangle.glb"}) {
    CAPTURE(good);
    const std::string src = test::data_file(good);
    const auto size = std::filesystem::file_size(src);
    auto dir = test::temp_dir("bad_prefix");
    const std::string ext = std::filesystem::path(src).extension().string();
    std::string bytes(size, '\0');
    {
      std::FILE* f = std::fopen(src.c_str(), "rb");
      REQUIRE(f);
      REQUIRE(std::fread(bytes.data(), 1, size, f) == size);
      std::fclose(f);
    }
    int refused = 0;
    for (std::size_t n = 0; n < size; ++n) {
      const std::string cut = (dir / ("cut" + ext)).string();
      std::FILE* f = std::fopen(cut.c_str(), "wb");
      REQUIRE(f);
      std::fwrite(bytes.data(), 1, n, f);
      std::fclose(f);
      try {
        read_mesh_data(cut);
      } catch (const IoError&) {
        ++refused;
      }
    }
    CHECK(refused == static_cast<int>(size));  // no strict prefix is a valid file here
  }
}

TEST_CASE("bad formats: every prefix of binary MSH and VTK files reads or throws IoError") {
  // The writers' binary layouts and the generated samples, cut at every byte.
  const auto dir = test::temp_dir("bad_prefix_msh_vtk");
  std::vector<std::string> sources = {test::data_file("fmt_vtk_zlib_be.vtp"), test::data_file("fmt_vtk_appended.vtu"),
                                      test::data_file("fmt_legacy_bin.vtk")};
  MeshData d;
  d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  d.triangles = {{0, 1, 2}};
  d.triangle_refs = {4};
  FieldData s;
  s.info = FieldInfo{"s", FieldKind::Scalar, 1};
  s.values = {1, 2, 3};
  d.fields.push_back(s);
  for (int version : {22, 41}) {
    WriteOptions o;
    o.msh_version = version;
    sources.push_back((dir / (version == 22 ? "src22.msh" : "src41.msh")).string());
    write_mesh_data(sources.back(), d, o);
  }
  WriteOptions z;
  z.vtk_compress = true;
  sources.push_back((dir / "srcz.vtu").string());
  write_mesh_data(sources.back(), d, z);
  for (const std::string& src : sources) {
    CAPTURE(src);
    std::string bytes;
    {
      std::FILE* f = std::fopen(src.c_str(), "rb");
      REQUIRE(f);
      char buf[4096];
      std::size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, n);
      std::fclose(f);
    }
    const std::string cut = (dir / ("cut" + std::filesystem::path(src).extension().string())).string();
    int refused = 0;
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      std::FILE* f = std::fopen(cut.c_str(), "wb");
      REQUIRE(f);
      std::fwrite(bytes.data(), 1, n, f);
      std::fclose(f);
      try {
        read_mesh_data(cut);
      } catch (const IoError&) {
        ++refused;
      }
    }
    CHECK(refused > static_cast<int>(bytes.size()) / 2);
  }
}
