// The `anisurf` program as a user runs it: help texts, info --json, convert,
// and bad input giving a clear message and a non-zero exit.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/mesh_io.h"
#include "test_util.h"

namespace {

struct Run {
  int code;
  std::string out;
  std::string err;
};

Run run_anisurf(const std::string& args, const std::string& tag) {
  auto dir = anisurf::test::temp_dir("cli_" + tag);
  std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  std::string cmd = std::string("\"") + ANISURF_BINARY + "\" " + args + " >" + out + " 2>" + err;
  int status = std::system(cmd.c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

std::string demo_mesh() { return std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.mesh"; }

}  // namespace

TEST_CASE("anisurf --help lists the commands, each has its own help with an example") {
  Run r = run_anisurf("--help", "help");
  CHECK(r.code == 0);
  CHECK(r.out.find("info") != std::string::npos);
  CHECK(r.out.find("convert") != std::string::npos);
  for (const char* c : {"info", "convert"}) {
    Run h = run_anisurf(std::string(c) + " --help", std::string("help_") + c);
    CHECK(h.code == 0);
    CHECK(h.out.find("usage: anisurf") != std::string::npos);
    CHECK(h.out.find("example:") != std::string::npos);
  }
  Run bad = run_anisurf("frobnicate", "unknown");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("unknown command") != std::string::npos);
}

TEST_CASE("anisurf info --json on the demo") {
  Run r = run_anisurf("info " + demo_mesh() + " --json", "info_json");
  REQUIRE(r.code == 0);
  for (const char* key : {"\"vertices\": 162", "\"triangles\": 320", "\"bbox\"", "\"euler_characteristic\": 2",
                          "\"components\": 1", "\"valid\": true"})
    CHECK_MESSAGE(r.out.find(key) != std::string::npos, key);
}

TEST_CASE("anisurf convert writes every output format, then reads it back") {
  auto dir = anisurf::test::temp_dir("cli_convert");
  for (const char* ext : {".mesh", ".meshb", ".obj", ".ply", ".stl", ".glb", ".msh", ".vtu", ".vtp", ".vtk"}) {
    std::string out = (dir / (std::string("demo") + ext)).string();
    Run r = run_anisurf("convert " + demo_mesh() + " " + out, std::string("convert") + (ext + 1));
    CAPTURE(ext);
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    Run i = run_anisurf("info " + out + " --json", std::string("reinfo") + (ext + 1));
    CHECK(i.code == 0);
    CHECK(i.out.find("\"vertices\": 162") != std::string::npos);
    CHECK(i.out.find("\"triangles\": 320") != std::string::npos);
  }
  // fields: the demo metric goes into a .sol beside a Medit output and into a .vtk
  std::string sol = std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.sol";
  Run r = run_anisurf("convert " + demo_mesh() + " " + (dir / "withsol.mesh").string() + " --sol " + sol, "convsol");
  CHECK(r.code == 0);
  CHECK(std::filesystem::exists(dir / "withsol.sol"));
  Run v = run_anisurf("convert " + demo_mesh() + " " + (dir / "demo.vtk").string() + " --sol " + sol, "convvtk");
  CHECK(v.code == 0);
  CHECK(std::filesystem::file_size(dir / "demo.vtk") > 1000);
}

TEST_CASE("anisurf convert: .msh and VTK XML options, fields from --sol inside the file") {
  auto dir = anisurf::test::temp_dir("cli_convert_fields");
  const std::string sol = std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.sol";
  const std::pair<const char*, const char*> cases[] = {{"a22.msh", "--msh-version 2.2 --ascii"},
                                                       {"b41.msh", ""},
                                                       {"z.vtu", "--zlib --vtk-encoding binary"},
                                                       {"a.vtp", "--ascii"},
                                                       {"b64.vtp", "--vtk-encoding appended-base64"}};
  for (const auto& [file, options] : cases) {
    CAPTURE(file);
    const std::string out = (dir / file).string();
    Run r = run_anisurf("convert " + demo_mesh() + " " + out + " --sol " + sol + " " + options, "convf");
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    CHECK_FALSE(std::filesystem::exists(std::filesystem::path(out).replace_extension(".sol")));
    const anisurf::MeshData d = anisurf::read_mesh_data(out);
    REQUIRE(d.fields.size() == 1);
    CHECK(d.fields[0].info.kind == anisurf::FieldKind::Tensor);
    CHECK(d.fields[0].values.size() == 6 * d.vertices.size());
  }
  Run bad = run_anisurf("convert " + demo_mesh() + " " + (dir / "x.msh").string() + " --msh-version 3", "convbad");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("--msh-version must be 4.1 or 2.2") != std::string::npos);
  Run zascii = run_anisurf("convert " + demo_mesh() + " " + (dir / "x.vtu").string() + " --zlib --ascii", "convz");
  CHECK(zascii.code == 2);
}

TEST_CASE("anisurf adapt IN.msh -o OUT.msh / OUT.vtu: the metric and interpolated fields inside OUT, no .sol") {
  auto dir = anisurf::test::temp_dir("cli_adapt_embedded");
  const std::string in = (dir / "in.msh").string();
  const std::string sol = std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.sol";
  REQUIRE(run_anisurf("convert " + demo_mesh() + " " + in, "adapt_in").code == 0);
  for (const char* out_name : {"out.msh", "out.vtu"}) {
    CAPTURE(out_name);
    const std::string out = (dir / out_name).string();
    Run r = run_anisurf("adapt " + in + " --size 0.4 --interpolate " + sol + " -o " + out + " -v 0", "adapt_emb");
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("with the metric and fields inside") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(std::filesystem::path(out).replace_extension(".sol")));
    CHECK_FALSE(std::filesystem::exists(std::filesystem::path(out).replace_extension(".fields.sol")));
    const anisurf::MeshData d = anisurf::read_mesh_data(out);
    REQUIRE(d.fields.size() == 2);
    CHECK(d.fields[0].info.name == "metric");
    CHECK(d.fields[0].info.ncomp == 6);
    CHECK(d.fields[1].info.name == "sol0");
    CHECK(d.fields[1].values.size() == 6 * d.vertices.size());
    // Isotropic size 0.4: the metric is 1 / 0.4^2 on the diagonal.
    CHECK(d.fields[0].values[0] == doctest::Approx(6.25));
  }
}

