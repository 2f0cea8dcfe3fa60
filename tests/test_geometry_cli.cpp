// `anisurf reconstruct` as a user runs it: the sampled hemisphere is within
// 5e-3 of the unit sphere, features and references survive, bad command
// lines are refused with a message.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/mesh_io.h"
#include "mesh/stats.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

struct Run {
  int code;
  std::string out, err;
};

Run reconstruct(const std::string& args, const std::string& tag) {
  const auto dir = test::temp_dir("geometry_cli_" + tag);
  const std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  const std::string cmd = std::string("\"") + ANISURF_BINARY + "\" reconstruct " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

}  // namespace

TEST_CASE("anisurf reconstruct hemi.mesh -k 4: every vertex within 5e-3 of the unit sphere, boundary kept") {
  ANISURF_REQUIRE_SHARED(path, "bench/inputs/hemi.mesh");
  const auto dir = test::temp_dir("geometry_cli_hemi_data");
  const std::string out = (dir / "h4.mesh").string();
  const Run r = reconstruct(path + " -k 4 -o " + out, "hemi");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("24 boundary") != std::string::npos);
  const SurfaceMesh m = load_mesh(out);
  double dmax = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v) dmax = std::fmax(dmax, std::fabs(norm(m.position(Vertex(v))) - 1));
  MESSAGE("anisurf reconstruct hemi.mesh -k 4: max vertex distance to the unit sphere " << dmax);
  CHECK(dmax < 5e-3);
  const MeshStats s = compute_stats(m);
  CHECK(s.triangles == 106 * 16);
  CHECK(s.boundary_edges == 24 * 4);
  CHECK(s.listed_edges == 24 * 4);
  CHECK(m.validate().ok());

  // the plain cubic with angle-weighted normals is much further off
  const std::string out2 = (dir / "h4_plain.mesh").string();
  REQUIRE(reconstruct(path + " -k 4 --normals angle --no-consistency --no-g1 --handle projection -o " + out2, "hemi_plain").code == 0);
  const SurfaceMesh m2 = load_mesh(out2);
  double d2 = 0;
  for (int v = 0; v < m2.vertex_capacity(); ++v) d2 = std::fmax(d2, std::fabs(norm(m2.position(Vertex(v))) - 1));
  CHECK(d2 > 5e-3);
}

TEST_CASE("anisurf reconstruct: ridges and corners of a cube survive, user edits, bad command lines") {
  const auto dir = test::temp_dir("geometry_cli_cube_data");
  const std::string in = (dir / "cube.mesh").string(), out = (dir / "cube3.mesh").string();
  save_mesh(in, test::build(test::cube()));
  Run r = reconstruct(in + " -k 3 -o " + out, "cube");
  INFO(r.err);
  REQUIRE(r.code == 0);
  MeshStats s = compute_stats(load_mesh(out));
  CHECK(s.ridge_edges == 36);
  CHECK(s.corner_vertices == 8);

  // -nr: no ridges, no corners
  r = reconstruct(in + " -k 2 -nr -o " + out, "cube_nr");
  REQUIRE(r.code == 0);
  s = compute_stats(load_mesh(out));
  CHECK(s.ridge_edges == 0);
  CHECK(s.corner_vertices == 0);

  // user edits (1-based ids): remove one cube edge, add a corner
  r = reconstruct(in + " -k 1 --remove-ridge 1-2 --add-corner 1 -o " + out, "cube_edit");
  REQUIRE(r.code == 0);
  s = compute_stats(load_mesh(out));
  CHECK(s.ridge_edges == 11);

  CHECK(reconstruct(in + " -k 0 -o " + out, "bad_k").code == 2);
  CHECK(reconstruct(in, "no_out").code == 2);
  CHECK(reconstruct(in + " --normals magic -o " + out, "bad_normals").code == 2);
  r = reconstruct(in + " --add-ridge 1-8 -o " + out, "bad_edge");  // a cube diagonal through the inside
  CHECK(r.code == 1);
  CHECK(r.err.find("not an edge") != std::string::npos);
}
