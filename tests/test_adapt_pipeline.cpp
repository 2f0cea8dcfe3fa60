// The engine's adaptation pipeline (remesh/adapt.h, metric/recipe.h): an
// in-memory call gives the command line's mesh, vertex targets are met after
// bounds and gradation, the cycles re-derive the metric and stop at a fixed
// point, outputs are checked writable before the work.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "mesh/stats.h"
#include "metric/surface_metric.h"
#include "remesh/adapt.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

remesh::AdaptOptions hessian_options(const std::string& f) {
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Hessian;
  o.metric.expression = f;
  return o;
}

int inverted_or_degenerate(const SurfaceMesh& m) {
  int bad = 0;
  for (int t = 0; t < m.triangle_capacity(); ++t)
    if (!m.is_deleted(Triangle(t)) && !(m.triangle_normal(Triangle(t)).z > 0)) ++bad;
  return bad;
}

}  // namespace

TEST_CASE("adapt pipeline: an in-memory call gives the command line's mesh") {
  const auto dir = test::temp_dir("adapt_pipeline_same");
  const std::string in = (dir / "sphere.mesh").string(), out = (dir / "out.mesh").string();
  save_mesh(in, test::build(test::icosphere(3)));
  int status = -1;
  test::capture(std::string(ANISURF_BINARY) + " adapt '" + in + "' --size '0.1 + 0.1 * abs(z)' -v 0 -o '" + out + "'",
                &status);
  REQUIRE(status == 0);
  const SurfaceMesh cli = load_mesh(out);

  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Size;
  o.metric.expression = "0.1 + 0.1 * abs(z)";
  const remesh::AdaptResult r = remesh::adapt({load_mesh(in)}, o);
  REQUIRE(r.mesh.validate().ok());
  REQUIRE(r.mesh.n_vertices() == cli.n_vertices());
  REQUIRE(r.mesh.n_triangles() == cli.n_triangles());
  double worst = 0;
  for (int v = 0; v < cli.n_vertices(); ++v) worst = std::max(worst, norm(r.mesh.position(Vertex(v)) - cli.position(Vertex(v))));
  CHECK(worst < 1e-9);  // the file keeps 17 significant digits at most
  REQUIRE(r.cycles.size() == 1);
  CHECK(r.cycles[0].final.in_band_share > 0.95);
  CHECK(r.metric.size() == static_cast<std::size_t>(r.mesh.vertex_capacity()));
}

TEST_CASE("metric recipe: a vertex target is met after bounds and gradation, and by the adapted mesh") {
  SurfaceMesh m = test::build(test::square_grid(10));
  MetricRecipe r;
  r.source = MetricRecipe::Source::Hessian;
  r.expression = "100*x^2";
  r.vertices = 300;
  r.hgrad = 1.3;
  const MetricResult built = build_metric(m, r);
  CHECK(std::abs(predicted_vertices(m, built.metric) - 300) <= 3);
  CHECK(built.predicted_vertices == doctest::Approx(predicted_vertices(m, built.metric)));

  remesh::AdaptOptions o;
  o.metric = r;
  const remesh::AdaptResult a = remesh::adapt({std::move(m)}, o);
  REQUIRE(a.mesh.validate().ok());
  CHECK(inverted_or_degenerate(a.mesh) == 0);
  CHECK(a.mesh.n_vertices() >= 270);
  CHECK(a.mesh.n_vertices() <= 330);
}

TEST_CASE("predicted vertices: the boundary term makes the prediction what is produced") {
  for (double h : {0.1, 0.04}) {
    CAPTURE(h);
    remesh::AdaptOptions o;
    o.metric.source = MetricRecipe::Source::Iso;
    o.metric.iso = h;
    const SurfaceMesh grid = test::build(test::square_grid(8));
    const double predicted = predicted_vertices(grid, MetricField(grid.vertex_capacity(), isotropic_metric(h)));
    const remesh::AdaptResult a = remesh::adapt({grid}, o);
    CHECK(std::abs(a.mesh.n_vertices() - predicted) <= 0.1 * predicted);
  }
}

TEST_CASE("adapt cycles: the metric is derived again on each output, a fixed point stops them") {
  remesh::AdaptOptions o = hessian_options("exp(-8*((x-0.5)^2+(y-0.5)^2))");
  o.metric.error = 0.002;
  o.metric.hgrad = 0;
  o.cycles = 8;
  const remesh::AdaptResult r = remesh::adapt({test::build(test::square_grid(6))}, o);
  REQUIRE(r.mesh.validate().ok());
  CHECK(inverted_or_degenerate(r.mesh) == 0);
  REQUIRE(r.cycles.size() >= 2);
  for (std::size_t k = 0; k < r.cycles.size(); ++k) {
    CAPTURE(k);
    CHECK(r.cycles[k].cycle == static_cast<int>(k) + 1);
    CHECK(r.cycles[k].final.vertices > 30);
    CHECK(std::isfinite(r.cycles[k].error_estimate));
    CHECK(r.cycles[k].error_estimate > 0);
  }
  // The first cycle's T_0 is the coarse grid: the next one, derived on the
  // adapted mesh, sees the function better.
  CHECK(r.cycles.back().error_estimate < 2 * o.metric.error);
  if (r.fixed_point) {
    REQUIRE(r.cycles.size() < 8);
    const double a = r.cycles[r.cycles.size() - 2].final.vertices, b = r.cycles.back().final.vertices;
    CHECK(std::abs(b - a) <= o.fixed_point * a);
  }
}

