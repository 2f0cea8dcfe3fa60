// Medit .mesh / .meshb readers and writers, the legacy VTK writer and the
// format dispatch of mesh_io: bit-exact round trips, the layouts met in real
// files (Mmg, libMeshb versions 1-4, both byte orders), the shared meshes.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/formats.h"
#include "io/mesh_io.h"
#include "io/parallel_lines.h"
#include "io/text_reader.h"
#include "mesh/build.h"
#include "test_util.h"

using namespace anisurf;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_points(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i].x, b[i].x) || !same_bits(a[i].y, b[i].y) || !same_bits(a[i].z, b[i].z)) return false;
  return true;
}

// A small mesh with every Medit section and coordinates that need all 17
// significant digits (or are subnormal, huge, negative zero).
MeshData rich_mesh(int dim) {
  MeshData d;
  d.dimension = dim;
  const double v[] = {0.1, 1.0 / 3.0, -2.5e-310, 1e300, 6.02214076e23, -0.0, 3.141592653589793,
                      123456789.12345679, 5e-324, -1.7976931348623157e308, 2.0 / 7.0, 1e-7};
  for (int i = 0; i < 8; ++i)
    d.vertices.push_back({v[i % 12], v[(i + 3) % 12], dim == 3 ? v[(i + 7) % 12] : 0.0});
  d.vertex_refs = {0, 1, -2, 3, 40, 5, 6, 2147483647};
  d.triangles = {{0, 1, 2}, {2, 3, 0}, {4, 5, 6}, {6, 7, 4}, {1, 5, 6}};
  d.triangle_refs = {1, 1, 2, -3, 7};
  d.edges = {{0, 1}, {1, 2}, {4, 5}};
  d.edge_refs = {10, 0, -1};
  d.corners = {0, 4};
  d.ridges = {0, 2};
  d.required_vertices = {7};
  d.required_edges = {1};
  d.required_triangles = {0, 4};
  d.normals = {{0.6, 0.8, dim == 3 ? 1.0 / 3.0 : 0.0}, {-1, 0, 0}};
  d.normal_at_vertex = {{0, 0}, {5, 1}};
  d.tangents = {{1.0 / 7.0, 0.25, 0}};
  d.tangent_at_vertex = {{1, 0}};
  return d;
}

void check_same(const MeshData& a, const MeshData& b) {
  CHECK(a.dimension == b.dimension);
  CHECK(same_points(a.vertices, b.vertices));
  CHECK(a.vertex_refs == b.vertex_refs);
  CHECK(a.triangles == b.triangles);
  CHECK(a.triangle_refs == b.triangle_refs);
  CHECK(a.edges == b.edges);
  CHECK(a.edge_refs == b.edge_refs);
  CHECK(a.corners == b.corners);
  CHECK(a.ridges == b.ridges);
  CHECK(a.required_vertices == b.required_vertices);
  CHECK(a.required_edges == b.required_edges);
  CHECK(a.required_triangles == b.required_triangles);
  CHECK(same_points(a.normals, b.normals));
  CHECK(a.normal_at_vertex == b.normal_at_vertex);
  CHECK(same_points(a.tangents, b.tangents));
  CHECK(a.tangent_at_vertex == b.tangent_at_vertex);
}

