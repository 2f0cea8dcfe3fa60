// locate/surface_distance.h: the distance from a mesh to a reference surface
// at vertices, edge midpoints and centroids. Analytic cases (a grid above a
// plane made of a few large triangles: the closest points lie inside them,
// far from their vertices; a sphere mesh scaled up), every sample against the
// brute-force distance to all reference triangles, the same result for any
// number of threads, and the figures of ../shared/bench/surfdist.py on the
// same pair of files when Python with numpy and scipy is there.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "core/error.h"
#include "io/mesh_io.h"
#include "locate/surface_distance.h"
#include "test_geometry_util.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

SurfaceMesh moved(const MeshData& d, double scale, const Vec3& shift) {
  MeshData m = d;
  for (Vec3& p : m.vertices) p = scale * p + shift;
  return test::build(m);
}

// Brute-force distances of every sample, in the order surface_distance measures them.
struct BruteForce {
  std::vector<double> vertex, midpoint, centroid;
};
BruteForce brute_force(const SurfaceMesh& mesh, const SurfaceMesh& ref) {
  const auto tris = test::live_triangles(ref);
  auto d = [&](const Vec3& x) { return std::sqrt(test::brute_force_d2(ref, tris, x)); };
  BruteForce b;
  for (Vertex v : mesh.vertices()) b.vertex.push_back(d(mesh.position(v)));
  for (Corner c : mesh.edges()) b.midpoint.push_back(d(0.5 * (mesh.position(mesh.edge_from(c)) + mesh.position(mesh.edge_to(c)))));
  for (Triangle t : mesh.triangles()) {
    Vec3 x;
    for (int k = 0; k < 3; ++k) x += mesh.position(mesh.vertex(t, k)) / 3.0;
    b.centroid.push_back(d(x));
  }
  return b;
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// A Python 3 with numpy and scipy (surfdist.py's imports), or "".
std::string python_with_numpy() {
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    int code = -1;
    test::capture(std::string(py) + " -c 'import numpy, scipy' 2>/dev/null", &code);
    if (code == 0) return py;
  }
  return "";
}

// The value of `"key": number` in surfdist.py's one-line JSON.
double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  REQUIRE_MESSAGE(at != std::string::npos, key << " in " << json);
  return std::stod(json.substr(at + key.size() + 4));
}

}  // namespace

TEST_CASE("surface distance: a grid above a plane of large triangles: exactly the height everywhere") {
  // Reference: the unit square in 8 triangles. Mesh: a 17 x 17 grid of
  // [0.1, 0.9]^2 at height 0.01, so that its samples are far from the
  // reference vertices (a vertex-to-vertex distance would be ~0.1).
  const SurfaceMesh ref = test::build(test::square_grid(2));
  const SurfaceMesh mesh = moved(test::square_grid(17), 0.8, Vec3(0.1, 0.1, 0.01));
  const SurfaceDistance d = surface_distance(mesh, ref);
  CHECK(d.vertices.count == mesh.n_vertices());
  CHECK(d.midpoints.count == 3 * 17 * 17 + 2 * 17);
  CHECK(d.centroids.count == mesh.n_triangles());
  for (const DistanceStats* s : {&d.vertices, &d.midpoints, &d.centroids}) {
    CHECK(s->max == doctest::Approx(0.01).epsilon(1e-12));
    CHECK(s->mean == doctest::Approx(0.01).epsilon(1e-12));
    CHECK(s->worst_closest.z == doctest::Approx(0.0).epsilon(1e-15));
    CHECK(norm(s->worst - s->worst_closest) == doctest::Approx(s->max).epsilon(1e-12));
  }
  for (Vertex v : mesh.vertices()) CHECK(d.vertex[static_cast<std::size_t>(v.idx)] == doctest::Approx(0.01).epsilon(1e-12));
  CHECK(d.reference_diagonal == doctest::Approx(std::sqrt(2.0)));
  CHECK(d.percent(d.max()) == doctest::Approx(100 * 0.01 / std::sqrt(2.0)).epsilon(1e-9));
}

