// `anisurf metric --weld TOL`: the metric is built on the welded surface (a
// soup of any format as one surface, as `anisurf adapt --weld` adapts it) and
// written numbered like the file's vertices, copies of a welded vertex
// sharing one value.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/mesh_io.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// The unit square as two triangles that share no vertex (6 vertices: file
// vertices 4 and 5 repeat 1 and 3).
std::string write_square_soup(const std::filesystem::path& dir) {
  const std::string soup = (dir / "soup.mesh").string();
  std::ofstream(soup) << "MeshVersionFormatted 2\nDimension 3\nVertices\n6\n"
                         "0 0 0 0\n1 0 0 0\n1 1 0 0\n0 0 0 0\n1 1 0 0\n0 1 0 0\nTriangles\n2\n1 2 3 0\n4 5 6 0\nEnd\n";
  return soup;
}

struct MetricRun {
  int status = -1;
  std::string output;
};

MetricRun run_metric(const std::string& mesh, const std::string& options, const std::string& sol) {
  MetricRun r;
  r.output = test::capture(std::string(ANISURF_BINARY) + " metric '" + mesh + "' " + options + " -o '" + sol + "' 2>&1",
                           &r.status);
  return r;
}

}  // namespace

TEST_CASE("anisurf metric --weld: a soup's metric is built on the welded surface") {
  const auto dir = test::temp_dir("metric_weld");
  const std::string soup = write_square_soup(dir);
  // The Hessian of the function is recovered from the vertex values around each
  // vertex: on one surface, every copy of a position sees the same neighbours.
  const std::string source = "--hessian-of 'x^2 + 3*x*y' --error 0.01 --hmax 1";
  const MetricRun apart = run_metric(soup, source, (dir / "apart.sol").string());
  const MetricRun welded = run_metric(soup, source + " --weld 0", (dir / "welded.sol").string());
  REQUIRE_MESSAGE(apart.status == 0, apart.output);
  REQUIRE_MESSAGE(welded.status == 0, welded.output);
  CHECK_MESSAGE(apart.output.find("vertices    6") != std::string::npos, apart.output);
  CHECK_MESSAGE(welded.output.find("vertices    4") != std::string::npos, welded.output);
  // One value per file vertex; the copies of a welded vertex share it.
  const auto fields = read_sol((dir / "welded.sol").string(), 6);
  REQUIRE(fields.size() == 1);
  const auto& m = fields[0].values;
  REQUIRE(m.size() == 6 * 6);
  for (int c = 0; c < 6; ++c) {
    CHECK(m[0 * 6 + c] == m[3 * 6 + c]);  // file vertices 1 and 4
    CHECK(m[2 * 6 + c] == m[4 * 6 + c]);  // file vertices 3 and 5
  }
}

TEST_CASE("anisurf metric --weld: a tolerance outside 0 <= TOL < 0.1 is a usage error") {
  const auto dir = test::temp_dir("metric_weld_usage");
  const std::string soup = write_square_soup(dir);
  for (const char* bad : {"0.5", "-1", "abc", "nan"}) {
    CAPTURE(bad);
    const MetricRun r = run_metric(soup, std::string("--size 0.1 --weld ") + bad, (dir / "x.sol").string());
    CHECK(r.status == 2);
    CHECK(r.output.find("--weld expects a tolerance") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "x.sol"));
  }
}