std::string write_text(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has_warning(const MeshData& d, const std::string& words) {
  return std::any_of(d.warnings.begin(), d.warnings.end(),
                     [&](const std::string& w) { return w.find(words) != std::string::npos; });
}

// An independent writer of GMF binary files (libMeshb layout) for the reader
// tests: any version 1-4, either byte order.
class GmfBytes {
 public:
  GmfBytes(int version, bool swap) : version_(version), swap_(swap) {
    i32(1);
    i32(version);
  }
  void i32(std::int32_t v) { raw(&v, 4); }
  void integer(long long v) {
    if (version_ >= 4) {
      std::int64_t x = v;
      raw(&x, 8);
    } else {
      i32(static_cast<std::int32_t>(v));
    }
  }
  void real(double v) {
    if (version_ == 1) {
      float f = static_cast<float>(v);
      raw(&f, 4);
    } else {
      raw(&v, 8);
    }
  }
  // Keyword code, a placeholder for the next position, the count if >= 0.
  std::size_t keyword(int code, long long count) {
    i32(code);
    const std::size_t slot = bytes.size();
    if (version_ >= 3) {
      std::int64_t z = 0;
      raw(&z, 8);
    } else {
      i32(0);
    }
    if (count >= 0) integer(count);
    return slot;
  }
  // Writes the current end of the data as the next position of a keyword.
  void patch(std::size_t slot) {
    const std::string end = bytes;
    bytes.clear();
    if (version_ >= 3) {
      std::int64_t p = static_cast<std::int64_t>(end.size());
      raw(&p, 8);
    } else {
      i32(static_cast<std::int32_t>(end.size()));
    }
    const std::string pos = bytes;
    bytes = end;
    bytes.replace(slot, pos.size(), pos);
  }
  std::string bytes;

 private:
  void raw(const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    std::string s(c, n);
    if (swap_) std::reverse(s.begin(), s.end());
    bytes += s;
  }
  int version_;
  bool swap_;
};

// A 2x1 square made of 2 triangles + 1 quadrilateral, with a skipped
// tetrahedron and an unknown keyword, in GMF version `version`.
std::string gmf_sample(int version, bool swap) {
  GmfBytes g(version, swap);
  std::size_t s = g.keyword(3, -1);
  g.i32(3);
  g.patch(s);
  const double p[6][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0.5}, {0, 1, 0.25}, {1, 1, -0.75}, {2, 1, 0.125}};
  s = g.keyword(4, 6);
  for (int i = 0; i < 6; ++i) {
    for (double x : p[i]) g.real(x);
    g.integer(i + 10);
  }
  g.patch(s);
  s = g.keyword(120, 2);  // not a keyword of this reader: skipped through its next position
  g.integer(77);
  g.integer(78);
  g.patch(s);
  s = g.keyword(6, 2);
  for (int t : {1, 2, 5, 1, 1, 5, 4, 4}) g.integer(t);  // two triangles with refs 1 and 4
  g.patch(s);
  s = g.keyword(7, 1);
  for (int q : {2, 3, 6, 5, 9}) g.integer(q);
  g.patch(s);
  s = g.keyword(8, 1);
  for (int q : {1, 2, 4, 6, 0}) g.integer(q);
  g.patch(s);
  s = g.keyword(5, 1);
  for (int e : {1, 2, 3}) g.integer(e);
  g.patch(s);
  s = g.keyword(14, 1);
  g.integer(1);
  g.patch(s);
  s = g.keyword(60, 1);
  for (double x : {0.0, 0.0, 1.0}) g.real(x);
  g.patch(s);
  s = g.keyword(20, 1);
  g.integer(6);
  g.integer(1);
  g.patch(s);
  s = g.keyword(59, 1);
  for (double x : {1.0, 0.0, 0.0}) g.real(x);
  g.patch(s);
  s = g.keyword(61, 1);
  g.integer(2);
  g.integer(1);
  g.patch(s);
  g.keyword(54, -1);
  return g.bytes;
}

}  // namespace

TEST_CASE("medit ascii round trip is bit-exact (3D and 2D)") {
  const auto dir = test::temp_dir("medit_ascii");
  for (int dim : {3, 2}) {
    CAPTURE(dim);
    const MeshData in = rich_mesh(dim);
    const std::string a = (dir / (std::string("a") + std::to_string(dim) + ".mesh")).string();
    const std::string b = (dir / (std::string("b") + std::to_string(dim) + ".mesh")).string();
    write_mesh_data(a, in);
    const MeshData out = read_mesh_data(a);
    check_same(in, out);
    CHECK(out.version == 2);
    CHECK(out.warnings.empty());
    write_mesh_data(b, out);
    CHECK(slurp(a) == slurp(b));
  }
}

TEST_CASE("medit ascii version 1 stores single precision") {
  const auto dir = test::temp_dir("medit_v1");
  MeshData in = rich_mesh(3);
  for (auto& p : in.vertices) p = {0.1, 1.0 / 3.0, 0.75};
  in.normals.clear();
  in.normal_at_vertex.clear();
  in.tangents.clear();
  in.tangent_at_vertex.clear();
  const std::string path = (dir / "v1.mesh").string();
  WriteOptions options;
  options.medit_version = 1;
  write_mesh_data(path, in, options);
  const MeshData out = read_mesh_data(path);
  CHECK(out.version == 1);
  REQUIRE(out.vertices.size() == in.vertices.size());
  // The text holds the shortest decimal of the float: it reads back as that
  // float, no longer as the double.
  for (const auto& p : out.vertices) {
    CHECK(static_cast<float>(p.x) == 0.1f);
    CHECK(static_cast<float>(p.y) == 1.0f / 3.0f);
    CHECK(p.y != 1.0 / 3.0);
    CHECK(p.z == 0.75);
  }
  options.medit_version = 3;
  CHECK_THROWS_AS(write_mesh_data(path, in, options), IoError);
}

TEST_CASE("medit binary round trip is bit-exact (3D and 2D)") {
  const auto dir = test::temp_dir("medit_binary");
  for (int dim : {3, 2}) {
    CAPTURE(dim);
    const MeshData in = rich_mesh(dim);
    const std::string a = (dir / (std::string("a") + std::to_string(dim) + ".meshb")).string();
    const std::string b = (dir / (std::string("b") + std::to_string(dim) + ".meshb")).string();
    write_mesh_data(a, in);
    const MeshData out = read_mesh_data(a);
    check_same(in, out);
    CHECK(out.warnings.empty());
    write_mesh_data(b, out);
    CHECK(slurp(a) == slurp(b));
    // ASCII -> binary -> ASCII keeps the text identical.
    const std::string t1 = (dir / (std::string("t1_") + std::to_string(dim) + ".mesh")).string();
    const std::string t2 = (dir / (std::string("t2_") + std::to_string(dim) + ".mesh")).string();
    write_mesh_data(t1, in);
    write_mesh_data(t2, read_mesh_data(a));
    CHECK(slurp(t1) == slurp(t2));
  }
}

