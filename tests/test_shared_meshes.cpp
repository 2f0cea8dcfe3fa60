// Every third-party mesh in ../shared/meshes loads, builds a valid corner table
// and gives the counts listed in ../shared/meshes/SOURCES.md (unique positions
// for formats that store split vertices); repaired defects are reported.
#include <doctest/doctest.h>

#include <chrono>

#include "io/mesh_io.h"
#include "mesh/stats.h"
#include "test_util.h"

using namespace anisurf;

namespace {

struct Expected {
  const char* file;
  int file_vertices;  // vertices stored in the file (-1: not checked)
  int vertices;       // after build (unique referenced positions)
  int triangles;      // in the file
  int components;     // -1: not checked (repairs change it)
  int boundary_loops; // -1: not checked
  int euler;          // chi = V - E + F; 99: not checked
};

// From SOURCES.md section 2.
const Expected kMeshes[] = {
    {"bunny.off", 3485, 3485, 6966, 1, 0, 2},
    {"spot.obj", 2930, 2930, 5856, 1, 0, 2},
    {"fandisk.off", 7229, 7229, 14454, 1, 0, 2},
    {"featuretype.STL", -1, 2010, 3476, 1, 16, -16},
    {"fixed_top.ply", 2374, 2374, 4772, 1, 0, -12},
    {"falcon.mesh", 37375, 37375, 74754, 1, 0, -2},
    {"torus.STL", -1, 4350, 8700, 1, 0, 0},
    {"mmg_torus.mesh", 4351, 1469, 2954, 1, 0, -8},
    {"mmg_teapot.mesh", 5917, 5898, 11617, 2, 3, -1},
    {"mmg_cube.mesh", 12, 12, 20, 1, 0, 2},
    {"camelhead.off", 11381, 11381, 22704, 1, 1, 1},
    // beetle: its 2 duplicated positions are pinch points (two fans touching);
    // they stay two vertices (SOURCES' chi -11 counts them merged)
    {"beetle.off", 19887, 19887, 38656, 1, 11, -9},
    {"Box.glb", 24, 8, 12, 1, 0, 2},
    {"Duck.glb", 2399, 2108, 4212, 1, 0, 2},
    {"Suzanne.gltf", 11808, 2012, 3936, 3, 4, 2},
    {"Avocado.gltf", 406, 363, 682, 2, 1, 3},
    // repaired on load: counts after repair are checked separately below
    {"thinker.mesh", 2200, -1, 4392, -1, -1, 99},
    {"bun_zipper_res2.ply", 8171, -1, 16301, -1, -1, 99},
};

}  // namespace

TEST_CASE("shared meshes: counts of SOURCES.md and a valid corner table") {
  for (const Expected& e : kMeshes) {
    const std::string name = e.file;
    CAPTURE(name);
    const std::string path = test::shared_file(std::string("meshes/") + e.file);
    if (path.empty()) {
      MESSAGE("skipped: ../shared/meshes not found (no shared test data)");
      return;
    }
    BuildReport rep;
    SurfaceMesh m;
    try {
      m = load_mesh(path, &rep);
    } catch (const std::exception& ex) {
      FAIL_CHECK("loading " << name << " threw: " << std::string(ex.what()));
      continue;
    }
    auto v = m.validate();
    INFO(v.summary());
    CHECK(v.ok());
    MeshStats s = compute_stats(m);
    if (e.file_vertices >= 0) CHECK(rep.input_vertices == e.file_vertices);
    if (name == "beetle.off") CHECK(rep.unique_positions == 19885);
    if (e.vertices >= 0) CHECK(s.vertices == e.vertices);
    CHECK(rep.input_triangles == e.triangles);
    if (e.components >= 0) CHECK(s.components == e.components);
    if (e.boundary_loops >= 0) CHECK(s.boundary_loops == e.boundary_loops);
    if (e.euler != 99) CHECK(s.euler_characteristic == e.euler);
  }
}

TEST_CASE("shared meshes: defects are repaired and reported") {
  ANISURF_REQUIRE_SHARED(zipper, "meshes/bun_zipper_res2.ply");
  {
    BuildReport rep;
    SurfaceMesh m = load_mesh(zipper, &rep);
    CHECK(m.validate().ok());
    CHECK(rep.duplicate_triangles == 87);
    CHECK(rep.unreferenced_vertices == 25);
    CHECK(m.n_triangles() == 16301 - 87);
    CHECK(rep.repaired());
  }
  ANISURF_REQUIRE_SHARED(thinker, "meshes/thinker.mesh");
  {
    BuildReport rep;
    SurfaceMesh m = load_mesh(thinker, &rep);
    CHECK(m.validate().ok());
    CHECK(rep.non_manifold_edges == 2);
    CHECK(compute_stats(m).components >= 2);
  }
  ANISURF_REQUIRE_SHARED(teapot, "meshes/mmg_teapot.mesh");
  {
    BuildReport rep;
    SurfaceMesh m = load_mesh(teapot, &rep);
    CHECK(m.validate().ok());
    CHECK(rep.flipped_triangles > 0);
    CHECK(rep.unreferenced_vertices == 19);
  }
}

TEST_CASE("falcon.mesh: read and build adjacency, time printed (bench_io measures it)") {
  ANISURF_REQUIRE_SHARED(falcon, "meshes/falcon.mesh");
  auto t0 = std::chrono::steady_clock::now();
  MeshData d = read_mesh_data(falcon);
  auto t1 = std::chrono::steady_clock::now();
  SurfaceMesh m;
  build_mesh(d, m);
  auto t2 = std::chrono::steady_clock::now();
  double read_s = std::chrono::duration<double>(t1 - t0).count();
  double build_s = std::chrono::duration<double>(t2 - t1).count();
  MESSAGE("falcon.mesh (74754 triangles): read " << read_s << " s, build adjacency " << build_s << " s");
  CHECK(m.n_triangles() == 74754);
  CHECK(m.validate().ok());
}
