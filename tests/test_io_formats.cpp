// OBJ, OFF, PLY, STL and glTF: round trips through write_mesh_data /
// read_mesh_data (bit-exact doubles where the format stores them), the
// hand-made fmt_* files that exercise each syntax, and the third-party meshes
// of ../shared/meshes against the counts of SOURCES.md section 2.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// Same bits (tells 0.0 from -0.0, compares denormals exactly).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }
double as_float(double x) { return static_cast<double>(static_cast<float>(x)); }

// Coordinates that a "%g" writer would not round-trip: thirds, a denormal,
// huge and tiny magnitudes, negative zero, 17-digit values.
MeshData awkward_mesh() {
  MeshData d;
  const double third = 1.0 / 3.0;
  d.vertices = {{third, -2.0 / 3.0, 0.1},
                {1e300, -1e-300, 4.9406564584124654e-324},
                {-0.0, 3.141592653589793, 2.718281828459045},
                {123456789.12345679, -9.999999999999999e22, 0.30000000000000004},
                {1.0, 1.0 + std::numeric_limits<double>::epsilon(), -1.0}};
  d.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 3, 4}, {4, 2, 0}};
  return d;
}

// A small closed mesh (octahedron) with references, for the PLY round trips.
MeshData octahedron_with_refs() {
  MeshData d;
  const double a = 1.0 / 7.0;
  d.vertices = {{a, 0, 0}, {-a, 0, 0}, {0, a * 3, 0}, {0, -a * 3, 0}, {0, 0, std::sqrt(2.0)}, {0, 0, -std::sqrt(2.0)}};
  d.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  d.vertex_refs = {1, 2, 3, -4, 2147483647, 0};
  d.triangle_refs = {10, 11, 12, 13, -2147483647, 15, 16, 0};
  return d;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint32_t le32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
  return v;
}

void require_valid(const SurfaceMesh& m) {
  auto r = m.validate();
  INFO(r.summary());
  REQUIRE(r.ok());
}

}  // namespace

TEST_CASE("io formats: OBJ round trip is bit-exact") {
  auto dir = test::temp_dir("fmt_obj");
  const MeshData in = awkward_mesh();
  const std::string path = (dir / "m.obj").string();
  write_mesh_data(path, in);
  const MeshData out = read_mesh_data(path);
  REQUIRE(out.vertices.size() == in.vertices.size());
  for (std::size_t i = 0; i < in.vertices.size(); ++i) CHECK(same_bits(out.vertices[i], in.vertices[i]));
  CHECK(out.triangles == in.triangles);
  CHECK(out.warnings.empty());
  CHECK_FALSE(out.split_vertices);
}

TEST_CASE("io formats: PLY round trips (ascii, binary little and big endian) keep doubles and refs") {
  auto dir = test::temp_dir("fmt_ply");
  for (MeshData in : {awkward_mesh(), octahedron_with_refs()}) {
    struct Variant {
      const char* name;
      bool binary, big;
    };
    for (Variant v : {Variant{"ascii", false, false}, Variant{"le", true, false}, Variant{"be", true, true}}) {
      const std::string variant = v.name;
      CAPTURE(variant);
      const std::string path = (dir / (std::string(v.name) + ".ply")).string();
      WriteOptions opt;
      opt.binary = v.binary;
      opt.big_endian = v.big;
      write_mesh_data(path, in, opt);
      const std::string head = read_bytes(path).substr(0, 60);
      CHECK(head.find(!v.binary ? "format ascii 1.0" : v.big ? "format binary_big_endian 1.0"
                                                              : "format binary_little_endian 1.0") !=
            std::string::npos);
      const MeshData out = read_mesh_data(path);
      REQUIRE(out.vertices.size() == in.vertices.size());
      for (std::size_t i = 0; i < in.vertices.size(); ++i) CHECK(same_bits(out.vertices[i], in.vertices[i]));
      CHECK(out.triangles == in.triangles);
      CHECK(out.vertex_refs == in.vertex_refs);
      CHECK(out.triangle_refs == in.triangle_refs);
    }
  }
}