TEST_CASE("medit binary reads versions 1 to 4 in both byte orders") {
  const auto dir = test::temp_dir("medit_gmf_versions");
  for (int version = 1; version <= 4; ++version) {
    for (bool swap : {false, true}) {
      CAPTURE(version);
      CAPTURE(swap);
      const std::string path = (dir / (std::string("v") + std::to_string(version) + (swap ? "s" : "") + ".meshb")).string();
      const std::string bytes = gmf_sample(version, swap);
      std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      const MeshData d = read_mesh_data(path);
      CHECK(d.dimension == 3);
      CHECK(d.version == (version == 1 ? 1 : 2));
      REQUIRE(d.vertices.size() == 6);
      CHECK(d.vertices[2] == Vec3(2, 0, 0.5));
      CHECK(d.vertices[4] == Vec3(1, 1, -0.75));
      CHECK(d.vertex_refs == std::vector<int>{10, 11, 12, 13, 14, 15});
      // 2 triangles + the quadrilateral split in 2, appended after them.
      REQUIRE(d.triangles.size() == 4);
      CHECK(d.triangles[0] == std::array<int, 3>{0, 1, 4});
      CHECK(d.triangles[1] == std::array<int, 3>{0, 4, 3});
      CHECK(d.triangles[2] == std::array<int, 3>{1, 2, 5});
      CHECK(d.triangles[3] == std::array<int, 3>{1, 5, 4});
      CHECK(d.triangle_refs == std::vector<int>{1, 4, 9, 9});
      CHECK(d.edges == std::vector<std::array<int, 2>>{{0, 1}});
      CHECK(d.edge_refs == std::vector<int>{3});
      CHECK(d.ridges == std::vector<int>{0});
      CHECK(same_points(d.normals, {Vec3(0, 0, 1)}));
      CHECK(d.normal_at_vertex == std::vector<std::array<int, 2>>{{5, 0}});
      CHECK(same_points(d.tangents, {Vec3(1, 0, 0)}));
      CHECK(d.tangent_at_vertex == std::vector<std::array<int, 2>>{{1, 0}});
      CHECK(has_warning(d, "1 Tetrahedra skipped"));
      CHECK(has_warning(d, "unknown keyword 120 skipped"));
      CHECK(has_warning(d, "1 quadrilaterals split into 2 triangles"));
    }
  }
}

TEST_CASE("medit ascii: Mmg layouts, case-insensitive keywords, skipped and split sections") {
  const auto dir = test::temp_dir("medit_layouts");
  const std::string text =
      "# written by hand\n"
      "  MeshVersionFormatted 1\n"
      "  dimension\n"
      "  3\n"
      "  VERTICES\n"
      "  5\n"
      "    0 0 0 1   # a comment after a vertex\n"
      "    1 0 0 2\n"
      "    1 1 0 3\n"
      "    0 1 0 4\n"
      "    0.5 0.5 1.0D+00 5\n"
      "  Quadrilaterals\n"
      "  1\n"
      "  1 2 3 4 7\n"
      "  Tetrahedra\n"
      "  1\n"
      "  1 2 3 5 0\n"
      "  Triangles\n"
      "  2\n"
      "  1 2 5 3\n"
      "  2 3 5 3\n"
      "  RequiredTriangles\n"
      "  1\n"
      "  2\n"
      "  FooBar\n"
      "  3\n"
      "  1 2 3\n"
      "  end\n";
  const MeshData d = read_mesh_data(write_text(dir, "layout.mesh", text));
  CHECK(d.version == 1);
  CHECK(d.dimension == 3);
  REQUIRE(d.vertices.size() == 5);
  CHECK(d.vertices[4] == Vec3(0.5, 0.5, 1.0));
  CHECK(d.vertex_refs == std::vector<int>{1, 2, 3, 4, 5});
  REQUIRE(d.triangles.size() == 4);
  CHECK(d.triangles[0] == std::array<int, 3>{0, 1, 4});
  CHECK(d.triangles[2] == std::array<int, 3>{0, 1, 2});
  CHECK(d.triangles[3] == std::array<int, 3>{0, 2, 3});
  CHECK(d.triangle_refs == std::vector<int>{3, 3, 7, 7});
  CHECK(d.required_triangles == std::vector<int>{1});
  CHECK(has_warning(d, "layout.mesh:15: 1 Tetrahedra skipped"));
  CHECK(has_warning(d, "layout.mesh:25: unknown section 'FooBar' skipped"));
  CHECK(has_warning(d, "1 quadrilaterals split into 2 triangles"));
}