TEST_CASE("surface distance: beside the plane, the closest point is on its boundary edge") {
  // The grid shifted by 0.3 in x: the samples beyond x = 1 are at
  // sqrt((x - 1)^2 + 0.01^2) from the reference's boundary edge.
  const SurfaceMesh ref = test::build(test::square_grid(2));
  const SurfaceMesh mesh = moved(test::square_grid(8), 1.0, Vec3(0.3, 0, 0.01));
  const SurfaceDistance d = surface_distance(mesh, ref);
  CHECK(d.vertices.max == doctest::Approx(std::hypot(0.3, 0.01)).epsilon(1e-12));
  CHECK(d.vertices.worst.x == doctest::Approx(1.3));
  CHECK(d.vertices.worst_closest.x == doctest::Approx(1.0));
  for (Vertex v : mesh.vertices()) {
    const Vec3& p = mesh.position(v);
    const double expect = p.x > 1 ? std::hypot(p.x - 1, 0.01) : 0.01;
    CHECK(d.vertex[static_cast<std::size_t>(v.idx)] == doctest::Approx(expect).epsilon(1e-12));
  }
  // The worst centroid: the one farthest beyond x = 1 (x = 1.3 - 1/24 or 1.3 - 2/24).
  CHECK(d.centroids.max == doctest::Approx(std::hypot(0.3 - 1.0 / 24, 0.01)).epsilon(1e-12));
}

TEST_CASE("surface distance: a sphere mesh scaled by 1.05 is 0.05 away at its vertices, every sample is the brute force") {
  const MeshData sphere = test::icosphere(3);
  const SurfaceMesh ref = test::build(sphere);
  const SurfaceMesh mesh = moved(sphere, 1.05, Vec3());
  const SurfaceDistance d = surface_distance(mesh, ref);
  // Every vertex of the reference lies on the unit sphere, so the radial
  // direction at a vertex is in its normal cone: the closest point of 1.05 v is v.
  CHECK(d.vertices.max == doctest::Approx(0.05).epsilon(1e-12));
  CHECK(d.vertices.mean == doctest::Approx(0.05).epsilon(1e-12));
  const BruteForce b = brute_force(mesh, ref);
  CHECK(d.midpoints.max == doctest::Approx(max_of(b.midpoint)).epsilon(1e-12));
  CHECK(d.midpoints.mean == doctest::Approx(mean_of(b.midpoint)).epsilon(1e-12));
  CHECK(d.centroids.max == doctest::Approx(max_of(b.centroid)).epsilon(1e-12));
  CHECK(d.centroids.mean == doctest::Approx(mean_of(b.centroid)).epsilon(1e-12));
  // Midpoints and centroids are closer to the flat triangles than 0.05.
  CHECK(d.centroids.max < 0.05);
  CHECK(d.max() == doctest::Approx(0.05).epsilon(1e-12));
  CHECK(d.worst_sample() == DistanceSample::Vertex);
}

TEST_CASE("surface distance: a coarse noisy sphere against a fine one: every sample equals the brute force, any thread count") {
  MeshData coarse = test::icosphere(2);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 0.02);
  for (Vec3& p : coarse.vertices) p += Vec3(g(rng), g(rng), g(rng));
  const SurfaceMesh mesh = test::build(coarse);
  const SurfaceMesh ref = test::build(test::icosphere(4));
  const BruteForce b = brute_force(mesh, ref);
  const Locator locator(ref);
  SurfaceDistanceOptions one;
  one.threads = 1;
  SurfaceDistanceOptions three;
  three.threads = 3;
  const SurfaceDistance d1 = surface_distance(mesh, locator, one), d3 = surface_distance(mesh, locator, three);
  for (const SurfaceDistance* d : {&d1, &d3}) {
    CHECK(d->vertices.max == doctest::Approx(max_of(b.vertex)).epsilon(1e-12));
    CHECK(d->vertices.mean == doctest::Approx(mean_of(b.vertex)).epsilon(1e-12));
    CHECK(d->midpoints.max == doctest::Approx(max_of(b.midpoint)).epsilon(1e-12));
    CHECK(d->midpoints.mean == doctest::Approx(mean_of(b.midpoint)).epsilon(1e-12));
    CHECK(d->centroids.max == doctest::Approx(max_of(b.centroid)).epsilon(1e-12));
    CHECK(d->centroids.mean == doctest::Approx(mean_of(b.centroid)).epsilon(1e-12));
  }
  std::size_t i = 0;
  for (Vertex v : mesh.vertices()) CHECK(d1.vertex[static_cast<std::size_t>(v.idx)] == doctest::Approx(b.vertex[i++]).epsilon(1e-12));
  // The same numbers, bit for bit, with one thread or three.
  CHECK(d1.midpoints.mean == d3.midpoints.mean);
  CHECK(d1.centroids.mean == d3.centroids.mean);
  CHECK(d1.centroids.worst_element == d3.centroids.worst_element);
  CHECK(d1.midpoints.worst_element == d3.midpoints.worst_element);
  // Without midpoints and centroids: the vertices only.
  SurfaceDistanceOptions vertices_only;
  vertices_only.midpoints = vertices_only.centroids = false;
  const SurfaceDistance dv = surface_distance(mesh, locator, vertices_only);
  CHECK(dv.vertices.max == d1.vertices.max);
  CHECK(dv.midpoints.count == 0);
  CHECK(dv.centroids.count == 0);
}

