// Medit solution files (.sol / .solb): bit-exact round trips of several
// fields (scalar, vector, tensor; 2D and 3D), the bench inputs, and fields
// carried through build_mesh (attach_fields / extract_fields / save_mesh).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "metric/metric.h"
#include "test_util.h"

using namespace anisurf;

namespace {

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Values that need 17 significant digits, subnormals, huge and negative zero.
double awkward(std::size_t i) {
  const double v[] = {0.1, 1.0 / 3.0, -2.5e-310, 1e300, 6.02214076e23, -0.0, 3.141592653589793, 5e-324, 2.0 / 7.0};
  return v[i % 9] * (i % 2 ? -1.0 : 1.0) + (i % 5 == 4 ? static_cast<double>(i) : 0.0);
}

// Scalar, tensor and vector fields on n vertices in dimension dim.
std::vector<FieldData> sample_fields(int n, int dim, bool custom_names) {
  const int tensor = dim == 3 ? 6 : 3;
  std::vector<FieldData> f = {{{custom_names ? "size" : "sol0", FieldKind::Scalar, 1}, {}},
                              {{custom_names ? "metric" : "sol1", FieldKind::Tensor, tensor}, {}},
                              {{custom_names ? "grad" : "sol2", FieldKind::Vector, dim}, {}}};
  std::size_t k = 0;
  for (auto& field : f)
    for (int i = 0; i < n * field.info.ncomp; ++i) field.values.push_back(awkward(k++));
  return f;
}

void check_same(const std::vector<FieldData>& a, const std::vector<FieldData>& b, bool names) {
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    CAPTURE(k);
    if (names) CHECK(a[k].info.name == b[k].info.name);
    CHECK(a[k].info.kind == b[k].info.kind);
    CHECK(a[k].info.ncomp == b[k].info.ncomp);
    CHECK(same_bits(a[k].values, b[k].values));
  }
}

}  // namespace

TEST_CASE(".sol round trip: several fields, 2D and 3D, bit-exact, names kept") {
  const auto dir = test::temp_dir("sol_ascii");
  for (int dim : {3, 2}) {
    for (bool custom : {true, false}) {
      CAPTURE(dim);
      CAPTURE(custom);
      const int n = 37;
      const auto in = sample_fields(n, dim, custom);
      const std::string a = (dir / (std::string("a") + std::to_string(dim) + (custom ? "c" : "d") + ".sol")).string();
      const std::string b = (dir / (std::string("b") + std::to_string(dim) + (custom ? "c" : "d") + ".sol")).string();
      write_sol(a, in, n, dim);
      int file_dim = 0;
      const auto out = read_sol(a, n, &file_dim);
      CHECK(file_dim == dim);
      check_same(in, out, true);
      write_sol(b, out, n, dim);
      CHECK(slurp(a) == slurp(b));
      // The names comment is only there when needed.
      CHECK((slurp(a).find("# anisurf field names: size metric grad") != std::string::npos) == custom);
    }
  }
}

TEST_CASE(".solb round trip: several fields, 2D and 3D, bit-exact") {
  const auto dir = test::temp_dir("sol_binary");
  for (int dim : {3, 2}) {
    CAPTURE(dim);
    const int n = 41;
    const auto in = sample_fields(n, dim, false);
    const std::string a = (dir / (std::string("a") + std::to_string(dim) + ".solb")).string();
    const std::string b = (dir / (std::string("b") + std::to_string(dim) + ".solb")).string();
    write_sol(a, in, n, dim);
    int file_dim = 0;
    const auto out = read_sol(a, n, &file_dim);
    CHECK(file_dim == dim);
    check_same(in, out, true);
    write_sol(b, out, n, dim);
    CHECK(slurp(a) == slurp(b));
    // .sol -> .solb -> .sol keeps the text identical.
    const std::string t1 = (dir / (std::string("t1_") + std::to_string(dim) + ".sol")).string();
    const std::string t2 = (dir / (std::string("t2_") + std::to_string(dim) + ".sol")).string();
    write_sol(t1, in, n, dim);
    write_sol(t2, read_sol(a, n), n, dim);
    CHECK(slurp(t1) == slurp(t2));
  }
}

TEST_CASE(".sol reader: Mmg layout with several types, vertex count checked") {
  const auto dir = test::temp_dir("sol_layout");
  const std::string path = (dir / "multi.sol").string();
  std::ofstream(path) << "MeshVersionFormatted 2\n\nDimension\n2\n\n  SolAtVertices\n3\n3 2 1 3\n"
                         "1 2  3  4 5 6\n"
                         "7 8  9  10 11 12\n"
                         "-1 -2  -3  -4 -5 -6\n\nSolAtTriangles\n1\n1 1\n42\nEnd\n";
  int dim = 0;
  const auto f = read_sol(path, 3, &dim);
  CHECK(dim == 2);
  REQUIRE(f.size() == 3);
  CHECK(f[0].info.name == "sol0");
  CHECK(f[0].info.kind == FieldKind::Vector);
  CHECK(f[0].values == std::vector<double>{1, 2, 7, 8, -1, -2});
  CHECK(f[1].info.name == "sol1");
  CHECK(f[1].values == std::vector<double>{3, 9, -3});
  CHECK(f[2].info.kind == FieldKind::Tensor);
  CHECK(f[2].info.ncomp == 3);
  CHECK(f[2].values == std::vector<double>{4, 5, 6, 10, 11, 12, -4, -5, -6});
  CHECK_THROWS_WITH_AS(read_sol(path, 4), doctest::Contains("multi.sol:7: 3 values but the mesh has 4 vertices"),
                       IoError);
}