TEST_CASE("medit ascii: ids may refer to a section that comes later") {
  const auto dir = test::temp_dir("medit_order");
  const std::string text =
      "MeshVersionFormatted 2\nDimension 2\n"
      "Ridges\n1\n2\n"
      "Triangles\n1\n1 2 3 0\n"
      "Edges\n2\n1 2 0\n2 3 0\n"
      "Vertices\n3\n0 0 1\n1 0 1\n0 1 1\n"
      "End\n";
  const MeshData d = read_mesh_data(write_text(dir, "order.mesh", text));
  CHECK(d.dimension == 2);
  CHECK(d.vertices.size() == 3);
  CHECK(d.vertices[1] == Vec3(1, 0, 0));
  CHECK(d.ridges == std::vector<int>{1});
  CHECK(d.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}});
  CHECK(d.warnings.empty());
  // The same file with a triangle that points past the vertices: refused with
  // the line of the id although the vertices come later.
  std::string bad = text;
  bad.replace(bad.find("1 2 3 0"), 7, "1 2 4 0");
  try {
    read_mesh_data(write_text(dir, "order_bad.mesh", bad));
    FAIL("accepted a triangle with vertex id 4 of 3");
  } catch (const IoError& e) {
    CHECK(std::string(e.what()).find("order_bad.mesh:8: triangle 1: vertex id 4 out of range 1..3") != std::string::npos);
  }
}

TEST_CASE("medit files of ../shared/meshes give the counts of SOURCES.md") {
  struct Expect {
    const char* file;
    std::size_t vertices, triangles;
  };
  const Expect expected[] = {{"meshes/mmg_cube.mesh", 12, 20},
                             {"meshes/mmg_torus.mesh", 4351, 2954},
                             {"meshes/mmg_teapot.mesh", 5917, 11617},
                             {"meshes/thinker.mesh", 2200, 4392},
                             {"meshes/falcon.mesh", 37375, 74754}};
  for (const auto& e : expected) {
    const std::string path = test::shared_file(e.file);
    if (path.empty()) {
      MESSAGE("skipped: ../shared/" << e.file << " not found (no shared test data)");
      continue;
    }
    CAPTURE(path);
    const MeshData d = read_mesh_data(path);
    CHECK(d.vertices.size() == e.vertices);
    CHECK(d.triangles.size() == e.triangles);
    CHECK(d.triangle_refs.size() == e.triangles);
    CHECK(d.dimension == 3);
  }
}

TEST_CASE("mmg_torus: volume data skipped, feature sections kept") {
  ANISURF_REQUIRE_SHARED(path, "meshes/mmg_torus.mesh");
  const MeshData d = read_mesh_data(path);
  CHECK(has_warning(d, "20067 Tetrahedra skipped"));
  CHECK(!d.edges.empty());
  CHECK(!d.ridges.empty());
  CHECK(!d.normals.empty());
  CHECK(d.normal_at_vertex.size() > 0);
  CHECK(!d.tangents.empty());
  CHECK(d.tangent_at_vertex.size() == d.tangents.size());
  // Mmg numbers these tangents after the 1375 normals (1376..1469).
  CHECK(has_warning(d, "94 TangentAtVertices ids numbered after the normals"));
  for (const auto& t : d.tangent_at_vertex) CHECK((t[1] >= 0 && t[1] < static_cast<int>(d.tangents.size())));
  for (int r : d.ridges) CHECK(r < static_cast<int>(d.edges.size()));
  // The binary form carries the same data.
  const auto dir = test::temp_dir("medit_torus");
  const std::string b = (dir / "torus.meshb").string();
  write_mesh_data(b, d);
  check_same(d, read_mesh_data(b));
}

TEST_CASE("medit files of ../shared/meshes build into valid meshes") {
  struct Expect {
    const char* file;
    int unreferenced;
  };
  const Expect expected[] = {{"meshes/mmg_cube.mesh", 0},
                             {"meshes/mmg_torus.mesh", 2882},
                             {"meshes/mmg_teapot.mesh", 19},
                             {"meshes/thinker.mesh", 0},
                             {"meshes/falcon.mesh", 0}};
  for (const auto& e : expected) {
    const std::string path = test::shared_file(e.file);
    if (path.empty()) {
      MESSAGE("skipped: ../shared/" << e.file << " not found (no shared test data)");
      continue;
    }
    CAPTURE(path);
    BuildReport report;
    const SurfaceMesh mesh = load_mesh(path, &report);
    const ValidationReport v = mesh.validate();
    CHECK_MESSAGE(v.ok(), v.summary());
    CHECK(report.unreferenced_vertices == e.unreferenced);
    CHECK(report.input_vertices == static_cast<int>(report.vertex_map.size()));
    CHECK(mesh.n_triangles() > 0);
  }
}