TEST_CASE("adapt cycles: a solution field is carried to each new mesh and its Hessian used") {
  SurfaceMesh m = test::build(test::square_grid(12));
  Property<FieldValue> f = m.add_field("u", FieldKind::Scalar, 1);
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    const Vec3 p = m.position(Vertex(v));
    f[Vertex(v)][0] = std::sin(3 * p.x) + p.y * p.y;
  }
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::HessianField;
  o.metric.field = "u";
  o.metric.error = 0.005;
  o.cycles = 3;
  const remesh::AdaptResult r = remesh::adapt({std::move(m)}, o);
  REQUIRE(r.mesh.validate().ok());
  const Property<FieldValue> u = r.mesh.get_field("u");
  double worst = 0;
  for (int v = 0; v < r.mesh.vertex_capacity(); ++v) {
    const Vec3 p = r.mesh.position(Vertex(v));
    worst = std::max(worst, std::abs(u[Vertex(v)][0] - (std::sin(3 * p.x) + p.y * p.y)));
  }
  // Carried by linear interpolation through the cycles: within the P1
  // interpolation error of the grid (|f''| h^2 / 8 ~ 9 / 144 / 8 per cycle).
  CHECK(worst < 0.03);
  CHECK(r.cycles.size() >= 2);
}

TEST_CASE("adapt options: refused before any work, the mesh untouched") {
  remesh::AdaptOptions o = hessian_options("x*x");
  CHECK_THROWS_AS(remesh::adapt({test::build(test::square_grid(2))}, o), Error);  // no target
  o.metric.error = 0.01;
  o.cycles = 0;
  CHECK_THROWS_AS(remesh::adapt({test::build(test::square_grid(2))}, o), Error);
  o.cycles = 1;
  o.metric.source = MetricRecipe::Source::HessianField;
  o.metric.field = "absent";
  CHECK_THROWS_WITH_AS(remesh::adapt({test::build(test::square_grid(2))}, o), doctest::Contains("absent"), Error);
}

TEST_CASE("outputs are checked writable before an adaptation starts") {
  const auto dir = test::temp_dir("adapt_unwritable");
  CHECK_THROWS_AS(check_writable(dir.string()), IoError);
  CHECK_THROWS_AS(check_writable((dir / "missing" / "out.mesh").string()), IoError);
  CHECK_NOTHROW(check_writable((dir / "out.mesh").string()));
  CHECK(std::filesystem::is_empty(dir));  // the probe is removed
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  int status = -1;
  const std::string text = test::capture(std::string(ANISURF_BINARY) + " adapt '" + mesh + "' --size 0.05 -o '" +
                                             (dir / "missing" / "out.mesh").string() + "' 2>&1",
                                         &status);
  CHECK(status != 0);
  CHECK(text.find("missing/out.mesh") != std::string::npos);
}

TEST_CASE("adapt: a metric whose predicted output cannot fit in memory is refused before any pass") {
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Iso;
  o.metric.iso = 1e-6;  // ~2.3e12 vertices on the unit square
  o.metric.hgrad = 0;
  CHECK_THROWS_WITH_AS(remesh::adapt({test::build(test::square_grid(4))}, o), doctest::Contains("predicts"), Error);
  o.metric.iso = 0.05;
  o.memory_limit = 1e5;  // 100 kB: 550 predicted vertices need ~220 kB
  CHECK_THROWS_WITH_AS(remesh::adapt({test::build(test::square_grid(4))}, o), doctest::Contains("refused"), Error);
  o.memory_limit = 0;
  CHECK(remesh::adapt({test::build(test::square_grid(4))}, o).mesh.validate().ok());
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  int status = -1;
  const auto dir = test::temp_dir("adapt_too_small");
  const std::string text = test::capture(std::string(ANISURF_BINARY) + " adapt '" + mesh + "' --size 3.5e-6 -o '" +
                                             (dir / "out.mesh").string() + "' 2>&1",
                                         &status);
  CHECK(status != 0);
  CHECK(text.find("predicts") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "out.mesh"));
}