TEST_CASE("anisurf adapt IN.vtu / IN.msh with a metric inside: used with no other source, or named") {
  auto dir = anisurf::test::temp_dir("cli_adapt_embedded_metric");
  const std::string sol = std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/demo.sol";
  // The same adaptation from demo.mesh + demo.sol and from one file holding both.
  const std::string ref = (dir / "ref.mesh").string();
  REQUIRE(run_anisurf("adapt " + demo_mesh() + " --sol " + sol + " -o " + ref + " -v 0", "ref").code == 0);
  for (const char* name : {"in.vtu", "in.msh"}) {
    CAPTURE(name);
    const std::string in = (dir / name).string(), out = (dir / (std::string("out_") + name)).string();
    REQUIRE(run_anisurf("convert " + demo_mesh() + " --sol " + sol + " " + in, "conv").code == 0);
    Run r = run_anisurf("adapt " + in + " -o " + out + " -v 0", "adapt_in_metric");
    CAPTURE(r.err);
    REQUIRE(r.code == 0);
    const anisurf::MeshData a = anisurf::read_mesh_data(ref), b = anisurf::read_mesh_data(out);
    CHECK(a.vertices.size() == b.vertices.size());
    CHECK(a.triangles.size() == b.triangles.size());
    REQUIRE(b.fields.size() == 1);  // the metric, not a second copy of the input's field
    CHECK(b.fields[0].info.name == "metric");
    // Named: the field must exist.
    Run bad = run_anisurf("adapt " + in + " --metric-field nope -o " + out + " -v 0", "adapt_bad_field");
    CHECK(bad.code == 1);
    CHECK(bad.err.find("no field 'nope'") != std::string::npos);
  }
  // A file without any tensor field and no source: refused, naming the file.
  const std::string plain = (dir / "plain.vtu").string();
  REQUIRE(run_anisurf("convert " + demo_mesh() + " " + plain, "conv_plain").code == 0);
  Run none = run_anisurf("adapt " + plain + " -o " + (dir / "x.vtu").string(), "adapt_no_metric");
  CHECK(none.code == 1);
  CHECK(none.err.find("plain.vtu: no metric") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "x.vtu"));
}

TEST_CASE("bad input: clear message, non-zero exit, no output left behind") {
  auto dir = anisurf::test::temp_dir("cli_bad");
  std::string missing = (dir / "nope.mesh").string();
  Run r = run_anisurf("info " + missing, "missing");
  CHECK(r.code == 1);
  CHECK(r.err.find("nope.mesh") != std::string::npos);

  Run ext = run_anisurf("info " + (dir / "x.xyz").string(), "ext");
  CHECK(ext.code == 1);
  CHECK(ext.err.find("unknown mesh format") != std::string::npos);

  // a truncated file: nothing written for convert
  std::string broken = (dir / "broken.mesh").string();
  {
    std::ofstream o(broken);
    o << "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n";
  }
  std::string out = (dir / "out.obj").string();
  Run c = run_anisurf("convert " + broken + " " + out, "conv_broken");
  CHECK(c.code == 1);
  CHECK(c.err.find("broken.mesh") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(dir))
    CHECK_MESSAGE(e.path().string().find(".tmp-") == std::string::npos, e.path().string());

  Run usage = run_anisurf("convert onlyone.mesh", "usage");
  CHECK(usage.code == 2);
}

