// Constrained projections (report 4.2: boundary and feature points project
// onto boundary and feature curves only; corners stay corners) and the
// interpolation of vertex fields at a located point.
#include <doctest/doctest.h>

#include <random>

#include "io/mesh_io.h"
#include "locate/interpolate.h"
#include "locate/locator.h"
#include "test_locate_util.h"
#include "test_util.h"

using namespace anisurf;

namespace {

// Tags as kRidge the edges whose dihedral angle exceeds `degrees`, and as
// kCorner the vertices where the number of tagged edges is neither 0 nor 2.
void tag_sharp_edges(SurfaceMesh& m, double degrees) {
  const double cos_max = std::cos(degrees * M_PI / 180);
  for (int c = 0; c < 3 * m.triangle_capacity(); ++c) {
    const Corner ch(c), o = m.opposite(ch);
    if (!o.is_valid() || o.idx < c || m.is_deleted(SurfaceMesh::triangle(ch))) continue;
    const Vec3 n0 = normalized(m.triangle_normal(SurfaceMesh::triangle(ch)));
    const Vec3 n1 = normalized(m.triangle_normal(SurfaceMesh::triangle(o)));
    if (dot(n0, n1) < cos_max) m.add_edge_tag(ch, kRidge);
  }
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    int n = 0;
    for (Corner c : m.fan(Vertex(v))) n += m.has_tag(SurfaceMesh::prev(c), kRidge);
    if (n != 0 && n != 2) m.add_vertex_tag(Vertex(v), kCorner);
  }
}

double brute_force_corner_d2(const SurfaceMesh& m, const Vec3& x, std::uint8_t tags) {
  double best = INFINITY;
  for (int v = 0; v < m.vertex_capacity(); ++v)
    if (!m.is_deleted(Vertex(v)) && (m.vertex_tags(Vertex(v)) & tags)) best = std::min(best, norm2(x - m.position(Vertex(v))));
  return best;
}

// The location lies on the feature edge it names.
bool on_its_feature_edge(const SurfaceMesh& m, const Location& r, std::uint8_t tags) {
  if (!r.edge.is_valid() || SurfaceMesh::triangle(r.edge) != r.triangle) return false;
  if (!(m.edge_tags(r.edge) & tags)) return false;
  return r.bary[SurfaceMesh::local_index(r.edge)] == 0;
}

}  // namespace

TEST_CASE("feature-constrained projections on fandisk's ridges and corners") {
  ANISURF_REQUIRE_SHARED(path, "meshes/fandisk.off");
  SurfaceMesh m = load_mesh(path);
  tag_sharp_edges(m, 30);
  Locator loc(m);
  REQUIRE(loc.n_feature_edges() > 100);
  REQUIRE(loc.n_corners() > 4);
  const test::PointSampler sample(m);
  const double diag = sample.diagonal();
  std::mt19937_64 rng(31);
  int bad = 0, off_edge = 0, inconsistent = 0, certified = 0;
  long long steps = 0;
  Hint prev;
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    const auto np = sample(rng, 1e-4, 1e-2);
    const double ref = std::sqrt(test::brute_force_feature_d2(m, np.x, kRidge));
    const std::array<Hint, 2> hints{prev, Hint{Triangle(np.source)}};
    const Location r = loc.project(np.x, hints, Constraint::OnFeature);
    const Location u = loc.project(np.x, Hint{}, Constraint::OnFeature);
    CHECK(r.constraint == Constraint::OnFeature);
    if (!test::same_distance(r.distance, ref, diag) || !test::same_distance(u.distance, ref, diag)) ++bad;
    if (!on_its_feature_edge(m, r, kRidge) || !on_its_feature_edge(m, u, kRidge)) ++off_edge;
    if (!test::consistent(m, r, np.x)) ++inconsistent;
    certified += !r.used_fallback;
    steps += r.steps;
    prev = r.hint();
  }
  CHECK(bad == 0);
  CHECK(off_edge == 0);
  CHECK(inconsistent == 0);
  MESSAGE("fandisk ridges: " << certified << "/" << n << " certified by the descent along the curves, mean steps "
                             << double(steps) / n);

  // Points sliding along a ridge, each hinted by the previous answer: the
  // descent follows the curve and certifies locally.
  int c = 0;
  while (!(m.edge_tags(Corner(c)) & kRidge)) ++c;
  Location last = loc.project(m.position(m.edge_from(Corner(c))), Hint{SurfaceMesh::triangle(Corner(c))},
                              Constraint::OnFeature);
  int local = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 x = last.point + Vec3(1e-4, -2e-4, 1.5e-4) * diag;
    last = loc.project(x, last.hint(), Constraint::OnFeature);
    CHECK(test::same_distance(last.distance, std::sqrt(test::brute_force_feature_d2(m, x, kRidge)), diag));
    local += !last.used_fallback;
  }
  CHECK(local > 150);

  // Fixed corners.
  for (int i = 0; i < 500; ++i) {
    const auto np = sample(rng, 1e-3, 5e-2);
    const Location r = loc.project(np.x, Hint{Triangle(np.source)}, Constraint::Fixed);
    REQUIRE(r.vertex.is_valid());
    CHECK(r.constraint == Constraint::Fixed);
    CHECK(m.has_tag(r.vertex, kCorner));
    CHECK(r.point == m.position(r.vertex));
    CHECK(m.vertex(r.triangle, SurfaceMesh::local_index(m.corner_of(r.triangle, r.vertex))) == r.vertex);
    CHECK(r.bary[SurfaceMesh::local_index(m.corner_of(r.triangle, r.vertex))] == 1);
    CHECK(test::same_distance(r.distance, std::sqrt(brute_force_corner_d2(m, np.x, kCorner)), diag));
  }
}