TEST_CASE(".solb reader: version 4 (64-bit ints) in the other byte order") {
  const auto dir = test::temp_dir("sol_v4");
  std::string b;
  auto put = [&](const void* p, std::size_t n) {
    std::string s(static_cast<const char*>(p), n);
    std::reverse(s.begin(), s.end());
    b += s;
  };
  auto i32 = [&](std::int32_t v) { put(&v, 4); };
  auto i64 = [&](std::int64_t v) { put(&v, 8); };
  auto f64 = [&](double v) { put(&v, 8); };
  i32(1);
  i32(4);
  i32(3);
  i64(24);
  i32(3);
  i32(62);
  const std::size_t slot = b.size();
  i64(0);
  i64(2);  // vertices
  i32(2);  // fields
  i32(1);
  i32(2);
  for (double v : {0.5, 1.0, 2.0, 3.0, -0.5, -1.0, -2.0, -3.0}) f64(v);
  std::int64_t end = static_cast<std::int64_t>(b.size());
  std::string pos(reinterpret_cast<const char*>(&end), 8);
  std::reverse(pos.begin(), pos.end());
  b.replace(slot, 8, pos);
  i32(54);
  i64(0);
  const std::string path = (dir / "v4.solb").string();
  std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
  int dim = 0;
  const auto f = read_sol(path, 2, &dim);
  CHECK(dim == 3);
  REQUIRE(f.size() == 2);
  CHECK(f[0].values == std::vector<double>{0.5, -0.5});
  CHECK(f[1].values == std::vector<double>{1, 2, 3, -1, -2, -3});
  CHECK_THROWS_WITH_AS(read_sol(path, 3), doctest::Contains("v4.solb: byte 36: 2 values but the mesh has 3 vertices"),
                       IoError);
}