TEST_CASE("anisurf adapt --weld: a triangle soup in any format adapts as one surface") {
  const auto dir = test::temp_dir("adapt_weld");
  const std::string soup = (dir / "soup.mesh").string();
  {
    // The unit square as two triangles that share no vertex (6 vertices).
    std::ofstream f(soup);
    f << "MeshVersionFormatted 2\nDimension 3\nVertices\n6\n"
         "0 0 0 0\n1 0 0 0\n1 1 0 0\n0 0 0 0\n1 1 0 0\n0 1 0 0\nTriangles\n2\n1 2 3 0\n4 5 6 0\nEnd\n";
  }
  auto adapted = [&](const std::string& extra, const std::string& name) {
    int status = -1;
    const std::string out = (dir / name).string();
    test::capture(std::string(ANISURF_BINARY) + " adapt '" + soup + "' --size 0.1 -v 0 " + extra + " -o '" + out + "'",
                  &status);
    REQUIRE(status == 0);
    return compute_stats(load_mesh(out));
  };
  const MeshStats apart = adapted("", "apart.mesh");
  const MeshStats welded = adapted("--weld 0", "welded.mesh");
  CHECK(apart.components == 2);
  CHECK(welded.components == 1);
  CHECK(welded.boundary_loops == 1);
  int status = -1;
  test::capture(std::string(ANISURF_BINARY) + " adapt '" + soup + "' --size 0.1 --weld 0.5 -o '" +
                    (dir / "x.mesh").string() + "' 2>&1",
                &status);
  CHECK(status == 2);  // a usage error
}

TEST_CASE("adapt surface auto: polyhedral for a coarsening whose G1 surface would lie within 0.05 h of the facets") {
  // icosphere(5): edges of about 0.033 on the unit sphere, turning by about
  // 0.02 rad from facet to facet: a chord sags by 8e-5.
  const SurfaceMesh fine = test::build(test::icosphere(5));
  auto iso = [](const SurfaceMesh& m, double h) {
    return MetricField(static_cast<std::size_t>(m.vertex_capacity()), isotropic_metric(h));
  };
  using remesh::SurfaceKind;
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.3)) == SurfaceKind::Polyhedral);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.06)) == SurfaceKind::Polyhedral);
  // Edges up to 1.21 long in the metric (the longest is 0.0413): below
  // lmax, the split pass leaves them.
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.034)) == SurfaceKind::Polyhedral);
  // A refinement is rebuilt on the smooth surface, however flat the facets.
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.02)) == SurfaceKind::G1);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.01)) == SurfaceKind::G1);
  // The largest sagitta (1.23e-4) against hausd / 2: above 5e-5, below 1.5e-4.
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.3), 1e-4) == SurfaceKind::G1);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.3), 3e-4) == SurfaceKind::Polyhedral);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, iso(fine, 0.3), 1e-3) == SurfaceKind::Polyhedral);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, MetricField{}) == SurfaceKind::G1);
  CHECK(remesh::resolve_surface(SurfaceKind::G1, fine, iso(fine, 0.3)) == SurfaceKind::G1);
  CHECK(remesh::resolve_surface(SurfaceKind::Polyhedral, fine, iso(fine, 0.001)) == SurfaceKind::Polyhedral);
  // One vertex asking for a size below its edges: G1.
  MetricField local = iso(fine, 0.3);
  local[0] = isotropic_metric(0.01);
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, fine, local) == SurfaceKind::G1);
  // The edges judged in chunks on several threads (icosphere(6): 3 chunks
  // of corner slots on 3 threads): one vertex's edges decide wherever they lie.
  {
    const test::ThreadLimitScope scope(thread_limit().load());
    thread_limit() = 3;
    const SurfaceMesh finer = test::build(test::icosphere(6));
    CHECK(remesh::resolve_surface(SurfaceKind::Auto, finer, iso(finer, 0.3)) == SurfaceKind::Polyhedral);
    for (int v : {0, finer.vertex_capacity() / 2, finer.vertex_capacity() - 1}) {
      CAPTURE(v);
      MetricField one = iso(finer, 0.3);
      one[static_cast<std::size_t>(v)] = isotropic_metric(0.005);
      CHECK(remesh::resolve_surface(SurfaceKind::Auto, finer, one) == SurfaceKind::G1);
    }
  }
  // A coarse sphere (edges of 0.5, facets turning by 0.4 rad) refined: G1.
  const SurfaceMesh coarse = test::build(test::icosphere(1));
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, coarse, iso(coarse, 0.1)) == SurfaceKind::G1);
  // A flat grid (its corners tagged as adapt() tags them) coarsened: polyhedral.
  SurfaceMesh flat = test::build(test::square_grid(4));
  detect_features(flat, FeatureOptions{});
  CHECK(remesh::resolve_surface(SurfaceKind::Auto, flat, iso(flat, 0.5)) == SurfaceKind::Polyhedral);

  // The coarsening runs on the facets, stays on the sphere and in band.
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Iso;
  o.metric.iso = 0.3;
  const remesh::AdaptResult r = remesh::adapt({fine}, o);
  REQUIRE(r.mesh.validate().ok());
  CHECK(r.surface == "polyhedral");
  CHECK(r.cycles.back().final.in_band_share > 0.95);
  double off = 0;
  for (Vertex v : r.mesh.vertices()) off = std::max(off, std::abs(norm(r.mesh.position(v)) - 1.0));
  CHECK(off < 3e-4);  // on the facets: within their sagitta 0.033^2 / 8 = 1.4e-4 of the sphere
  o.surface = SurfaceKind::G1;
  CHECK(remesh::adapt({fine}, o).surface == "g1-bezier");
}
