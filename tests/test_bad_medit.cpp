// Broken Medit files (.mesh, .meshb, .sol, .solb) under tests/data/bad: each
// must be refused with an IoError naming the file, the place (line or byte)
// and what was expected; never a crash, never a hang.
#include <doctest/doctest.h>

#include <exception>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "io/mesh_io.h"
#include "mesh/mesh_data.h"
#include "test_util.h"

namespace {

struct BadCase {
  const char* file;
  const char* place;     // ":line:" or "byte N"
  const char* expected;  // words of the message that say what was expected
  int n_vertices = -1;   // .sol: the mesh's vertex count
};

const BadCase kCases[] = {
    {"bad_medit_truncated.mesh", ":7:", "vertex 3: expected z coordinate, found the end of the file"},
    {"bad_medit_wrong_count.mesh", ":9:", "vertex 5: expected x coordinate, found the keyword 'Triangles'"},
    {"bad_medit_index_range.mesh", ":12:", "triangle 2: vertex id 99 out of range 1..4"},
    {"bad_medit_index_zero.mesh", ":10:", "triangle 1: vertex id 0 out of range 1..3 (ids are 1-based)"},
    {"bad_medit_nan.mesh", ":6:", "vertex 2: y coordinate is not finite ('nan'), expected a finite number"},
    {"bad_medit_inf.mesh", ":7:", "vertex 3: x coordinate is not finite ('-inf'), expected a finite number"},
    {"bad_medit_no_dimension.mesh", ":2:", "Vertices section before 'Dimension', expected 'Dimension 2'"},
    {"bad_medit_keyword_order.mesh", ":1:", "expected 'MeshVersionFormatted' at the start"},
    {"bad_medit_non_numeric.mesh", ":7:", "vertex 3: expected z coordinate (a number), found 'O'"},
    {"bad_medit_negative_count.mesh", ":9:", "Triangles: negative count -1, expected a count >= 0"},
    {"bad_medit_extra_entries.mesh", ":7:", "expected a section keyword, found the number '0'"},
    {"bad_medit_ridge_range.mesh", ":6:", "ridge 2: edge id 3 out of range 1..2"},
    {"bad_medit_dimension.mesh", ":3:", "Dimension 4 unsupported, expected 2 or 3"},
    {"bad_medit_duplicate.mesh", ":6:", "second Vertices section (the first one is at line 3), expected each"},
    {"bad_medit_tetra_short.mesh", ":12:", "tetrahedron 2: expected a number, found the keyword 'Triangles'"},
    {"bad_meshb_truncated.meshb", "byte 32", "truncated file: Vertices announces 4 entries"},
    {"bad_meshb_magic.meshb", "byte 0", "not a Medit binary file: expected the code 1"},
    {"bad_meshb_version.meshb", "byte 4", ".meshb version 9 unsupported, expected 1, 2, 3 or 4"},
    {"bad_meshb_next_past_end.meshb", "byte 24", "next-keyword position 100000 is past the end of the file, expected at most 180"},
    {"bad_meshb_next_loop.meshb", "byte 40", "position 20 points backwards, expected a position after byte 36"},
    {"bad_meshb_index_range.meshb", "byte 176", "triangle 2: vertex id 9 out of range 1..4"},
    {"bad_meshb_nan.meshb", "byte 68", "vertex 2: y coordinate is not finite, expected a finite number"},
    {"bad_sol_size.sol", ":6:", "5 values but the mesh has 4 vertices (expected one value per vertex)", 4},
    {"bad_sol_type.sol", ":5:", "unknown solution type 7, expected 1 (scalar), 2 (vector) or 3 (symmetric tensor)"},
    {"bad_sol_nan.sol", ":7:", "vertex 2: field sol0 component 2 is not finite ('NaN'), expected a finite number"},
    {"bad_sol_negative_count.sol", ":4:", "SolAtVertices: negative count -4, expected a count >= 0"},
    {"bad_sol_truncated.sol", ":8:", "vertex 3: expected a value of field sol0, found the end of the file"},
    {"bad_sol_no_dimension.sol", ":2:", "SolAtVertices before 'Dimension', expected 'Dimension 2'"},
    {"bad_sol_truncated.solb", "byte 40", "truncated file: SolAtVertices announces 10 vertices"},
};

bool is_sol(const std::string& f) { return f.find(".sol") != std::string::npos; }

}  // namespace