TEST_CASE("io formats: STL round trips (ascii and binary) are exact at float precision") {
  auto dir = test::temp_dir("fmt_stl");
  // 1e300 does not fit a float: keep a mesh whose coordinates do.
  MeshData fits = octahedron_with_refs();
  fits.vertex_refs.clear();
  fits.triangle_refs.clear();
  fits.vertices[0] = {1.0 / 3.0, 0.1, -0.0};
  for (bool binary : {false, true}) {
    CAPTURE(binary);
    const std::string path = (dir / (binary ? "b.stl" : "a.stl")).string();
    WriteOptions opt;
    opt.binary = binary;
    write_mesh_data(path, fits, opt);
    if (binary) CHECK(std::filesystem::file_size(path) == 84 + 50 * fits.triangles.size());
    const MeshData out = read_mesh_data(path);
    CHECK(out.split_vertices);
    REQUIRE(out.triangles.size() == fits.triangles.size());
    REQUIRE(out.vertices.size() == 3 * fits.triangles.size());
    for (std::size_t t = 0; t < fits.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = fits.vertices[static_cast<std::size_t>(fits.triangles[t][k])];
        const Vec3& q = out.vertices[static_cast<std::size_t>(out.triangles[t][k])];
        CHECK(same_bits(q, Vec3(as_float(p.x), as_float(p.y), as_float(p.z))));
      }
    // Welding the corners gives back the octahedron.
    SurfaceMesh m;
    build_mesh(out, m);
    require_valid(m);
    CHECK(m.n_vertices() == 6);
    CHECK(m.n_triangles() == 8);
  }
}

TEST_CASE("io formats: a binary STL whose header begins with 'solid' is read as binary") {
  auto dir = test::temp_dir("fmt_stl_solid");
  const std::string path = (dir / "s.stl").string();
  MeshData in = octahedron_with_refs();
  WriteOptions opt;
  opt.binary = true;
  write_mesh_data(path, in, opt);
  std::string bytes = read_bytes(path);
  bytes.replace(0, 12, "solid object");
  write_bytes(path, bytes);
  const MeshData out = read_mesh_data(path);
  CHECK(out.triangles.size() == 8);
  CHECK(out.vertices.size() == 24);
}

TEST_CASE("io formats: glb round trip at float precision, valid GLB container") {
  auto dir = test::temp_dir("fmt_glb");
  MeshData in = octahedron_with_refs();
  in.vertex_refs.clear();
  in.triangle_refs.clear();
  in.vertices[0] = {1.0 / 3.0, 0.1, 1e-3};
  const std::string path = (dir / "o.glb").string();
  write_mesh_data(path, in);

  const std::string bytes = read_bytes(path);
  REQUIRE(bytes.size() >= 28);
  CHECK(bytes.substr(0, 4) == "glTF");
  CHECK(le32(bytes, 4) == 2);
  CHECK(le32(bytes, 8) == bytes.size());
  const std::uint32_t json_len = le32(bytes, 12);
  CHECK(json_len % 4 == 0);
  CHECK(bytes.substr(16, 4) == "JSON");
  const std::string json = bytes.substr(20, json_len);
  CHECK(json.find("\"version\":\"2.0\"") != std::string::npos);
  REQUIRE(20 + json_len + 8 <= bytes.size());
  CHECK(le32(bytes, 20 + json_len) % 4 == 0);
  CHECK(bytes.substr(20 + json_len + 4, 4) == std::string("BIN\0", 4));
  CHECK(20 + json_len + 8 + le32(bytes, 20 + json_len) == bytes.size());

  // Read back through tinygltf (the glTF reader).
  const MeshData out = read_mesh_data(path);
  CHECK(out.split_vertices);
  REQUIRE(out.vertices.size() == in.vertices.size());
  for (std::size_t i = 0; i < in.vertices.size(); ++i) {
    const Vec3& p = in.vertices[i];
    CHECK(same_bits(out.vertices[i], Vec3(as_float(p.x), as_float(p.y), as_float(p.z))));
  }
  CHECK(out.triangles == in.triangles);
}