TEST_CASE("boundary points project onto the boundary (beetle), weaker constraints where there is nothing to hold") {
  ANISURF_REQUIRE_SHARED(path, "meshes/beetle.off");
  const SurfaceMesh m = load_mesh(path);
  Locator loc(m);
  CHECK(loc.n_feature_edges() == 1136);  // the boundary edges (kBoundary)
  CHECK(loc.n_corners() == 0);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(32);
  int bad = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto np = sample(rng, 1e-4, 1e-2);
    const Location r = loc.project(np.x, Hint{Triangle(np.source)}, Constraint::OnFeature);
    bad += !on_its_feature_edge(m, r, kBoundary) ||
           !test::same_distance(r.distance, std::sqrt(test::brute_force_feature_d2(m, np.x, kBoundary)), sample.diagonal());
    // No corner on beetle: a Fixed query holds to the feature curves.
    const Location f = loc.project(np.x, Hint{Triangle(np.source)}, Constraint::Fixed);
    CHECK(f.constraint == Constraint::OnFeature);
    CHECK(f.distance == r.distance);
  }
  CHECK(bad == 0);

  // A closed smooth mesh without tags: constrained queries become free ones.
  ANISURF_REQUIRE_SHARED(torus_path, "meshes/torus.STL");
  const SurfaceMesh torus = load_mesh(torus_path);
  Locator tl(torus);
  CHECK(tl.n_feature_edges() == 0);
  const Vec3 x = torus.position(Vertex(0)) + Vec3(0.01, 0.02, 0.03);
  const Location a = tl.project(x, Hint{}, Constraint::Fixed), b = tl.project(x);
  CHECK(a.constraint == Constraint::Free);
  CHECK(a.distance == b.distance);
}

