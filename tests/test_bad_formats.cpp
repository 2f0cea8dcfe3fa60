// Broken OBJ / OFF / PLY / STL / glTF files (tests/data/bad/bad_{obj,off,ply,
// stl,gltf}_*): read_mesh_data refuses each with an IoError that names the
// file, the place (line for text, byte for binary) and what was expected.
// The binary ones come from tests/data/fmt_generate.py.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <string>

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
};

}  // namespace

TEST_CASE("bad formats: each broken OBJ/OFF/PLY/STL/glTF file gives an IoError with file, place and expectation") {
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

TEST_CASE("bad formats: every bad_{obj,off,ply,stl,gltf}_* file is covered by the table") {
  const std::string dir = test::data_file("bad");
  int found = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    bool ours = false;
    for (const char* prefix : {"bad_obj_", "bad_off_", "bad_ply_", "bad_stl_", "bad_gltf_"})
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