TEST_CASE("io formats: writers refuse out-of-range ids and empty glb") {
  auto dir = test::temp_dir("fmt_refuse");
  MeshData bad = octahedron_with_refs();
  bad.triangles[3][1] = 6;
  for (std::string name : {"x.obj", "x.ply", "x.stl", "x.glb"}) {
    CAPTURE(name);
    const std::string path = (dir / name).string();
    CHECK_THROWS_AS(write_mesh_data(path, bad), IoError);
    CHECK_FALSE(std::filesystem::exists(path));
  }
  CHECK_THROWS_AS(write_mesh_data((dir / "empty.glb").string(), MeshData{}), IoError);
  // 1e300 has no float: STL and glb refuse it rather than writing infinity.
  CHECK_THROWS_AS(write_mesh_data((dir / "big.stl").string(), awkward_mesh()), IoError);
  CHECK_THROWS_AS(write_mesh_data((dir / "big.glb").string(), awkward_mesh()), IoError);
}

TEST_CASE("io formats: OBJ syntax (a/b/c, negative indices, polygons, ignored statements)") {
  const MeshData d = read_mesh_data(test::data_file("fmt_poly.obj"));
  REQUIRE(d.vertices.size() == 11);
  REQUIRE(d.triangles.size() == 6 * 2 + 1);
  // "f 1 4 3 2" fan-triangulated, 0-based.
  CHECK(d.triangles[0] == std::array<int, 3>{0, 3, 2});
  CHECK(d.triangles[1] == std::array<int, 3>{0, 2, 1});
  // "f 5/1 6/2 7/3 8/1", "f 2/1/1 ..." and "f 1//1 ..." keep the vertex part.
  CHECK(d.triangles[2] == std::array<int, 3>{4, 5, 6});
  CHECK(d.triangles[4] == std::array<int, 3>{0, 1, 5});
  CHECK(d.triangles[6] == std::array<int, 3>{1, 2, 6});
  // "f -3 -2 -1" after 11 vertices.
  CHECK(d.triangles.back() == std::array<int, 3>{8, 9, 10});
  // "v 1 0 0 1.0" (w) and "v 1 1 0 0.5 0.5 0.5" (colour): xyz only.
  CHECK(d.vertices[1] == Vec3(1, 0, 0));
  CHECK(d.vertices[2] == Vec3(1, 1, 0));
  // One warning for the unknown statement ('curv'), none for vt/vn/g/o/s/l/usemtl/mtllib.
  REQUIRE(d.warnings.size() == 1);
  CHECK(d.warnings[0].find("curv") != std::string::npos);
  SurfaceMesh m;
  build_mesh(d, m);
  require_valid(m);
}

TEST_CASE("io formats: NOFF with normals, comments, blank lines, polygon and face colours") {
  const MeshData d = read_mesh_data(test::data_file("fmt_noff.off"));
  REQUIRE(d.vertices.size() == 5);
  CHECK(d.vertices[4] == Vec3(0.5, 0.5, 1));
  REQUIRE(d.triangles.size() == 2 + 4);
  CHECK(d.triangles[0] == std::array<int, 3>{0, 3, 2});
  CHECK(d.triangles[1] == std::array<int, 3>{0, 2, 1});
  CHECK(d.triangles[5] == std::array<int, 3>{3, 0, 4});
  SurfaceMesh m;
  auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(m.n_vertices() == 5);
  CHECK(rep.flipped_triangles == 0);
}