TEST_CASE("falcon.mesh (75k triangles) reads fast") {
  ANISURF_REQUIRE_SHARED(path, "meshes/falcon.mesh");
  read_mesh_data(path);  // warm the file cache
  const auto t0 = std::chrono::steady_clock::now();
  const MeshData d = read_mesh_data(path);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MESSAGE("falcon.mesh: " << d.triangles.size() << " triangles read in " << seconds * 1000 << " ms");
  CHECK(d.triangles.size() == 74754);
  // Well under a second in Release (about 50 ms); the bound leaves room for a
  // Debug build on a loaded machine, while catching a quadratic parser.
  CHECK(seconds < 3.0);
}

TEST_CASE("mesh_format_from_path: case-insensitive extensions, clear refusal") {
  CHECK(mesh_format_from_path("a/b/MODEL.MESH") == MeshFormat::Medit);
  CHECK(mesh_format_from_path("x.Meshb") == MeshFormat::MeditBinary);
  CHECK(mesh_format_from_path("x.obj") == MeshFormat::Obj);
  CHECK(mesh_format_from_path("x.OFF") == MeshFormat::Off);
  CHECK(mesh_format_from_path("x.ply") == MeshFormat::Ply);
  CHECK(mesh_format_from_path("x.STL") == MeshFormat::Stl);
  CHECK(mesh_format_from_path("x.gltf") == MeshFormat::Gltf);
  CHECK(mesh_format_from_path("x.glb") == MeshFormat::Glb);
  CHECK(mesh_format_from_path("x.vtk") == MeshFormat::Vtk);
  try {
    mesh_format_from_path("dir/file.xyz");
    FAIL("accepted .xyz");
  } catch (const IoError& e) {
    CHECK(std::string(e.what()) ==
          "dir/file.xyz: unknown mesh format '.xyz', expected one of .mesh .meshb .obj .off .ply .stl .gltf .glb "
          ".msh .vtu .vtp .vtk");
  }
  CHECK_THROWS_AS(mesh_format_from_path("noextension"), IoError);
  CHECK(mesh_format_from_path("x.MSH") == MeshFormat::Gmsh);
  CHECK(mesh_format_from_path("x.vtu") == MeshFormat::Vtu);
  CHECK(mesh_format_from_path("x.Vtp") == MeshFormat::Vtp);
  CHECK_THROWS_WITH_AS(read_mesh_data("out.vtk"), doctest::Contains("out.vtk: cannot open file"), IoError);
  const auto dir = test::temp_dir("medit_dispatch");
  CHECK_THROWS_WITH_AS(write_mesh_data((dir / "x.off").string(), rich_mesh(3)), doctest::Contains("cannot write '.off'"),
                       IoError);
  CHECK_THROWS_WITH_AS(read_mesh_data((dir / "missing.mesh").string()), doctest::Contains("missing.mesh"), IoError);
}

TEST_CASE("medit writers refuse inconsistent data and leave no file behind") {
  const auto dir = test::temp_dir("medit_refuse");
  MeshData d = rich_mesh(3);
  d.triangles[1][2] = 8;  // 8 vertices: ids 0..7
  for (const char* name : {"bad.mesh", "bad.meshb"}) {
    const std::string path = (dir / name).string();
    CHECK_THROWS_WITH_AS(write_mesh_data(path, d), doctest::Contains("triangle 1: id 8 out of range 0..7"), IoError);
    CHECK(!std::filesystem::exists(path));
  }
  d = rich_mesh(3);
  d.vertex_refs.pop_back();
  CHECK_THROWS_WITH_AS(write_mesh_data((dir / "refs.mesh").string(), d),
                       doctest::Contains("vertex_refs has 7 entries, expected 0 or 8"), IoError);
}

// --- legacy VTK -------------------------------------------------------------------