TEST_CASE("anisurf distance: a grid 0.25 above a plane of two triangles, read from OFF, OBJ and STL") {
  auto dir = anisurf::test::temp_dir("cli_distance_files");
  // Reference: the unit square as two triangles (OFF); mesh: a 4 x 4 grid of
  // [0.25, 0.75]^2 at z = 0.25 (OBJ), far from the reference's vertices.
  const std::string ref = (dir / "plane.off").string(), out = (dir / "grid.obj").string();
  std::ofstream(ref) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  {
    std::ofstream obj(out);
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) obj << "v " << 0.25 + 0.125 * i << " " << 0.25 + 0.125 * j << " 0.25\n";
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const int a = j * 5 + i + 1, b = a + 1, c = a + 6, d = a + 5;
        obj << "f " << a << " " << b << " " << c << "\nf " << a << " " << c << " " << d << "\n";
      }
  }
  Run r = run_anisurf("distance " + ref + " " + out, "distance_text");
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("V 25  T 32") != std::string::npos);
  // 0.25 / sqrt(2) = 17.6777% of the diagonal, at every kind of sample.
  CHECK(r.out.find("vertices   (     25)   0.25         ( 17.6777%)   0.25         ( 17.6777%)") != std::string::npos);
  CHECK(r.out.find("midpoints  (     56)   0.25") != std::string::npos);
  CHECK(r.out.find("centroids  (     32)   0.25") != std::string::npos);
  CHECK(r.out.find("worst       0.25 (17.6777% of the diagonal) at the vertex of vertex 1") != std::string::npos);

  Run j = run_anisurf("distance " + ref + " " + out + " --json --threads 2", "distance_json");
  INFO(j.out << j.err);
  REQUIRE(j.code == 0);
  for (const char* key : {"\"V\": 25", "\"T\": 32", "\"vert_max\": 0.25", "\"mid_max\": 0.25", "\"cen_mean\": 0.25",
                          "\"sample\": \"vertex\"", "\"element\": \"vertex 1\"", "\"reference_diagonal\": 1.414"})
    CHECK_MESSAGE(j.out.find(key) != std::string::npos, key);

  // The same reference as STL (split vertices, merged on reading).
  const std::string stl = (dir / "plane.stl").string();
  std::ofstream(stl) << "solid p\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
                        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid p\n";
  Run s = run_anisurf("distance " + stl + " " + out + " --json", "distance_stl");
  INFO(s.out << s.err);
  REQUIRE(s.code == 0);
  CHECK(s.out.find("\"cen_max\": 0.25") != std::string::npos);
}

TEST_CASE("anisurf distance: help, bad usage and unreadable files") {
  Run h = run_anisurf("distance --help", "distance_help");
  CHECK(h.code == 0);
  CHECK(h.out.find("usage: anisurf distance REF OUT") != std::string::npos);
  CHECK(h.out.find("example:") != std::string::npos);
  CHECK(run_anisurf("--help", "distance_overview").out.find("distance") != std::string::npos);
  Run one = run_anisurf("distance " + demo_mesh(), "distance_one");
  CHECK(one.code == 2);
  CHECK(one.err.find("expected REF and OUT") != std::string::npos);
  Run threads = run_anisurf("distance " + demo_mesh() + " " + demo_mesh() + " --threads 1.5", "distance_threads");
  CHECK(threads.code == 2);
  CHECK(threads.err.find("--threads expects a whole number") != std::string::npos);
  Run missing = run_anisurf("distance " + demo_mesh() + " /nonexistent/out.mesh", "distance_missing");
  CHECK(missing.code == 1);
  CHECK(missing.err.find("anisurf distance: error: ") != std::string::npos);
  CHECK(missing.err.find("/nonexistent/out.mesh") != std::string::npos);
  // A mesh against itself: 0 everywhere.
  Run self = run_anisurf("distance " + demo_mesh() + " " + demo_mesh() + " --json", "distance_self");
  REQUIRE(self.code == 0);
  const auto at = self.out.find("\"max\": ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(self.out.substr(at + 7)) < 1e-12);
}