TEST_CASE("io formats: PLY element order, property types, refs, vertex_index, skipped elements") {
  // The ascii file and the big-endian file describe the same kind of content.
  SUBCASE("ascii") {
    const MeshData d = read_mesh_data(test::data_file("fmt_elements.ply"));
    REQUIRE(d.vertices.size() == 5);
    CHECK(d.vertices[2] == Vec3(1, 1.25, 0));
    CHECK(d.vertices[4] == Vec3(0.5, 0.5, 1));
    CHECK(d.vertex_refs == std::vector<int>{1, 2, 3, 4, -4});
    REQUIRE(d.triangles.size() == 3);
    CHECK(d.triangles[0] == std::array<int, 3>{0, 1, 2});
    CHECK(d.triangles[1] == std::array<int, 3>{0, 2, 3});
    CHECK(d.triangles[2] == std::array<int, 3>{0, 4, 1});
    CHECK(d.triangle_refs == std::vector<int>{11, 11, -12});
  }
  SUBCASE("binary big endian") {
    const MeshData d = read_mesh_data(test::data_file("fmt_be.ply"));
    REQUIRE(d.vertices.size() == 5);
    CHECK(same_bits(d.vertices[2].y, 1.0 / 3.0));  // a double property
    CHECK(d.vertices[2].x == 1.0);                 // a float property
    CHECK(d.vertices[4].z == 2.0);                 // an int property
    CHECK(d.vertex_refs == std::vector<int>{10, 11, 12, 13, 14});
    REQUIRE(d.triangles.size() == 3);
    CHECK(d.triangles[1] == std::array<int, 3>{0, 2, 3});
    CHECK(d.triangles[2] == std::array<int, 3>{0, 4, 1});
    CHECK(d.triangle_refs == std::vector<int>{5, 5, 6});
  }
}

TEST_CASE("io formats: ASCII STL with several solids and upper-case keywords") {
  const MeshData d = read_mesh_data(test::data_file("fmt_tetra.stl"));
  CHECK(d.split_vertices);
  REQUIRE(d.triangles.size() == 4);
  REQUIRE(d.vertices.size() == 12);
  CHECK(d.vertices[11] == Vec3(0, 0, 1.5));
  SurfaceMesh m;
  auto rep = build_mesh(d, m);
  require_valid(m);
  CHECK(rep.input_vertices - rep.merged_vertices == 5);  // (0,0,1) and (0,0,1.5) differ: an open surface
}