namespace {

// Minimal reader of the legacy VTK files written by write_vtk: checks the
// layout keyword by keyword and returns the numbers of each block.
struct VtkFile {
  std::vector<double> points;
  std::vector<long long> lines, polygons, cell_ref;
  struct Array {
    std::string kind, name;
    int ncomp = 0;
    std::vector<double> values;
  };
  std::vector<Array> point_arrays;
};

VtkFile parse_vtk(const std::string& path) {
  std::istringstream in(slurp(path));
  std::string line;
  std::getline(in, line);
  REQUIRE(line.rfind("# vtk DataFile Version", 0) == 0);
  std::getline(in, line);  // title
  std::getline(in, line);
  REQUIRE(line == "ASCII");
  std::getline(in, line);
  REQUIRE(line == "DATASET POLYDATA");
  VtkFile f;
  std::string word;
  long long n_points = 0;
  auto numbers = [&](std::size_t n) {
    std::vector<double> v(n);
    for (auto& x : v) REQUIRE(static_cast<bool>(in >> x));
    return v;
  };
  auto ints = [&](std::size_t n) {
    std::vector<long long> v(n);
    for (auto& x : v) REQUIRE(static_cast<bool>(in >> x));
    return v;
  };
  while (in >> word) {
    if (word == "POINTS") {
      std::string type;
      in >> n_points >> type;
      CHECK(type == "double");
      f.points = numbers(static_cast<std::size_t>(3 * n_points));
    } else if (word == "LINES" || word == "POLYGONS") {
      long long n = 0, size = 0;
      in >> n >> size;
      const long long per = word == "LINES" ? 2 : 3;
      CHECK(size == n * (per + 1));
      auto v = ints(static_cast<std::size_t>(size));
      for (long long c = 0; c < n; ++c) {
        CHECK(v[static_cast<std::size_t>(c * (per + 1))] == per);
        for (long long k = 1; k <= per; ++k) {
          const long long id = v[static_cast<std::size_t>(c * (per + 1) + k)];
          CHECK((id >= 0 && id < n_points));
          (word == "LINES" ? f.lines : f.polygons).push_back(id);
        }
      }
    } else if (word == "CELL_DATA") {
      long long n = 0;
      in >> n;
      std::string s, name, type, lt, def;
      int nc = 0;
      in >> s >> name >> type >> nc >> lt >> def;
      CHECK(s == "SCALARS");
      CHECK(name == "ref");
      CHECK(lt == "LOOKUP_TABLE");
      f.cell_ref = ints(static_cast<std::size_t>(n));
      CHECK(n == static_cast<long long>(f.lines.size() / 2 + f.polygons.size() / 3));
    } else if (word == "POINT_DATA") {
      long long n = 0;
      in >> n;
      CHECK(n == n_points);
    } else if (word == "SCALARS" || word == "VECTORS" || word == "TENSORS") {
      VtkFile::Array a;
      a.kind = word;
      std::string type;
      in >> a.name >> type;
      a.ncomp = word == "VECTORS" ? 3 : word == "TENSORS" ? 9 : 1;
      if (word == "SCALARS") {
        std::string lt, def;
        in >> a.ncomp >> lt >> def;
        CHECK(lt == "LOOKUP_TABLE");
      }
      a.values = numbers(static_cast<std::size_t>(n_points * a.ncomp));
      f.point_arrays.push_back(std::move(a));
    } else {
      FAIL("unexpected keyword in the VTK file: " << word);
    }
  }
  return f;
}

}  // namespace

TEST_CASE("legacy VTK writer: points, cells, references and fields re-parse") {
  const auto dir = test::temp_dir("medit_vtk");
  MeshData d = rich_mesh(3);
  const std::size_t nv = d.vertices.size();
  for (std::size_t i = 0; i < nv; ++i) d.vertices[i] = {0.1 * static_cast<double>(i), 1.0 / 3.0, -1e-7};
  FieldData scalar{{"size", FieldKind::Scalar, 1}, {}};
  FieldData vec{{"grad u", FieldKind::Vector, 3}, {}};
  FieldData metric{{"metric", FieldKind::Tensor, 6}, {}};
  for (std::size_t i = 0; i < nv; ++i) {
    scalar.values.push_back(0.5 * static_cast<double>(i));
    for (int c = 0; c < 3; ++c) vec.values.push_back(static_cast<double>(i) + 0.25 * c);
    for (int c = 0; c < 6; ++c) metric.values.push_back(10.0 * static_cast<double>(i) + c + 1);
  }
  d.fields = {scalar, vec, metric};
  const std::string path = (dir / "mesh.vtk").string();
  write_mesh_data(path, d);
  const VtkFile f = parse_vtk(path);
  REQUIRE(f.points.size() == 3 * nv);
  for (std::size_t i = 0; i < nv; ++i) {
    CHECK(f.points[3 * i] == d.vertices[i].x);
    CHECK(f.points[3 * i + 2] == d.vertices[i].z);
  }
  REQUIRE(f.polygons.size() == 3 * d.triangles.size());
  for (std::size_t t = 0; t < d.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) CHECK(f.polygons[3 * t + k] == d.triangles[t][k]);
  REQUIRE(f.lines.size() == 2 * d.edges.size());
  // Cell order of POLYDATA: lines first, then polygons.
  std::vector<long long> refs(d.edge_refs.begin(), d.edge_refs.end());
  refs.insert(refs.end(), d.triangle_refs.begin(), d.triangle_refs.end());
  CHECK(f.cell_ref == refs);
  REQUIRE(f.point_arrays.size() == 4);
  CHECK(f.point_arrays[0].name == "vertex_ref");
  CHECK(f.point_arrays[0].values[2] == -2);
  CHECK(f.point_arrays[1].kind == "SCALARS");
  CHECK(f.point_arrays[1].values[3] == 1.5);
  CHECK(f.point_arrays[2].kind == "VECTORS");
  CHECK(f.point_arrays[2].name == "grad_u");
  CHECK(f.point_arrays[2].values[3 * 2 + 1] == 2.25);
  const auto& t = f.point_arrays[3];
  CHECK(t.kind == "TENSORS");
  // Vertex 2: m11 m12 m22 m13 m23 m33 = 21 22 23 24 25 26 -> full symmetric matrix.
  const std::vector<double> m(t.values.begin() + 18, t.values.begin() + 27);
  CHECK(m == std::vector<double>{21, 22, 24, 22, 23, 25, 24, 25, 26});
}