TEST_CASE("surface distance: deleted slots are NaN and left out, an empty reference is an error") {
  SurfaceMesh mesh = moved(test::square_grid(4), 1.0, Vec3(0, 0, 0.5));
  const SurfaceMesh ref = test::build(test::square_grid(2));
  // The corner (1, 0) lies in one triangle: delete both.
  Vertex corner;
  for (Vertex v : mesh.vertices())
    if (mesh.position(v).x == 1 && mesh.position(v).y == 0) corner = v;
  REQUIRE(corner.is_valid());
  mesh.delete_triangle(SurfaceMesh::triangle(mesh.corner(corner)));
  mesh.delete_vertex(corner);
  const SurfaceDistance d = surface_distance(mesh, ref);
  CHECK(d.vertices.count == 24);
  CHECK(d.centroids.count == 31);
  CHECK(d.vertex.size() == static_cast<std::size_t>(mesh.vertex_capacity()));
  CHECK(std::isnan(d.vertex[static_cast<std::size_t>(corner.idx)]));
  CHECK(d.max() == doctest::Approx(0.5));
  CHECK_THROWS_AS(surface_distance(mesh, SurfaceMesh()), Error);
  try {
    surface_distance(mesh, SurfaceMesh());
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("no triangle") != std::string::npos);
  }
}

TEST_CASE("surface distance: the figures of surfdist.py on the same files") {
  const std::string script = test::shared_file("bench/surfdist.py");
  const std::string python = python_with_numpy();
  if (script.empty() || python.empty()) {
    MESSAGE("skipped: needs ../shared/bench/surfdist.py and Python 3 with numpy and scipy");
    return;
  }
  const auto dir = test::temp_dir("surface_distance_surfdist");
  MeshData coarse = test::icosphere(2);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 0.03);
  for (Vec3& p : coarse.vertices) p += Vec3(g(rng), g(rng), g(rng));
  const SurfaceMesh mesh = test::build(coarse), ref = test::build(test::icosphere(3));
  const std::string out_path = (dir / "out.mesh").string(), ref_path = (dir / "ref.mesh").string();
  save_mesh(out_path, mesh);
  save_mesh(ref_path, ref);
  int code = -1;
  const std::string json = test::capture(python + " " + script + " " + ref_path + " " + out_path + " --json", &code);
  REQUIRE_MESSAGE(code == 0, json);
  // Measured on the meshes as written (the files round the positions).
  const SurfaceDistance d = surface_distance(load_mesh(out_path), load_mesh(ref_path));
  CHECK(json_number(json, "V") == d.vertices.count);
  CHECK(json_number(json, "T") == d.centroids.count);
  CHECK(json_number(json, "vert_max") == doctest::Approx(d.vertices.max).epsilon(1e-9));
  CHECK(json_number(json, "vert_mean") == doctest::Approx(d.vertices.mean).epsilon(1e-9));
  CHECK(json_number(json, "mid_max") == doctest::Approx(d.midpoints.max).epsilon(1e-9));
  CHECK(json_number(json, "cen_max") == doctest::Approx(d.centroids.max).epsilon(1e-9));
  CHECK(json_number(json, "cen_mean") == doctest::Approx(d.centroids.mean).epsilon(1e-9));
  CHECK(json_number(json, "worst_centroid_tri") == d.centroids.worst_element + 1);
}