TEST_CASE("sol writers and dispatch refuse what they cannot write") {
  const auto dir = test::temp_dir("sol_refuse");
  auto f = sample_fields(4, 3, true);
  CHECK_THROWS_WITH_AS(write_sol((dir / "x.sol").string(), f, 4, 2),
                       doctest::Contains("field 'metric': tensor with 6 components, expected 3 in dimension 2"), IoError);
  CHECK_THROWS_WITH_AS(write_sol((dir / "x.solb").string(), f, 5, 3),
                       doctest::Contains("field 'size' has 4 values, expected 5 x 1 = 5"), IoError);
  CHECK_THROWS_WITH_AS(write_sol((dir / "x.sol").string(), std::vector<FieldData>{}, 4, 3), doctest::Contains("no field"), IoError);
  f[0].values[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH_AS(write_sol((dir / "x.sol").string(), f, 4, 3),
                       doctest::Contains("field 'size': vertex 3 has a non-finite value"), IoError);
  CHECK(!std::filesystem::exists(dir / "x.sol"));
  CHECK_THROWS_WITH_AS(read_sol((dir / "x.txt").string()), doctest::Contains("expected .sol or .solb"), IoError);
}

TEST_CASE("bench inputs: meshes and their .sol files load with matching sizes") {
  struct Pair {
    const char* mesh;
    const char* sol;
    int dim;
    std::size_t vertices;
    FieldKind kind;
    int ncomp;
  };
  const Pair pairs[] = {
      {"bench/inputs/hemi.mesh", "bench/inputs/hemi_iso.sol", 3, 66, FieldKind::Scalar, 1},
      {"bench/inputs/sphere20k.mesh", "bench/inputs/sphere20k_iso.sol", 3, 10242, FieldKind::Scalar, 1},
      {"bench/inputs/sphere20k.mesh", "bench/inputs/sphere20k_isofine.sol", 3, 10242, FieldKind::Scalar, 1},
      {"bench/inputs/sphere20k.mesh", "bench/inputs/sphere20k_band.sol", 3, 10242, FieldKind::Tensor, 6},
      {"bench/inputs/sphere20k.mesh", "bench/inputs/sphere20k_bandfine.sol", 3, 10242, FieldKind::Tensor, 6},
      {"bench/inputs/square2d.mesh", "bench/inputs/square2d.sol", 2, 121, FieldKind::Tensor, 3},
      {"bench/inputs/square3d.mesh", "bench/inputs/square3d.sol", 3, 121, FieldKind::Tensor, 6},
  };
  for (const auto& p : pairs) {
    const std::string mesh = test::shared_file(p.mesh);
    const std::string sol = test::shared_file(p.sol);
    if (mesh.empty() || sol.empty()) {
      MESSAGE("skipped: ../shared/" << p.sol << " not found (no shared test data)");
      continue;
    }
    CAPTURE(sol);
    const MeshData d = read_mesh_data(mesh);
    CHECK(d.dimension == p.dim);
    CHECK(d.vertices.size() == p.vertices);
    CHECK(!d.triangles.empty());
    int dim = 0;
    const auto fields = read_sol(sol, static_cast<int>(d.vertices.size()), &dim);
    CHECK(dim == p.dim);
    REQUIRE(fields.size() == 1);
    CHECK(fields[0].info.kind == p.kind);
    CHECK(fields[0].info.ncomp == p.ncomp);
    CHECK(fields[0].values.size() == p.vertices * static_cast<std::size_t>(p.ncomp));
    // Wrong mesh: the count check names the line of the count.
    const std::string words = ":6: " + std::to_string(p.vertices) + " values but the mesh has";
    CHECK_THROWS_WITH_AS(read_sol(sol, static_cast<int>(d.vertices.size()) + 1), doctest::Contains(words.c_str()),
                         IoError);
  }
  ANISURF_REQUIRE_SHARED(square, "bench/inputs/square2d.sol");
  const auto f = read_sol(square, 121);
  CHECK(f[0].values[0] == 4444.4444444444443);
  CHECK(f[0].values[1] == 0);
  CHECK(f[0].values[2] == 1);
}

TEST_CASE("fields follow the build: attach_fields, extract_fields, save_mesh to .sol") {
  ANISURF_REQUIRE_SHARED(mesh_path, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol_path, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("sol_attach");
  // A sibling .sol with the same stem is not loaded implicitly.
  std::filesystem::copy_file(mesh_path, dir / "hemi.mesh");
  std::filesystem::copy_file(sol_path, dir / "hemi.sol");
  BuildReport report;
  SurfaceMesh mesh = load_mesh((dir / "hemi.mesh").string(), &report);
  CHECK(mesh.fields().empty());

  const MeshData data = read_mesh_data(mesh_path);
  auto fields = read_sol(sol_path, static_cast<int>(data.vertices.size()));
  // A second, varying field so that a wrong vertex mapping shows.
  FieldData x{{"x", FieldKind::Scalar, 1}, {}};
  FieldData m{{"metric", FieldKind::Tensor, 6}, {}};
  for (const auto& p : data.vertices) {
    x.values.push_back(p.x);
    for (double c : {p.x, p.y, p.z, p.x + p.y, p.y + p.z, p.z + p.x}) m.values.push_back(c);
  }
  fields.push_back(x);
  fields.push_back(m);
  attach_fields(mesh, fields, report);
  REQUIRE(mesh.fields().size() == 3);
  const auto back = extract_fields(mesh);
  REQUIRE(back.size() == 3);
  CHECK(back[0].info.name == "sol0");
  CHECK(back[1].info.name == "x");
  REQUIRE(back[1].values.size() == static_cast<std::size_t>(mesh.n_vertices()));
  for (int v = 0; v < mesh.n_vertices(); ++v) {
    CHECK(back[1].values[static_cast<std::size_t>(v)] == mesh.position(Vertex(v)).x);
    CHECK(back[2].values[6 * static_cast<std::size_t>(v) + 4] == mesh.position(Vertex(v)).y + mesh.position(Vertex(v)).z);
  }
  const std::string out = (dir / "out.sol").string();
  save_mesh(out, mesh);
  check_same(back, read_sol(out, mesh.n_vertices()), true);
  // A field sized for another mesh is refused.
  fields[0].values.pop_back();
  CHECK_THROWS_AS(attach_fields(mesh, fields, report), Error);
}

TEST_CASE("sol: a metric written from its tensors in place reads back bit-exact") {
  const auto dir = test::temp_dir("sol_view");
  std::vector<SymTensor3> metric;
  for (std::size_t i = 0; i < 50; ++i)
    metric.push_back(SymTensor3(1.0 + static_cast<double>(i), awkward(i), 2.0 / static_cast<double>(i + 1), 1.0 / 3.0,
                                awkward(i + 3), 1e6 + static_cast<double>(i)));
  const std::vector<FieldView> views = {FieldView{FieldInfo{"metric", FieldKind::Tensor, 6}, metric.front().m.data(),
                                                  6 * metric.size()}};
  for (const char* name : {"m.sol", "m.solb"}) {
    const std::string path = (dir / name).string();
    write_sol(path, views, static_cast<int>(metric.size()), 3);
    const std::vector<FieldData> back = read_sol(path, static_cast<int>(metric.size()));
    REQUIRE(back.size() == 1);
    CHECK(back[0].info.kind == FieldKind::Tensor);
    std::vector<double> flat;
    for (const SymTensor3& M : metric) flat.insert(flat.end(), M.m.begin(), M.m.end());
    CHECK(same_bits(back[0].values, flat));
  }
  // A view shorter than the vertex count is refused, naming the field.
  const std::vector<FieldView> short_view = {FieldView{FieldInfo{"metric", FieldKind::Tensor, 6}, metric.front().m.data(), 6}};
  CHECK_THROWS_WITH_AS(write_sol((dir / "s.sol").string(), short_view, 2, 3), doctest::Contains("metric"), IoError);
}