TEST_CASE("legacy VTK writer: 2D tensors become 3x3 and 2D vectors get z = 0") {
  const auto dir = test::temp_dir("medit_vtk2d");
  MeshData d;
  d.dimension = 2;
  d.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  d.triangles = {{0, 1, 2}};
  d.fields.resize(2);
  d.fields[0].info = {"m", FieldKind::Tensor, 3};
  d.fields[0].values = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  d.fields[1].info = {"v", FieldKind::Vector, 2};
  d.fields[1].values = {1, 2, 3, 4, 5, 6};
  const std::string path = (dir / "square.vtk").string();
  write_mesh_data(path, d);
  const VtkFile f = parse_vtk(path);
  CHECK(f.cell_ref == std::vector<long long>{0});
  REQUIRE(f.point_arrays.size() == 2);
  const std::vector<double> m(f.point_arrays[0].values.begin() + 9, f.point_arrays[0].values.begin() + 18);
  CHECK(m == std::vector<double>{4, 5, 0, 5, 6, 0, 0, 0, 0});
  const std::vector<double> v(f.point_arrays[1].values.begin() + 3, f.point_arrays[1].values.begin() + 6);
  CHECK(v == std::vector<double>{3, 4, 0});
}

namespace {

// The text of a 300 x 300 grid (90000 vertices, 178802 triangles: sections
// large enough to be read in parallel chunks) with coordinates that need 17
// digits, and of a SolAtVertices of one tensor per vertex; `line` edits each
// data line (0-based within its section) before it is written.
struct GridText {
  std::string mesh, sol;
};
GridText grid_text(const std::function<std::string(const char* section, int i, std::string line)>& edit) {
  const int n = 300;
  GridText g;
  g.mesh = "MeshVersionFormatted 2\nDimension 3\nVertices\n" + std::to_string(n * n) + "\n";
  for (int i = 0; i < n * n; ++i) {
    const double x = (i % n) / 3.0, y = (i / n) / 7.0, z = std::sin(0.1 * i);
    g.mesh += edit("Vertices", i,
                   format_double(x) + " " + format_double(y) + " " + format_double(z) + " " + std::to_string(i % 5));
    g.mesh += "\n";
  }
  std::vector<std::string> tris;
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const int a = r * n + c + 1, b = a + 1, d = a + n, e = d + 1;
      tris.push_back(std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(e) + " 1");
      tris.push_back(std::to_string(a) + " " + std::to_string(e) + " " + std::to_string(d) + " 2");
    }
  g.mesh += "Triangles\n" + std::to_string(tris.size()) + "\n";
  for (std::size_t t = 0; t < tris.size(); ++t) g.mesh += edit("Triangles", static_cast<int>(t), tris[t]) + "\n";
  g.mesh += "End\n";
  g.sol = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n" + std::to_string(n * n) + "\n1 3\n";
  for (int i = 0; i < n * n; ++i) {
    std::string line;
    for (int k = 0; k < 6; ++k) line += (k ? " " : "") + format_double(1.0 + k + i / 9.0);
    g.sol += edit("SolAtVertices", i, line) + "\n";
  }
  g.sol += "End\n";
  return g;
}

std::string keep(const char*, int, std::string line) { return line; }

struct ReadOutcome {
  MeshData mesh;
  std::vector<FieldData> sol;
  std::string error;
};
// Reads the grid's files with `threads` threads (the error's message when
// a reader refuses them).
ReadOutcome read_grid(const GridText& g, int threads) {
  const auto dir = test::temp_dir("parallel_lines");
  const std::string mesh = (dir / "grid.mesh").string(), sol = (dir / "grid.sol").string();
  std::ofstream(mesh, std::ios::binary) << g.mesh;
  std::ofstream(sol, std::ios::binary) << g.sol;
  const test::ThreadLimitScope scope(threads);
  ReadOutcome out;
  try {
    out.mesh = io::read_medit(mesh);
    out.sol = read_sol(sol);
  } catch (const IoError& e) {
    out.error = e.what();
  }
  return out;
}

// The fields of two reads bit for bit equal.
bool same_sol(const std::vector<FieldData>& a, const std::vector<FieldData>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].values.size() != b[k].values.size() ||
        std::memcmp(a[k].values.data(), b[k].values.data(), a[k].values.size() * sizeof(double)) != 0)
      return false;
  return true;
}

}  // namespace