TEST_CASE("vertex constraints of T_1 and propagation under constraints") {
  ANISURF_REQUIRE_SHARED(path, "meshes/fandisk.off");
  SurfaceMesh g = load_mesh(path);
  tag_sharp_edges(g, 30);
  Locator loc(g);
  // T_1: the same mesh moved slightly (tags kept).
  SurfaceMesh t1 = g;
  std::mt19937_64 rng(33);
  std::normal_distribution<double> gauss;
  const double diag = g.bbox().diagonal();
  for (int v = 0; v < t1.vertex_capacity(); ++v) t1.position(Vertex(v)) += Vec3(gauss(rng), gauss(rng), gauss(rng)) * (1e-4 * diag);
  int n_fixed = 0, n_feature = 0;
  for (int v = 0; v < t1.vertex_capacity(); ++v) {
    const Constraint c = vertex_constraint(t1, Vertex(v));
    n_fixed += c == Constraint::Fixed;
    n_feature += c == Constraint::OnFeature;
    CHECK((c == Constraint::Fixed) == t1.has_tag(Vertex(v), kCorner));
  }
  CHECK(n_fixed == loc.n_corners());
  CHECK(n_feature > 0);
  std::vector<Hint> hints;
  PropagationStats st;
  const std::vector<Location> r = project_vertices(t1, loc, hints, true, &st);
  int bad = 0;
  for (int v = 0; v < t1.vertex_capacity(); ++v) {
    const Vertex vh(v);
    const Vec3& x = t1.position(vh);
    const Constraint c = vertex_constraint(t1, vh);
    CHECK(r[v].constraint == c);
    double ref2;
    if (c == Constraint::Fixed) {
      ref2 = brute_force_corner_d2(g, x, kCorner);
      // Each corner finds its own copy (moved by 1e-4 of the diagonal).
      CHECK(r[v].vertex == vh);
    } else if (c == Constraint::OnFeature) {
      if (v % 5) continue;  // brute force on a fifth of them
      ref2 = test::brute_force_feature_d2(g, x, kRidge);
      CHECK(on_its_feature_edge(g, r[v], kRidge));
    } else {
      if (v % 20) continue;
      ref2 = test::brute_force_d2(g, test::live_triangles(g), x);
    }
    bad += !test::same_distance(r[v].distance, std::sqrt(ref2), diag);
  }
  CHECK(bad == 0);
  CHECK(st.seeds == 1);
  // A neighbour's result is a few triangles away: a few moves (the walk
  // towards a free point moves one triangle at a time).
  CHECK(st.mean_steps() < 3);
}

TEST_CASE("interpolation of vertex fields at a located point reproduces linear fields") {
  ANISURF_REQUIRE_SHARED(path, "meshes/bunny.off");
  SurfaceMesh m = load_mesh(path);
  const Vec3 a(0.3, -1.2, 2.5);
  const double b = 0.7;
  auto lin = [&](const Vec3& p) { return dot(a, p) + b; };
  Property<double> fs = m.add_vertex_property<double>("f");
  Property<Vec3> fp = m.add_vertex_property<Vec3>("p");
  Property<FieldValue> fv = m.add_field("sol", FieldKind::Tensor, 6);
  MetricField metric(static_cast<std::size_t>(m.vertex_capacity()));
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    const Vec3& p = m.position(Vertex(v));
    fs[Vertex(v)] = lin(p);
    fp[Vertex(v)] = p;
    fv[Vertex(v)] = {lin(p), 2 * lin(p), p.x, p.y, p.z, -lin(p)};
    // A metric whose coefficients are linear in the position (and SPD on the bunny).
    metric[v] = SymTensor3(10 + p.x, 0.1 * p.y, 10 + p.z, 0, 0.2 * p.x, 12);
  }
  Locator loc(m);
  const test::PointSampler sample(m);
  std::mt19937_64 rng(34);
  for (int i = 0; i < 300; ++i) {
    const auto np = sample(rng, 1e-3, 2e-2);
    const Location r = loc.project(np.x, Hint{Triangle(np.source)});
    const Vec3& q = r.point;
    CHECK(interpolate(m, r, fs) == doctest::Approx(lin(q)).epsilon(1e-12));
    CHECK(norm(interpolate(m, r, fp) - q) <= 1e-12 * norm(q));
    const FieldValue v = interpolate_field(m, r, "sol");
    CHECK(v[1] == doctest::Approx(2 * lin(q)).epsilon(1e-12));
    CHECK(v[3] == doctest::Approx(q.y).epsilon(1e-12));
    const SymTensor3 M = interpolate_metric(m, metric, r, MetricInterpolation::Linear);
    CHECK(M.xx() == doctest::Approx(10 + q.x).epsilon(1e-12));
    CHECK(M.yz() == doctest::Approx(0.2 * q.x).epsilon(1e-12));
    // A constant metric stays constant under every law.
    MetricField constant(metric.size(), SymTensor3(4, 1, 3, 0.5, 0.2, 2));
    for (MetricInterpolation how : {MetricInterpolation::Linear, MetricInterpolation::Inverse,
                                    MetricInterpolation::LinearSize, MetricInterpolation::LogEuclidean}) {
      const SymTensor3 C = interpolate_metric(m, constant, r, how);
      for (int k = 0; k < 6; ++k) CHECK(C.m[k] == doctest::Approx(constant[0].m[k]).epsilon(1e-9));
    }
  }
  Location any;
  any.triangle = Triangle(0);
  any.bary = {1, 0, 0};
  CHECK_THROWS_AS(interpolate_field(m, any, "nope"), Error);
}