TEST_CASE("io formats: glTF node transforms, instancing, strips, fans, stride, points skipped") {
  const MeshData d = read_mesh_data(test::data_file("fmt_scene.gltf"));
  CHECK(d.split_vertices);
  // Mesh 0 (strip, 4 vertices) under two nodes, mesh 1 (fan) under one; the
  // node of mesh 2 is not in the scene.
  REQUIRE(d.vertices.size() == 12);
  REQUIRE(d.triangles.size() == 6);
  auto near = [](const Vec3& a, const Vec3& b) { return norm(a - b) < 1e-12; };
  // node 1: translate (10,0,0) * scale 2
  CHECK(near(d.vertices[3], {12, 2, 0}));
  // node 2: translate (10,0,0) * rotate 90 degrees about z: (1,0,0) -> (0,1,0)
  CHECK(near(d.vertices[5], {10, 1, 0}));
  CHECK(near(d.vertices[6], {9, 0, 0}));
  // node 3: matrix with translation (0,0,5)
  CHECK(near(d.vertices[11], {1, 1, 5}));
  // strip: (0,1,2), (1,3,2) (odd triangle keeps the winding); fan: (1,3,0), (3,2,0).
  CHECK(d.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(d.triangles[1] == std::array<int, 3>{1, 3, 2});
  CHECK(d.triangles[4] == std::array<int, 3>{9, 11, 8});
  CHECK(d.triangles[5] == std::array<int, 3>{11, 10, 8});
  // the points primitive (twice instanced) is reported once
  bool warned = false;
  for (const auto& w : d.warnings) warned |= w.find("points") != std::string::npos;
  CHECK(warned);
  // every triangle faces +z like the square it comes from
  for (const auto& t : d.triangles) {
    Vec3 n = cross(d.vertices[static_cast<std::size_t>(t[1])] - d.vertices[static_cast<std::size_t>(t[0])],
                   d.vertices[static_cast<std::size_t>(t[2])] - d.vertices[static_cast<std::size_t>(t[0])]);
    CHECK(n.z > 0);
  }
}

TEST_CASE("io formats: minimal glb") {
  const MeshData d = read_mesh_data(test::data_file("fmt_triangle.glb"));
  REQUIRE(d.vertices.size() == 3);
  REQUIRE(d.triangles.size() == 1);
  CHECK(d.vertices[1] == Vec3(1, 0, 0));
}

namespace {

struct SharedCase {
  const char* file;
  std::size_t vertices;   // in the file (STL: 3 per facet; glTF: per primitive instance)
  std::size_t triangles;
  int unique_positions;   // after merging identical positions
};

// SOURCES.md section 2 (STL "vertices" there are the merged corners).
const SharedCase kShared[] = {
    {"meshes/bunny.off", 3485, 6966, 3485},
    {"meshes/fandisk.off", 7229, 14454, 7229},
    {"meshes/camelhead.off", 11381, 22704, 11381},
    {"meshes/beetle.off", 19887, 38656, 19885},
    {"meshes/spot.obj", 2930, 5856, 2930},
    {"meshes/bun_zipper_res2.ply", 8171, 16301, 8171},
    {"meshes/fixed_top.ply", 2374, 4772, 2374},
    {"meshes/featuretype.STL", 3 * 3476, 3476, 2010},
    {"meshes/torus.STL", 3 * 8700, 8700, 4350},
    {"meshes/Box.glb", 24, 12, 8},
    {"meshes/Duck.glb", 2399, 4212, 2108},
    {"meshes/Suzanne.gltf", 11808, 3936, 2012},
    {"meshes/Avocado.gltf", 406, 682, 363},
};

}  // namespace

TEST_CASE("io formats: third-party meshes have the file-level counts of SOURCES.md") {
  ANISURF_REQUIRE_SHARED(probe, "meshes/SOURCES.md");
  for (const SharedCase& c : kShared) {
    const std::string file = c.file;
    CAPTURE(file);
    const std::string path = test::shared_file(file);
    REQUIRE_FALSE(path.empty());
    const MeshData d = read_mesh_data(path);
    CHECK(d.vertices.size() == c.vertices);
    CHECK(d.triangles.size() == c.triangles);
    bool ids_ok = true, finite = true;
    for (const auto& t : d.triangles)
      for (int id : t) ids_ok &= id >= 0 && static_cast<std::size_t>(id) < d.vertices.size();
    for (const Vec3& p : d.vertices) finite &= std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    CHECK(ids_ok);
    CHECK(finite);
  }
}

TEST_CASE("io formats: third-party meshes build with the unique positions of SOURCES.md") {
  ANISURF_REQUIRE_SHARED(probe, "meshes/SOURCES.md");
  for (const SharedCase& c : kShared) {
    const std::string file = c.file;
    CAPTURE(file);
    const MeshData d = read_mesh_data(test::shared_file(file));
    SurfaceMesh m;
    BuildOptions opt;
    opt.merge = BuildOptions::Merge::Always;
    opt.merge_tolerance = 0;  // SOURCES.md merges identical positions only
    const BuildReport rep = build_mesh(d, m, opt, c.file);
    require_valid(m);
    CHECK(rep.input_vertices - rep.merged_vertices == c.unique_positions);
  }
}

TEST_CASE("io formats: glTF samples weld into closed meshes with the default build") {
  ANISURF_REQUIRE_SHARED(box, "meshes/Box.glb");
  ANISURF_REQUIRE_SHARED(duck, "meshes/Duck.glb");
  for (const std::string& path : {box, duck}) {
    CAPTURE(path);
    const MeshData d = read_mesh_data(path);
    SurfaceMesh m;
    build_mesh(d, m);
    require_valid(m);
    CHECK(m.n_vertices() == (path == box ? 8 : 2108));
    for (int v = 0; v < m.vertex_capacity(); ++v)
      if (!m.is_deleted(Vertex(v))) REQUIRE_FALSE(m.is_boundary(Vertex(v)));
  }
}

TEST_CASE("io formats: Duck.glb has the 0.01 scale of its root node applied") {
  ANISURF_REQUIRE_SHARED(duck, "meshes/Duck.glb");
  const MeshData d = read_mesh_data(duck);
  BBox b;
  for (const Vec3& p : d.vertices) b.add(p);
  // The raw positions span about 165 x 154 x 115 units; scaled: metres.
  const Vec3 size = b.hi - b.lo;
  CHECK(size.x > 1.0);
  CHECK(size.x < 2.0);
  CHECK(size.y > 1.0);
  CHECK(size.y < 2.0);
  CHECK(size.z > 0.8);
  CHECK(size.z < 1.5);
}
