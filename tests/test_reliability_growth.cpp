// Reliability (issue 14, item 5): a valid metric the surface cannot carry -
// sizes 1e4 apart on a unit sphere, the long one 11 times the radius - made
// the refinement run to 144k vertices where the metric predicts ~900. The
// adaptation now stops past AdaptOptions::max_growth x the prediction (+ the
// input's vertices), within seconds, with the prediction and the refusing
// filters in the message, and the CLI writes nothing.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/mesh_io.h"
#include "metric/metric_field.h"
#include "remesh/adapt.h"
#include "remesh/adapted_mesh.h"
#include "remesh/reference.h"
#include "remesh/remesher.h"
#include "test_geometry_util.h"
#include "test_util.h"
#ifdef ANISURF_WITH_GL
#include "editor/script.h"
#include "editor/session.h"
#endif

using namespace anisurf;
using test::capture;
using test::temp_dir;

namespace {

SurfaceMesh sphere(int levels) {
  SurfaceMesh m;
  build_mesh(test::icosphere(levels), m);
  return m;
}

// Sizes 11.3 along x and y, 1.13e-3 along z: on the unit sphere's equator
// the long size runs along the parallels, which a chord of that length
// cannot follow; the metric predicts under a thousand vertices.
MetricField needle_metric(const SurfaceMesh& m) {
  SymTensor3 M;
  M.m = {0.0078, 0, 0.0078, 0, 0, 7.8e5};
  return MetricField(static_cast<std::size_t>(m.vertex_capacity()), M);
}

}  // namespace

TEST_CASE("reliability: a metric the surface cannot carry stops the adaptation with the prediction in the message") {
  const SurfaceMesh in = sphere(3);  // 642 vertices
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Given;
  o.metric.given = needle_metric(in);
  o.metric.hgrad = 0;
  o.protect_fraction = 0;  // the geometry protection would shorten the needles to what the sphere carries
  std::string message;
  try {
    remesh::adapt({in}, o);
  } catch (const remesh::AdaptationStopped& e) {
    message = e.what();
  }
  INFO(message);
  REQUIRE_FALSE(message.empty());
  CHECK(message.find("the metric predicts") != std::string::npos);
  CHECK(message.find("refusals") != std::string::npos);
}

TEST_CASE("reliability: a remesher over its vertex limit ends its schedule with a valid mesh") {
  const SurfaceMesh in = sphere(2);
  const MetricField metric(static_cast<std::size_t>(in.vertex_capacity()), isotropic_metric(0.02));
  remesh::PolyhedralSurface geometry(in);
  remesh::ControlSpace control(in, metric, true);
  remesh::AdaptedMesh adapted(in, geometry, control);
  remesh::RemeshOptions options;
  options.max_vertices = 2000;  // the metric asks for ~36k
  remesh::Remesher remesher(adapted, options);
  const std::vector<remesh::PassReport> passes = remesher.run();
  REQUIRE_FALSE(passes.empty());
  CHECK(passes.back().over_limit);
  CHECK(passes.back().interrupted);
  CHECK(remesher.finished());
  CHECK(adapted.mesh().validate().ok());
  CHECK(adapted.mesh().n_vertices() > 2000);
  CHECK(adapted.mesh().n_vertices() < 2000 + 1000);  // stopped within a poll's operations
}

TEST_CASE("reliability: a round that ends over its vertex limit ends the schedule after it") {
  const SurfaceMesh in = sphere(2);
  const MetricField metric(static_cast<std::size_t>(in.vertex_capacity()), isotropic_metric(0.1));
  remesh::PolyhedralSurface geometry(in);
  remesh::ControlSpace control(in, metric, true);
  remesh::AdaptedMesh adapted(in, geometry, control);
  remesh::RemeshOptions options;
  options.max_round_vertices = 500;  // the metric asks for ~1450
  remesh::Remesher remesher(adapted, options);
  const std::vector<remesh::PassReport> passes = remesher.run();
  REQUIRE_FALSE(passes.empty());
  CHECK(passes.back().over_limit);
  CHECK_FALSE(passes.back().interrupted);  // the round's passes all ran
  CHECK(passes.back().round == 1);
  CHECK(remesher.finished());
  CHECK(adapted.mesh().validate().ok());
}

TEST_CASE("reliability: anisurf adapt stops on a metric the surface cannot carry, exit 1, nothing written") {
  const auto dir = temp_dir("growth_cli");
  const std::string mesh = (dir / "sphere.mesh").string(), sol = (dir / "needle.sol").string();
  SurfaceMesh in = sphere(4);
  save_mesh(mesh, in);
  set_metric_field(in, needle_metric(in));
  write_sol(sol, extract_fields(in), in.n_vertices());
  const std::string out = (dir / "out.mesh").string();
  int code = 0;
  const std::string text = capture(std::string("\"") + ANISURF_BINARY + "\" adapt \"" + mesh + "\" --sol \"" + sol + "\" --hausd 0 -o \"" + out + "\" 2>&1", &code);
  INFO(text);
  CHECK(code == 1);
  CHECK(text.find("adaptation stopped") != std::string::npos);
  CHECK(text.find("--max-growth") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
  CHECK_FALSE(std::filesystem::exists(dir / "out.sol"));
}

#ifdef ANISURF_WITH_GL
TEST_CASE("reliability: the editor's run stops on a metric the surface cannot carry, the mesh kept valid") {
  const auto dir = temp_dir("growth_editor");
  const std::string mesh = (dir / "sphere.mesh").string(), sol = (dir / "needle.sol").string();
  SurfaceMesh in = sphere(3);
  save_mesh(mesh, in);
  set_metric_field(in, needle_metric(in));
  write_sol(sol, extract_fields(in), in.n_vertices());
  const auto script = dir / "run.anisurf";
  std::ofstream(script) << "open " << mesh << " " << sol << "\nhgrad 0\nrun\n";
  editor::EditorSession s;
  editor::ViewState v;
  editor::ScriptHost host;
  for (const auto& l : editor::read_script(script.string())) editor::execute(l, s, v, host);
  s.wait();  // the passes run on the session's worker
  const std::string err = s.adaptation_error();
  INFO(err);
  CHECK(err.find("adaptation stopped") != std::string::npos);
  CHECK(err.find("the metric predicts") != std::string::npos);
  const editor::DisplayState d = s.display();
  REQUIRE(d.snapshot);
  CHECK(d.snapshot->mesh.validate().ok());
}
#endif  // ANISURF_WITH_GL
