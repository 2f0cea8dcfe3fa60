// The memory of the adaptation's timeline: a snapshot's mesh goes without the
// remesher's working properties (measured in heap bytes per vertex slot), a
// run keeps its last kMaxRunSnapshots passes, and a kept snapshot still
// restarts the adaptation; a cancel still returns to where the run started.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <malloc.h>

#include <algorithm>
#include <array>

#include "editor/adaptation.h"
#include "editor/session.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "locate/location.h"
#include "remesh/adapted_mesh.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;

namespace {

std::string demo(const char* ext) { return test::asset_file(std::string("demo.") + ext); }

std::size_t heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

// Heap bytes that a copy made by `copy` holds.
template <class Copy>
std::size_t bytes_of_copy(Copy copy) {
  const std::size_t before = heap_bytes();
  const SurfaceMesh held = copy();
  return heap_bytes() - before;
}

bool has_vertex_property(const SurfaceMesh& m, const std::string& name) {
  const auto names = m.vertex_properties().names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

TEST_CASE("snapshots: the mesh of a snapshot goes without the remesher's working properties") {
  SurfaceMesh m;
  build_mesh(read_mesh_data(demo("mesh")), m);
  // The properties AdaptedMesh attaches (adapted_mesh.cpp), with their types.
  m.add_vertex_property<SymTensor3>(remesh::kMetricProperty, SymTensor3::identity());
  m.add_vertex_property<double>(remesh::kIsotropicMetricProperty, 1.0);
  m.add_vertex_property<std::array<float, 3>>("remesh:normal");
  m.add_vertex_property<std::uint8_t>(remesh::kPlacementProperty, 1);
  m.add_vertex_property<Hint>("remesh:hint_g");
  m.add_vertex_property<Hint>("remesh:hint_0");
  const SurfaceMesh snap = snapshot_mesh(m);
  for (const char* working : kRemesherWorkingProperties) CHECK_FALSE(has_vertex_property(snap, working));
  CHECK(has_vertex_property(snap, remesh::kPlacementProperty));
  CHECK(snap.n_vertices() == m.n_vertices());
  CHECK(snap.n_triangles() == m.n_triangles());
  CHECK(snap.validate().ok());
  for (Vertex v : m.vertices()) CHECK(snap.position(v) == m.position(v));
  for (Triangle t : m.triangles())
    for (int k = 0; k < 3; ++k) CHECK(snap.vertex(t, k) == m.vertex(t, k));

  const double slots = m.vertex_capacity();
  const double full = static_cast<double>(bytes_of_copy([&] { return SurfaceMesh(m); })) / slots;
  const double kept = static_cast<double>(bytes_of_copy([&] { return snapshot_mesh(m); })) / slots;
  MESSAGE("heap bytes per vertex slot: a plain copy " << full << ", a snapshot's mesh " << kept);
  CHECK(full - kept >= 60);  // 68 bytes of working data per vertex
  CHECK(kept <= 110);        // positions, connectivity (2 triangles per vertex), tags, placements
}

TEST_CASE("snapshots: a run keeps its last passes, a kept pass restarts the adaptation, cancel returns to the start") {
  EditorSession s;
  s.open(demo("mesh"), demo("sol"));
  s.run(2);
  s.wait();
  REQUIRE(s.timeline().size() == 3);
  const auto before_run = s.timeline();
  s.run();
  s.wait();
  auto tl = s.timeline();
  REQUIRE(s.dropped_passes() > 0);  // the demo's schedule has more passes than a run keeps
  CHECK(tl.size() == 3 + kMaxRunSnapshots);
  // The states before the run are the same objects.
  for (std::size_t i = 0; i < before_run.size(); ++i) CHECK(tl[i] == before_run[i]);
  CHECK(tl.back()->schedule.phase == Schedule::Phase::Done);
  for (const auto& snap : tl) {
    CHECK(snap->mesh.validate().ok());
    for (const char* working : kRemesherWorkingProperties) CHECK_FALSE(has_vertex_property(snap->mesh, working));
    CHECK(snap->metric.size() == static_cast<std::size_t>(snap->mesh.vertex_capacity()));
  }

  // Restart from the first kept pass of the run: the remesher is rebuilt from
  // that snapshot's mesh and finishes the schedule.
  const std::size_t kept_first = before_run.size();
  s.scrub(static_cast<int>(kept_first));
  s.run();
  s.wait();
  CHECK(s.adaptation_error().empty());
  tl = s.timeline();
  CHECK(tl[kept_first] != nullptr);
  CHECK(tl.back()->schedule.phase == Schedule::Phase::Done);
  CHECK(tl.back()->mesh.validate().ok());

  // A cancelled run: back to the state it started from, whatever it dropped.
  s.reset();
  s.run(1);
  s.wait();
  const auto start = s.timeline().back();
  s.run();
  s.cancel();
  s.wait();
  CHECK(s.timeline().back() == start);
}

#endif