TEST_CASE("medit and sol ascii: large sections read on parallel chunks give what one thread reads, errors alike") {
  // One entity per line: 1 and 3 threads read the same bits.
  const ReadOutcome one = read_grid(grid_text(keep), 1);
  REQUIRE(one.error.empty());
  CHECK(one.mesh.vertices.size() == 90000);
  CHECK(one.mesh.triangles.size() == 178802);
  REQUIRE(one.sol.size() == 1);
  CHECK(one.sol[0].values.size() == 540000);
  CHECK(one.mesh.vertices[12345].x == 45.0 / 3.0);
  CHECK(one.mesh.triangles[1][2] == 300);
  CHECK(one.sol[0].values[6 * 9 + 2] == 3.0 + 1.0);
  const ReadOutcome parallel = read_grid(grid_text(keep), 3);
  check_same(one.mesh, parallel.mesh);
  CHECK(same_sol(one.sol, parallel.sol));
  // Layouts the chunks leave to the token by token reading (a comment, an
  // entity across two lines, a line of two entities, CRLF ends, tabs):
  // the same data on 3 threads.
  const std::vector<std::function<std::string(const char*, int, std::string)>> layouts = {
      [](const char* s, int i, std::string l) { return i == 70000 ? l + " # a comment" : l; },
      [](const char* s, int i, std::string l) {
        return std::string(s) == "Triangles" && i == 100 ? l.replace(l.find(' '), 1, "\n") : l;
      },
      [](const char* s, int i, std::string l) {
        return std::string(s) == "SolAtVertices" && i == 80000 ? l.replace(l.rfind(' '), 1, "\n") : l;
      },
      [](const char*, int, std::string l) { return l + "\r"; },
      [](const char*, int i, std::string l) { return i % 7 == 0 ? "\t" + l + " \t" : l; },
  };
  for (std::size_t k = 0; k < layouts.size(); ++k) {
    CAPTURE(k);
    const ReadOutcome three = read_grid(grid_text(layouts[k]), 3);
    CHECK(three.error.empty());
    check_same(one.mesh, three.mesh);
    CHECK(same_sol(one.sol, three.sol));
  }
  // Values the reading refuses: the same message (file, line, entity) on 1
  // and 3 threads.
  const std::vector<std::function<std::string(const char*, int, std::string)>> bad = {
      [](const char* s, int i, std::string l) { return std::string(s) == "Triangles" && i == 150000 ? "7 0 8 1" : l; },
      [](const char* s, int i, std::string l) { return std::string(s) == "Triangles" && i == 9 ? "7 90001 8 1" : l; },
      [](const char* s, int i, std::string l) { return std::string(s) == "Vertices" && i == 88888 ? "1 nan 2 0" : l; },
      [](const char* s, int i, std::string l) { return std::string(s) == "Vertices" && i == 5 ? "1 2 3 x" : l; },
      [](const char* s, int i, std::string l) {
        return std::string(s) == "SolAtVertices" && i == 66666 ? "1 2 3 inf 5 6" : l;
      },
  };
  for (std::size_t k = 0; k < bad.size(); ++k) {
    CAPTURE(k);
    const ReadOutcome serial = read_grid(grid_text(bad[k]), 1), parallel = read_grid(grid_text(bad[k]), 3);
    CHECK(!serial.error.empty());
    CHECK(parallel.error == serial.error);
  }
}

TEST_CASE("parse_lines_in_parallel takes every line of a regular run on several threads, none of an irregular one") {
  // 100000 lines of "i 2i" after a count line, then a keyword.
  std::string text = "Section 100000  \n";
  for (int i = 0; i < 100000; ++i) text += std::to_string(i) + " " + std::to_string(2 * i) + "\n";
  text += "End\n";
  auto run = [](const std::string& t, int threads, std::vector<long long>& got) {
    TextReader in(t, "lines.txt", '#');
    std::string_view token;
    REQUIRE(in.next(token));
    REQUIRE(in.next(token));  // the count
    got.assign(100000, -1);
    const test::ThreadLimitScope scope(threads);
    const bool taken = parse_lines_in_parallel(in, 100000, 2, 65536, [&](long long i, const std::string_view* tok) {
      long long a = 0, b = 0;
      if (!parse_integer(tok[0], a) || !parse_integer(tok[1], b)) return false;
      got[static_cast<std::size_t>(i)] = a + b;
      return true;
    });
    // Past the lines when taken (the keyword next, on its line), else where it was.
    REQUIRE(in.next(token));
    CHECK(token == (taken ? "End" : "0"));
    CHECK(in.line() == (taken ? 100002 : 2));
    return taken;
  };
  std::vector<long long> got;
  CHECK(run(text, 3, got));
  bool all = true;
  for (int i = 0; i < 100000; ++i) all = all && got[static_cast<std::size_t>(i)] == 3LL * i;
  CHECK(all);
  CHECK_FALSE(run(text, 1, got));  // one thread: the caller's own reading
  std::string comment = text, split = text, keyword = text, extra = text;
  comment.insert(comment.find("\n77777 "), " # note");
  split.replace(split.find("\n5000 ") + 5, 1, "\n");
  keyword.replace(keyword.find("\n99999 ") + 1, 5, "Edges");
  extra.insert(extra.find("\n123 ") + 4, " 9");
  for (const std::string* t : {&comment, &split, &keyword, &extra}) CHECK_FALSE(run(*t, 3, got));
  CHECK_FALSE(run(text.substr(0, text.size() - 20), 3, got));  // fewer lines than announced
}