TEST_CASE("broken Medit files are refused with file, place and what was expected") {
  for (const BadCase& c : kCases) {
    const std::string path = anisurf::test::data_file(std::string("bad/") + c.file);
    CAPTURE(path);
    std::string message;
    bool refused = false;
    try {
      if (is_sol(c.file))
        anisurf::read_sol(path, c.n_vertices);
      else
        anisurf::read_mesh_data(path);
    } catch (const anisurf::IoError& e) {
      refused = true;
      message = e.what();
    }
    CAPTURE(message);
    CHECK(refused);
    CHECK(message.find(c.file) != std::string::npos);
    CHECK(message.find(c.place) != std::string::npos);
    CHECK(message.find(c.expected) != std::string::npos);
  }
}

TEST_CASE("a .sol that matches no mesh size is refused only when a size is given") {
  const std::string path = anisurf::test::data_file("bad/bad_sol_size.sol");
  const auto fields = anisurf::read_sol(path, -1);
  REQUIRE(fields.size() == 1);
  CHECK(fields[0].values.size() == 5);
  CHECK_NOTHROW(anisurf::read_sol(path, 5));
}

namespace {

// Reads a Medit mesh or solution file; true if read, false if refused with an
// IoError. Any other exception fails the test.
bool read_or_refuse(const std::string& path) {
  try {
    if (is_sol(path))
      anisurf::read_sol(path, -1);
    else
      anisurf::read_mesh_data(path);
    return true;
  } catch (const anisurf::IoError&) {
    return false;
  } catch (const std::exception& e) {
    FAIL_CHECK("not an IoError: " << e.what());
    return false;
  }
}

}  // namespace

TEST_CASE("every truncation and single-byte corruption of Medit files is read or refused cleanly") {
  using namespace anisurf;
  const auto dir = test::temp_dir("bad_medit_fuzz");
  MeshData d;
  d.vertices = {{0, 0, 0}, {1, 0, 0.5}, {0, 1, 0.25}, {1, 1, 1}};
  d.triangles = {{0, 1, 2}, {1, 3, 2}};
  d.triangle_refs = {1, 2};
  d.edges = {{0, 1}, {1, 3}};
  d.ridges = {1};
  d.corners = {3};
  d.normals = {{0, 0, 1}};
  d.normal_at_vertex = {{2, 0}};
  FieldData metric;
  metric.info = {"metric", FieldKind::Tensor, 6};
  for (int i = 0; i < 24; ++i) metric.values.push_back(0.5 + i);
  const std::vector<std::string> names = {"m.mesh", "m.meshb", "m.sol", "m.solb"};
  for (const std::string& name : names) {
    const std::string good = (dir / name).string();
    if (is_sol(name))
      write_sol(good, {metric}, 4, 3);
    else
      write_mesh_data(good, d);
    REQUIRE(read_or_refuse(good));
    std::string bytes;
    {
      std::ifstream in(good, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string bad = (dir / ("x_" + name)).string();
    auto attempt = [&](const std::string& content) {
      std::ofstream(bad, std::ios::binary | std::ios::trunc).write(content.data(), static_cast<std::streamsize>(content.size()));
      return read_or_refuse(bad);
    };
    int refused = 0;
    for (std::size_t n = 0; n < bytes.size(); ++n) refused += attempt(bytes.substr(0, n)) ? 0 : 1;
    for (std::size_t i = 0; i < bytes.size(); ++i)
      for (char c : {'\0', '\xff', '9'}) {
        std::string copy = bytes;
        copy[i] = c;
        refused += attempt(copy) ? 0 : 1;
      }
    CAPTURE(name);
    CHECK(refused > static_cast<int>(bytes.size()) / 2);
  }
}
