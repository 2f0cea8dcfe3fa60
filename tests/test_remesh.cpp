// The remesher (engine/remesh): every operator keeps the mesh valid and
// uninverted, new vertices lie on the geometry with the metric of T_0,
// fixed and feature vertices are respected, and whole runs reach the metric.
#include <doctest/doctest.h>

#include <algorithm>
#include <stdexcept>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <unordered_map>

#include "geometry/features.h"
#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "mesh/build.h"
#include "mesh/operators.h"
#include "metric/metric_field.h"
#include "metric/quality.h"
#include "metric/surface_metric.h"
#include "remesh/adapt.h"
#include "remesh/remesher.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::remesh;

namespace {

// T_G = T_0 = the input mesh with its features; T_1 a copy being adapted.
struct Setup {
  SurfaceMesh input;
  std::unique_ptr<GeometrySurface> geometry;
  std::unique_ptr<ControlSpace> control;
  std::unique_ptr<AdaptedMesh> adapted;
};

std::unique_ptr<Setup> make_setup(const std::string& mesh_path, const std::string& sol_path, double iso_size,
                                  bool g1, const InputBound& bound = {}) {
  auto s = std::make_unique<Setup>();
  BuildReport report;
  s->input = load_mesh(mesh_path, &report);
  MetricField metric;
  if (!sol_path.empty()) {
    attach_fields(s->input, read_sol(sol_path, report.input_vertices), report);
    metric = metric_from_field(s->input, {}, report.vertex_origin);
  } else {
    metric.assign(static_cast<std::size_t>(s->input.vertex_capacity()), isotropic_metric(iso_size));
  }
  detect_features(s->input);
  if (g1)
    s->geometry = std::make_unique<BezierGeometry>(s->input);
  else
    s->geometry = std::make_unique<PolyhedralSurface>(s->input);
  s->control = std::make_unique<ControlSpace>(s->input, metric, true, MetricInterpolation::Linear, "sol0");
  s->adapted = std::make_unique<AdaptedMesh>(s->input, *s->geometry, *s->control, LengthFormula::LinearMetric, false,
                                             bound);
  return s;
}

// An icosphere of `levels` whose vertices are moved in and out by up to
// `jitter` of the radius (seeded), as T_G = T_0 = T_1 on its polyhedral
// surface with an isotropic metric of size h.
struct JitteredSphere {
  SurfaceMesh input;
  MetricField metric;
  std::unique_ptr<PolyhedralSurface> geometry;
  std::unique_ptr<ControlSpace> control;
  std::unique_ptr<AdaptedMesh> adapted;
  JitteredSphere(int levels, double jitter, unsigned seed, double h, const FeatureOptions& features) {
    input = test::build(test::jittered_icosphere(levels, 1 - jitter, 1 + jitter, seed));
    detect_features(input, features);
    geometry = std::make_unique<PolyhedralSurface>(input);
    metric.assign(static_cast<std::size_t>(input.vertex_capacity()), isotropic_metric(h));
    control = std::make_unique<ControlSpace>(input, metric, true, MetricInterpolation::Linear, "sol0");
    adapted = std::make_unique<AdaptedMesh>(input, *geometry, *control, LengthFormula::LinearMetric, false);
  }
};

int count_tag(const SurfaceMesh& m, Tag t) {
  int n = 0;
  for (int i = 0; i < m.vertex_capacity(); ++i)
    if (!m.is_deleted(Vertex(i)) && m.has_tag(Vertex(i), t)) ++n;
  return n;
}

// Checks after a pass: connectivity invariants and orientation.
void check_state(AdaptedMesh& a, const char* what) {
  const ValidationReport v = a.mesh().validate();
  INFO(what);
  REQUIRE_MESSAGE(v.ok(), v.summary());
  CHECK(a.count_inverted() == 0);
}

// Runs the loop of Remesher::run() pass by pass, checking after each.
std::vector<PassReport> run_checked(Remesher& r, AdaptedMesh& a, int max_rounds) {
  std::vector<PassReport> out;
  auto one = [&](PassKind k) {
    out.push_back(r.step(k));
    check_state(a, std::string(pass_name(k)).c_str());
    return out.back();
  };
  one(PassKind::Swap);
  for (int it = 0; it < max_rounds; ++it) {
    const int s = one(PassKind::Split).splits;
    const int c = one(PassKind::Collapse).collapses;
    one(PassKind::Swap);
    one(PassKind::Smooth);
    if (s + c == 0) break;
  }
  one(PassKind::Final);
  return out;
}

}  // namespace

TEST_CASE("remesh: T_1 starts on T_G with the metric of T_0 at every vertex") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, true);
  AdaptedMesh& a = *s->adapted;
  for (int i = 0; i < a.mesh().vertex_capacity(); ++i) {
    const Vertex v(i);
    CHECK(a.mesh().position(v) == s->input.position(v));
    for (int k = 0; k < 6; ++k) CHECK(a.metric(v).m[k] == doctest::Approx(s->control->metric()[i].m[k]));
  }
  check_state(a, "initial");
}

TEST_CASE("control space: the target's complexity computed, or taken as the caller measured it") {
  const SurfaceMesh mesh = test::build(test::icosphere(2));
  MetricField metric(static_cast<std::size_t>(mesh.vertex_capacity()), isotropic_metric(0.3));
  for (int i = 0; i < mesh.vertex_capacity(); i += 3) metric[static_cast<std::size_t>(i)] = isotropic_metric(0.15);
  const double measured = metric_complexity(mesh, metric);
  REQUIRE(measured > 0);
  AdaptOptions o;
  const auto computed = make_control(mesh, metric, true, o);
  CHECK(computed->target_complexity() == measured);
  const auto given = make_control(mesh, metric, true, o, 2.5 * measured);
  CHECK(given->target_complexity() == 2.5 * measured);
}

TEST_CASE("remesh: random operator sequences keep the mesh valid, on the surface and uninverted") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  for (const bool g1 : {false, true}) {
    auto s = make_setup(mesh, sol, 0, g1);
    AdaptedMesh& a = *s->adapted;
    SurfaceMesh& m = a.mesh();
    const OperatorOptions o;
    std::mt19937 rng(7);
    const int boundary_before = [&] {
      int n = 0;
      for (int i = 0; i < m.vertex_capacity(); ++i)
        if (!m.is_deleted(Vertex(i)) && m.is_boundary(Vertex(i))) ++n;
      return n;
    }();
    int done[4] = {0, 0, 0, 0};
    for (int step = 0; step < 1500; ++step) {
      const int t = std::uniform_int_distribution<int>(0, m.triangle_capacity() - 1)(rng);
      if (m.is_deleted(Triangle(t))) continue;
      const Corner c = SurfaceMesh::corner(Triangle(t), std::uniform_int_distribution<int>(0, 2)(rng));
      const int op = step < 600 ? 0 : std::uniform_int_distribution<int>(0, 3)(rng);
      if (op == 0) {
        const SplitPlan p = can_split(a, c, o);
        if (p.why != Rejection::None) continue;
        const Vertex v = split(a, c, p);
        if (p.swap_instead) {
          CHECK(!v.is_valid());
          continue;
        }
        // On the geometry (or at the admitted straight midpoint), with T_0's metric there.
        if (p.projected && !g1) {
          const Projection pr = a.geometry().project(m.position(v), {}, Constraint::Free);
          CHECK(pr.location.distance < 1e-9);
        }
        // (or, where the surface point was refused or too far from the
        // input, on or near the input's triangles)
        if (p.projected && g1 && !p.at.pulled) CHECK(std::abs(norm(m.position(v)) - 1.0) < 5e-3);
        if (p.projected && p.at.pulled) {
          CHECK(norm(m.position(v) - p.at.on_input) <= a.input_tolerance(p.at.hint_g.triangle, p.at.values.metric) + 1e-9);
        }
        CHECK(is_spd(a.metric(v)));
      } else if (op == 1) {
        const CollapsePlan p = can_collapse(a, c, o);
        if (p.why != Rejection::None) continue;
        CHECK(a.kind(p.removed) != VertexKind::Fixed);
        collapse(a, p);
      } else if (op == 2) {
        if (can_swap(a, c, o).why != Rejection::None) continue;
        swap(a, c);
      } else {
        const Vertex v = m.vertex(c);
        const bool was_on_surface = a.on_surface(v);
        const MovePlan p = can_move(a, v, o);
        // The displacement starts at most max_move of the shortest edge and
        // is halved no further than min_move of it.
        if (was_on_surface) CHECK(p.tries <= 1 + static_cast<int>(std::ceil(std::log2(o.max_move / o.min_move))));
        if (p.why != Rejection::None) continue;
        // A vertex left off the surface (a split at the straight midpoint) is
        // projected whatever the quality; any other move does not lower it.
        if (a.on_surface(v)) CHECK(p.quality_after >= p.quality_before);
        move(a, v, p);
      }
      ++done[op];
      const ValidationReport r = m.validate();
      REQUIRE_MESSAGE(r.ok(), r.summary());
    }
    CHECK(done[0] > 100);
    CHECK(done[1] > 10);
    CHECK(done[2] > 10);
    CHECK(done[3] > 10);
    CHECK(a.count_inverted() == 0);
    // The boundary circle is kept: its vertices were only split along it or collapsed along it.
    int boundary_after = 0;
    for (int i = 0; i < m.vertex_capacity(); ++i)
      if (!m.is_deleted(Vertex(i)) && m.is_boundary(Vertex(i))) {
        ++boundary_after;
        CHECK(std::abs(m.position(Vertex(i)).z) < 1e-6);  // hemi's rim lies in z = 0
      }
    CHECK(boundary_after >= boundary_before);
  }
}

TEST_CASE("remesh: sphere20k with h = 0.05, every pass valid and uninverted, the band reached") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/sphere20k_iso.sol");
  auto s = make_setup(mesh, sol, 0, false);
  RemeshOptions o;
  o.op.lmin = 0.72;
  Remesher r(*s->adapted, o);
  const PassReport before = r.measure();
  const auto passes = run_checked(r, *s->adapted, 20);
  const PassReport after = r.measure();
  CHECK(before.in_band_share < 0.9);
  CHECK(after.in_band_share > 0.97);
  CHECK(after.q_min > 0.5);
  CHECK(after.length_max <= o.op.lmax * 1.05);
  // On the unit sphere (polyhedral T_G: within its chordal error).
  for (int i = 0; i < s->adapted->mesh().vertex_capacity(); ++i)
    if (!s->adapted->mesh().is_deleted(Vertex(i)))
      CHECK(std::abs(norm(s->adapted->mesh().position(Vertex(i))) - 1.0) < 1e-3);
  // Each report counts what changed; touched ids are live or reused slots.
  int total = 0;
  for (const auto& p : passes) total += p.changes();
  CHECK(total > 0);
}

TEST_CASE("remesh: hemi with h = 0.085 on the G1 surface, valid passes, vertices near the unit sphere") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  // The report's section 7.2: the smooth surface of a coarse input, free of
  // the bound to its facets (adapt --free-surface).
  InputBound free;
  free.enabled = false;
  auto s = make_setup(mesh, sol, 0, true, free);
  RemeshOptions o;
  o.op.lmin = 0.72;
  Remesher r(*s->adapted, o);
  run_checked(r, *s->adapted, 20);
  const PassReport after = r.measure();
  CHECK(after.vertices > 500);
  CHECK(after.in_band_share > 0.95);
  CHECK(after.q_min > 0.3);
  double worst = 0;
  for (int i = 0; i < s->adapted->mesh().vertex_capacity(); ++i)
    if (!s->adapted->mesh().is_deleted(Vertex(i)))
      worst = std::max(worst, std::abs(norm(s->adapted->mesh().position(Vertex(i))) - 1.0));
  // The coarse polyhedron is 1.4e-2 away from the sphere; the G1 surface much closer.
  CHECK(worst < 5e-3);
}

TEST_CASE("remesh: fandisk with h = diagonal/50 keeps its ridges and corners") {
  ANISURF_REQUIRE_SHARED(mesh, "meshes/fandisk.off");
  auto s = make_setup(mesh, "", 0, false);
  const double h = s->input.bbox().diagonal() / 50;
  s = make_setup(mesh, "", h, false);
  const int ridges_in = count_tag(s->input, kRidge);
  REQUIRE(ridges_in > 0);
  RemeshOptions o;
  o.op.lmin = 0.72;
  Remesher r(*s->adapted, o);
  run_checked(r, *s->adapted, 20);
  const SurfaceMesh& out = s->adapted->mesh();
  CHECK(r.measure().in_band_share > 0.9);

  // Every output ridge edge lies on an input ridge curve: its ends on the
  // input feature edges, its midpoint within the sag the operators allow
  // (OperatorOptions::curve_sag of the size h).
  Locator features(s->input);
  int ridge_edges = 0;
  double worst_sag = 0;
  double ridge_length_out = 0, ridge_length_in = 0;
  for (int t = 0; t < s->input.triangle_capacity(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(Triangle(t), k);
      if (s->input.canonical(c) == c && s->input.has_tag(c, kRidge))
        ridge_length_in += norm(s->input.position(s->input.edge_to(c)) - s->input.position(s->input.edge_from(c)));
    }
  for (int t = 0; t < out.triangle_capacity(); ++t) {
    if (out.is_deleted(Triangle(t))) continue;
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(Triangle(t), k);
      if (out.canonical(c) != c || !out.has_tag(c, kRidge)) continue;
      ++ridge_edges;
      const Vec3 a = out.position(out.edge_from(c)), b = out.position(out.edge_to(c));
      ridge_length_out += norm(b - a);
      int which = 0;
      for (const Vec3& x : {a, b, 0.5 * (a + b)}) {
        const Location l = features.project(x, {}, Constraint::OnFeature);
        CHECK(l.constraint == Constraint::OnFeature);
        if (which == 2) worst_sag = std::max(worst_sag, l.distance);
        CHECK_MESSAGE(l.distance <= (which == 2 ? o.op.curve_sag * h * (1 + 1e-9) : 1e-9 * h), "point " << which << " of ridge edge " << out.edge_from(c).idx << "-" << out.edge_to(c).idx << " length " << norm(b - a) / h);
        ++which;
      }
    }
  }
  CHECK(ridge_edges > 0);
  MESSAGE("fandisk: " << ridge_edges << " ridge edges, largest sag " << worst_sag / h << " h; ridge length " << ridge_length_out / ridge_length_in << " of the input's");
  // The curves survive whole: the chords are at most a little shorter than the input polylines.
  CHECK(ridge_length_out <= ridge_length_in * (1 + 1e-9));
  CHECK(ridge_length_out >= 0.98 * ridge_length_in);
  // Corners are fixed: every input corner is still a vertex.
  Locator all(s->input);
  for (int i = 0; i < s->input.vertex_capacity(); ++i) {
    const Vertex v(i);
    if (!s->input.has_tag(v, kCorner)) continue;
    bool found = false;
    for (int j = 0; j < out.vertex_capacity() && !found; ++j)
      found = !out.is_deleted(Vertex(j)) && out.position(Vertex(j)) == s->input.position(v);
    CHECK_MESSAGE(found, "corner " << i << " lost");
  }
}

TEST_CASE("remesh: the solution of T_0 is interpolated at every new and moved vertex (exact for a linear field)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  SurfaceMesh input = load_mesh(mesh);
  detect_features(input);
  // f(x, y, z) = (x + 2y - z, 3z): linear, so its interpolation on the
  // polyhedral T_G at a vertex's location is its value at that position.
  Property<FieldValue> f = input.add_field("f", FieldKind::Vector, 2);
  for (int i = 0; i < input.vertex_capacity(); ++i) {
    const Vec3& p = input.position(Vertex(i));
    f[Vertex(i)] = {p.x + 2 * p.y - p.z, 3 * p.z, 0, 0, 0, 0};
  }
  const MetricField metric(static_cast<std::size_t>(input.vertex_capacity()), isotropic_metric(0.08));
  PolyhedralSurface geometry(input);
  ControlSpace control(input, metric, true);
  REQUIRE(control.field_infos().size() == 1);
  AdaptedMesh a(input, geometry, control);
  Remesher r(a);
  const auto passes = r.run();
  const SurfaceMesh& out = a.mesh();
  CHECK(out.n_vertices() < input.n_vertices() / 2);  // h = 0.08: coarsened
  const Property<FieldValue> g = out.get_field("f");
  REQUIRE(g.is_valid());
  for (int i = 0; i < out.vertex_capacity(); ++i) {
    const Vertex v(i);
    if (out.is_deleted(v)) continue;
    const Vec3& p = out.position(v);
    CHECK(g[v][0] == doctest::Approx(p.x + 2 * p.y - p.z).epsilon(1e-9));
    CHECK(g[v][1] == doctest::Approx(3 * p.z).epsilon(1e-9));
  }
}

TEST_CASE("remesh: measure() sums its blocks of triangles alike on any number of threads") {
  // An icosphere of 81920 triangles (5 blocks of slots), its vertices moved
  // off the sphere so that lengths and qualities differ from triangle to
  // triangle: the same figures, bit for bit, on 1 and 3 threads, and the
  // metric module's figures.
  const JitteredSphere s(6, 0.02, 11, 0.02, FeatureOptions{});
  const MetricField& metric = s.metric;
  AdaptedMesh& adapted = *s.adapted;
  const test::ThreadLimitScope scope(thread_limit().load());
  thread_limit() = 1;
  const PassReport one = Remesher(adapted).measure();
  thread_limit() = 3;
  const PassReport three = Remesher(adapted).measure();
  CHECK(one.triangles == 81920);
  CHECK(one.edges == three.edges);
  CHECK(one.histogram == three.histogram);
  CHECK(one.in_band_share == three.in_band_share);
  CHECK(one.length_min == three.length_min);
  CHECK(one.length_max == three.length_max);
  CHECK(one.q_min == three.q_min);
  CHECK(one.q_mean == three.q_mean);
  const MeshQuality q = measure_mesh_quality(adapted.mesh(), metric);
  CHECK(q.edges == one.edges);
  CHECK(q.in_band_share == doctest::Approx(one.in_band_share));
  CHECK(q.q_min == doctest::Approx(one.q_min));
  CHECK(q.q_mean == doctest::Approx(one.q_mean));
}

TEST_CASE("adapted mesh: T_G's rough triangles are those whose fans turn past 60 degrees (the cone test agrees)") {
  // A sphere whose vertices are moved in and out at random: fans of every
  // spread, some with two triangles more than 60 degrees apart, most not.
  // A triangle is rough when, at one of its vertices, another triangle of
  // the fan turns more than 60 degrees from it (or the vertex is on a
  // feature or near another sheet): the cone shortcut must not change that.
  FeatureOptions no_ridges;
  no_ridges.detect_ridges = false;
  const JitteredSphere s(4, 0.025, 3, 0.05, no_ridges);
  const SurfaceMesh& input = s.input;
  const PolyhedralSurface& geometry = *s.geometry;
  const AdaptedMesh& adapted = *s.adapted;
  std::vector<Vec3> unit(static_cast<std::size_t>(input.triangle_capacity()));
  for (Triangle t : input.triangles()) unit[static_cast<std::size_t>(t.idx)] = normalized(input.triangle_normal(t));
  int rough = 0, wrong = 0;
  for (Triangle t : input.triangles()) {
    bool expected = false;
    for (int k = 0; k < 3; ++k) {
      const Vertex v = input.vertex(t, k);
      double longest = 0;
      for (Vertex w : input.ring_vertices(v)) longest = std::max(longest, norm(input.position(w) - input.position(v)));
      expected = expected || geometry.clearance(v) < 0.25 * longest;
      for (Corner b : input.fan_corners(v))
        expected = expected || dot(unit[static_cast<std::size_t>(t.idx)],
                                   unit[static_cast<std::size_t>(SurfaceMesh::triangle(b).idx)]) < 0.5;
    }
    rough += expected;
    wrong += adapted.near_feature(Hint{t}) != expected;
  }
  INFO(rough << " rough of " << input.n_triangles());
  CHECK(rough > 50);
  CHECK(rough < input.n_triangles() / 2);
  CHECK(wrong == 0);
}

TEST_CASE("adapted mesh: count_inverted counts on several threads what is_inverted finds triangle by triangle") {
  // T_G a sphere of 81920 triangles; T_1 its copy with every 50th vertex
  // pushed past its neighbours along the surface (folded fans): the count in
  // chunks of slots on 1 and 3 threads, each chunk with its own copy of the
  // surface, equals the triangles' own tests.
  const JitteredSphere s(6, 0.0, 1, 0.02, FeatureOptions{});
  SurfaceMesh folded = s.input;
  for (int v = 0; v < folded.vertex_capacity(); v += 50) {
    const Vec3 p = folded.position(Vertex(v));
    Vec3 tangent = cross(p, Vec3(0.3, 0.5, 0.8));
    folded.position(Vertex(v)) = p + 0.05 * normalized(tangent);
  }
  AdaptedMesh adapted(folded, *s.geometry, *s.control, LengthFormula::LinearMetric, false);
  int one_by_one = 0;
  for (Triangle t : adapted.mesh().triangles()) one_by_one += adapted.is_inverted(t);
  const test::ThreadLimitScope scope(1);
  const int on_one = adapted.count_inverted();
  thread_limit() = 3;
  const int on_three = adapted.count_inverted();
  INFO(one_by_one << " inverted of " << adapted.mesh().n_triangles());
  CHECK(one_by_one > 100);
  CHECK(on_one == one_by_one);
  CHECK(on_three == one_by_one);
}

TEST_CASE("remesh: a coarsening's collapses leave their swaps to the fans they settle") {
  // A sphere of 20480 triangles coarsened about 3 times in length: with
  // defer_unsettled_swaps a collapse whose fan still holds an edge to
  // collapse tries no swaps; the fans settled and the swap pass after make
  // up for them. Fewer swaps, a valid mesh and the same shapes after the
  // swap pass.
  struct Outcome {
    int collapses = 0, swaps = 0;
    double q_min = 0, q_mean = 0;
  };
  auto coarsen = [](bool defer) {
    const JitteredSphere s(5, 0.01, 7, 0.15, FeatureOptions{});
    RemeshOptions o;
    o.defer_unsettled_swaps = defer;
    Remesher r(*s.adapted, o);
    const PassReport collapsed = r.step(PassKind::Collapse);
    check_state(*s.adapted, defer ? "deferred collapse pass" : "collapse pass");
    const PassReport swapped = r.step(PassKind::Swap);
    check_state(*s.adapted, "swap pass");
    return Outcome{collapsed.collapses, collapsed.swaps + swapped.swaps, swapped.q_min, swapped.q_mean};
  };
  const Outcome now = coarsen(false), deferred = coarsen(true);
  INFO("swaps " << now.swaps << " -> " << deferred.swaps << ", q min " << now.q_min << " -> " << deferred.q_min
                << ", q mean " << now.q_mean << " -> " << deferred.q_mean);
  CHECK(now.collapses > 5000);
  CHECK(deferred.collapses > 0.95 * now.collapses);
  CHECK(deferred.swaps < 0.8 * now.swaps);
  CHECK(deferred.q_min > 0.8 * now.q_min);
  CHECK(deferred.q_mean > now.q_mean - 0.01);
}

TEST_CASE("remesh: pass reports agree with measure_mesh_quality and name live vertices") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, false);
  Remesher r(*s->adapted);
  bool first_split = true;
  for (PassKind k : {PassKind::Swap, PassKind::Split, PassKind::Collapse, PassKind::Swap, PassKind::Smooth,
                     PassKind::Split, PassKind::Final}) {
    const PassReport rep = r.step(k);
    CAPTURE(pass_name(k));
    const SurfaceMesh& m = s->adapted->mesh();
    int sum = 0;
    for (int c : rep.histogram) sum += c;
    CHECK(sum == rep.edges);
    CHECK(rep.vertices == m.n_vertices());
    CHECK(rep.seconds >= 0);
    CHECK(rep.q_min <= rep.q_mean);
    for (int v : rep.touched) CHECK(v < m.vertex_capacity());
    if (k == PassKind::Split && first_split) CHECK(rep.splits > 0);  // hemi's edges are 3-7 units long
    if (k == PassKind::Split) first_split = false;
    // The same figures from the metric module (eq. 6 lengths, eq. 17 quality).
    MetricField M(static_cast<std::size_t>(m.vertex_capacity()));
    for (int i = 0; i < m.vertex_capacity(); ++i)
      if (!m.is_deleted(Vertex(i))) M[i] = s->adapted->metric(Vertex(i));
    const MeshQuality q = measure_mesh_quality(m, M);
    CHECK(q.edges == rep.edges);
    CHECK(q.in_band_share == doctest::Approx(rep.in_band_share));
    CHECK(q.q_min == doctest::Approx(rep.q_min));
    CHECK(q.q_mean == doctest::Approx(rep.q_mean));
  }
}

TEST_CASE("remesh: the metric of every T_1 vertex is T_0's metric interpolated at its position (T_0 = T_G or a copy)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  SurfaceMesh input = load_mesh(mesh);
  detect_features(input);
  MetricField metric(static_cast<std::size_t>(input.vertex_capacity()));
  for (int i = 0; i < input.vertex_capacity(); ++i) {
    const Vec3& p = input.position(Vertex(i));
    metric[i] = metric_from_sizes({0.06 + 0.03 * p.z, 0.05, 0.05 - 0.02 * p.x}, {Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0)});
  }
  const SurfaceMesh t0_copy = input;
  for (const bool same : {true, false}) {
    CAPTURE(same);
    PolyhedralSurface geometry(input);
    ControlSpace control(same ? input : t0_copy, metric, same);
    AdaptedMesh a(input, geometry, control);
    Remesher r(a);
    r.step(PassKind::Split);
    r.step(PassKind::Collapse);
    r.step(PassKind::Smooth);
    // An independent location of every vertex in T_0 and the same interpolation.
    Locator t0(same ? input : t0_copy);
    const SurfaceMesh& out = a.mesh();
    int checked = 0;
    for (int i = 0; i < out.vertex_capacity(); ++i) {
      const Vertex v(i);
      if (out.is_deleted(v)) continue;
      const Location l = t0.project(out.position(v), {}, Constraint::Free);
      REQUIRE(l.distance < 1e-9);
      const SymTensor3 expected = interpolate_metric(
          {metric[input.vertex(l.triangle, 0).idx], metric[input.vertex(l.triangle, 1).idx],
           metric[input.vertex(l.triangle, 2).idx]},
          l.bary, MetricInterpolation::Linear);
      for (int k = 0; k < 6; ++k)
        CHECK(a.metric(v).m[k] == doctest::Approx(expected.m[k]).epsilon(1e-7).scale(frobenius_norm(expected)));
      ++checked;
    }
    CHECK(checked == out.n_vertices());
  }
}

TEST_CASE("remesh: Remark 6 relaxation: intermediate metrics between the mesh's sizes and the target, then the target") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, true);
  ControlSpace& c = *s->control;
  // t = 0: the sizes of the input mesh itself (mean incident edge length).
  c.set_relaxation(0);
  const Vertex v(0);
  double sum = 0;
  int n = 0;
  for (Vertex w : one_ring(s->input, v)) {
    sum += norm(s->input.position(w) - s->input.position(v));
    ++n;
  }
  CHECK(c.metric()[0].xx() == doctest::Approx(1 / ((sum / n) * (sum / n))));
  // t = 1/2: the geometric mean of the sizes (log-Euclidean).
  c.set_relaxation(0.5);
  const double h_target = 1 / std::sqrt(c.target_metric()[0].xx());
  CHECK(1 / std::sqrt(c.metric()[0].xx()) == doctest::Approx(std::sqrt(h_target * sum / n)));
  c.set_relaxation(1);
  CHECK(c.metric()[0] == c.target_metric()[0]);

  RemeshOptions o;
  o.op.lmin = 0.72;
  o.relaxation_stages = 2;
  Remesher r(*s->adapted, o);
  r.run();
  check_state(*s->adapted, "relaxed run");
  CHECK(c.metric()[0] == c.target_metric()[0]);
  const PassReport after = r.measure();
  CHECK(after.in_band_share > 0.95);
  CHECK(after.q_min > 0.3);
}

TEST_CASE("remesh: run() is advance() until finished, a stopped run resumes, snapshots of the schedule resume it") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  RemeshOptions o;
  o.op.lmin = 0.72;
  o.relaxation_stages = 1;
  // Reference: one run().
  auto ref = make_setup(mesh, sol, 0, true);
  Remesher r_ref(*ref->adapted, o);
  const std::vector<PassReport> all = r_ref.run();
  REQUIRE(all.size() > 6);
  CHECK(all.front().kind == PassKind::Swap);
  CHECK(all.back().kind == PassKind::Final);
  CHECK(r_ref.finished());
  CHECK(r_ref.schedule().stage == 1);  // both stages ran
  CHECK_THROWS_AS(r_ref.advance(), std::logic_error);

  // The same schedule a pass at a time, stopped after 5 passes and resumed.
  auto s = make_setup(mesh, sol, 0, true);
  Remesher r(*s->adapted, o);
  int seen = 0;
  std::vector<PassReport> got = r.run([&](const PassReport&) { ++seen; }, [&] { return seen == 5; });
  CHECK(got.size() == 5);
  CHECK(!r.finished());
  while (!r.finished()) {
    const PassKind planned = r.next_pass();
    got.push_back(r.advance());
    CHECK(got.back().kind == planned);
  }
  REQUIRE(got.size() == all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    CAPTURE(i);
    CHECK(got[i].kind == all[i].kind);
    CHECK(got[i].round == all[i].round);
    CHECK(got[i].changes() == all[i].changes());
    CHECK(got[i].vertices == all[i].vertices);
  }

  // A copy of the mesh and of the schedule mid-run: a new remesher resumes
  // the schedule there (the relaxed metric of the stage set again) and ends it.
  auto t = make_setup(mesh, sol, 0, true);
  Remesher first(*t->adapted, o);
  for (int i = 0; i < 6; ++i) first.advance();
  const Schedule mid = first.schedule();
  CHECK(mid.phase == Schedule::Phase::Round);
  AdaptedMesh copy(t->adapted->mesh(), *t->geometry, *t->control);
  Remesher second(copy, o);
  second.set_schedule(mid);
  CHECK(second.next_pass() == first.next_pass());
  second.run();
  CHECK(second.finished());
  check_state(copy, "resumed run");
  CHECK(second.measure().in_band_share > 0.95);
  CHECK(t->control->metric()[0] == t->control->target_metric()[0]);  // the last stage is the target
}

TEST_CASE("remesh: an interrupted pass stops early with a valid mesh and the schedule resumes at that pass") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, true);
  RemeshOptions o;
  o.op.lmin = 0.72;
  Remesher r(*s->adapted, o);
  r.advance();  // the initial swaps
  REQUIRE(r.next_pass() == PassKind::Split);
  const Schedule before = r.schedule();
  int polls = 0;
  r.set_interrupt([&] { return ++polls >= 2; });  // the second poll: after about 512 splits
  const PassReport cut = r.advance();
  CHECK(cut.kind == PassKind::Split);
  CHECK(cut.interrupted);
  CHECK(cut.splits > 0);
  CHECK(cut.splits < 900);  // hemi's whole first split pass makes about 900
  check_state(*s->adapted, "interrupted split");
  CHECK(r.schedule().round == before.round);  // the pass is still to do
  CHECK(r.next_pass() == PassKind::Split);
  r.set_interrupt({});
  const PassReport rest = r.advance();
  CHECK(!rest.interrupted);
  CHECK(rest.kind == PassKind::Split);
  CHECK(rest.splits > 0);
  r.run();
  CHECK(r.finished());
  check_state(*s->adapted, "after the resumed run");
  CHECK(r.measure().in_band_share > 0.95);
}

TEST_CASE("remesh: the final valence swaps bring interior valences toward 6 without lowering the worst quality (isotropic metric)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/sphere20k_iso.sol");
  auto deviation = [](AdaptedMesh& a) {
    const SurfaceMesh& m = a.mesh();
    long long d = 0;
    for (int i = 0; i < m.vertex_capacity(); ++i) {
      const Vertex v(i);
      if (m.is_deleted(v) || m.is_isolated(v) || a.kind(v) != VertexKind::Free) continue;
      d += (m.valence(v) - 6) * (m.valence(v) - 6);
    }
    return d;
  };
  long long dev[2];
  double worst[2];
  for (const bool on : {false, true}) {
    auto s = make_setup(mesh, sol, 0, true);
    RemeshOptions o;
    o.op.lmin = 0.72;
    o.valence_swaps = on;
    Remesher r(*s->adapted, o);
    r.run();
    check_state(*s->adapted, on ? "with valence swaps" : "without");
    dev[on] = deviation(*s->adapted);
    const PassReport m = r.measure();
    worst[on] = m.q_min;
    CHECK(m.in_band_share > 0.98);
    CHECK(m.q_min > 0.5);
  }
  MESSAGE("valence deviation " << dev[0] << " -> " << dev[1] << ", q min " << worst[0] << " -> " << worst[1]);
  CHECK(dev[1] < dev[0]);
  CHECK(worst[1] >= worst[0]);
}

TEST_CASE("remesh: Remark 5 cache: the edges of the last 10 modifications are protected from being undone") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  for (const int cache : {10, 0}) {
    CAPTURE(cache);
    auto s = make_setup(mesh, sol, 0, false);
    RemeshOptions o;
    o.cache_size = cache;
    o.local_swaps = false;  // the spokes of a split vertex stay its four edges
    Remesher r(*s->adapted, o);
    const PassReport split = r.step(PassKind::Split);
    REQUIRE(split.splits > 20);
    const SurfaceMesh& m = s->adapted->mesh();
    const Vertex last(split.touched.back()), first(split.touched.front());
    for (Vertex w : one_ring(m, last)) {
      CHECK(r.in_cache(last, w, PassKind::Collapse) == (cache > 0));  // a collapse would undo the split
      CHECK(!r.in_cache(last, w, PassKind::Split));
    }
    // Older modifications have left the cache (it holds the last 10).
    for (Vertex w : one_ring(m, first)) CHECK(!r.in_cache(first, w, PassKind::Collapse));
  }
}

TEST_CASE("remesh: the swaps around a split vertex leave no link edge that can_swap accepts") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, false);
  RemeshOptions o;
  o.local_swaps = false;  // the split pass leaves the swaps to the test
  Remesher r(*s->adapted, o);
  const PassReport split = r.step(PassKind::Split);
  REQUIRE(split.splits > 20);
  RemeshOptions with_swaps;
  Remesher swapper(*s->adapted, with_swaps);
  const SurfaceMesh& m = s->adapted->mesh();
  int swaps = 0, checked = 0;
  for (int idx : split.touched) {
    const Vertex v(idx);
    if (m.is_deleted(v) || m.is_isolated(v)) continue;
    PassReport report;
    swaps += swapper.local_swaps(v, report);
    CHECK(report.swaps >= 0);
    for (Corner c : m.fan_corners(v)) {
      // c names the edge of its triangle opposite v: a link edge
      const SwapPlan plan = can_swap(*s->adapted, c, with_swaps.op);
      CHECK_MESSAGE(plan.why != Rejection::None, "vertex " << idx << ": a link edge still improves by a swap");
      ++checked;
    }
  }
  MESSAGE(swaps << " swaps around " << split.touched.size() << " split vertices, " << checked << " link edges checked");
  CHECK(swaps > 0);
  check_state(*s->adapted, "after the local swaps");
}

// The bundled demo (scripts/make_demo.py): a 162-vertex icosphere under a
// metric of sizes 0.015 across a wavy band and 0.1 along it. On its coarse
// triangles the metric varies so much between the vertices that c_K with a
// metric per edge reads 0 for well-shaped triangles (and well for needles).
namespace {
std::string demo_file(const char* name) { return std::string(ANISURF_TEST_DATA_DIR) + "/../../assets/" + name; }

// Smallest angle cosine between a triangle's normal and the surface normals
// at its free corners, over the mesh (1: every triangle along the surface).
double worst_surface_cosine(const AdaptedMesh& a) {
  const SurfaceMesh& m = a.mesh();
  double worst = 1;
  for (int t = 0; t < m.triangle_capacity(); ++t) {
    if (m.is_deleted(Triangle(t))) continue;
    const Vec3 n = normalized(m.triangle_normal(Triangle(t)));
    for (int k = 0; k < 3; ++k) {
      const Vec3& s = a.surface_normal(m.vertex(Triangle(t), k));
      if (norm2(s) > 0) worst = std::min(worst, dot(n, s));
    }
  }
  return worst;
}

// Min over the triangles of c_K with the edges in the centroid metric,
// computed here from metric/quality.h (independently of the operators).
double min_centroid_quality(const AdaptedMesh& a) {
  const SurfaceMesh& m = a.mesh();
  double q = 1;
  for (int t = 0; t < m.triangle_capacity(); ++t) {
    if (m.is_deleted(Triangle(t))) continue;
    std::array<Vec3, 3> p;
    std::array<SymTensor3, 3> M;
    for (int k = 0; k < 3; ++k) {
      p[k] = m.position(m.vertex(Triangle(t), k));
      M[k] = a.metric(m.vertex(Triangle(t), k));
    }
    q = std::min(q, triangle_quality_in(p, centroid_metric(M, MetricInterpolation::Linear)));
  }
  return q;
}
}  // namespace

TEST_CASE("remesh: demo sphere, the initial swaps do not trade coarse triangles of c_K 0 (metric per edge) for needles") {
  auto s = make_setup(demo_file("demo.mesh"), demo_file("demo.sol"), 0, true);
  AdaptedMesh& a = *s->adapted;
  // The situation of the bug: coarse input triangles whose per-edge c_K is 0
  // while they are fine in one metric.
  int zero = 0;
  for (int t = 0; t < a.mesh().triangle_capacity(); ++t)
    if (!a.mesh().is_deleted(Triangle(t)) && a.quality(Triangle(t)) < 1e-3 && a.quality_in_one_metric(Triangle(t)) > 0.2)
      ++zero;
  REQUIRE(zero > 10);
  const double before = min_centroid_quality(a);
  Remesher r(a);
  r.step(PassKind::Swap);
  check_state(a, "initial swaps");
  // Each swap must improve its pair, so the mesh's worst triangle cannot get worse.
  CHECK(min_centroid_quality(a) >= before);
}

TEST_CASE("remesh: demo sphere with its anisotropic band, every edge split to at most lmax (no needles left over)") {
  for (const bool g1 : {true, false}) {
    CAPTURE(g1);
    auto s = make_setup(demo_file("demo.mesh"), demo_file("demo.sol"), 0, g1);
    RemeshOptions o;
    o.op.lmin = 0.72;  // anisurf adapt's default
    Remesher r(*s->adapted, o);
    const std::vector<PassReport> passes = run_checked(r, *s->adapted, o.max_rounds);
    const PassReport end = r.measure();
    // Before the fix about 1% of the edges stayed at lengths 2-11 between
    // needles tilted up to 60 degrees off the sphere that no split could cut.
    CHECK(end.length_max <= 2.0);
    CHECK(end.histogram[kLengthBins.size() - 2] + end.histogram[kLengthBins.size() - 1] == 0);  // [2, 5) and beyond
    CHECK(end.in_band_share > 0.98);
    CHECK(end.q_min > 0.3);
    // (Surface normals of the polyhedral T_G are its facets': some 35 degrees apart.)
    CHECK(worst_surface_cosine(*s->adapted) > std::cos(45.0 * std::numbers::pi / 180.0));
  }
}

namespace {

// A flat strip 4 x 1 whose lower boundary runs straight along y = 0 but for
// a notch at each end of the unit segment K-R: J just before K and O just
// after R, each 0.005 from it, the boundary turning by 35 degrees at J, K,
// R and O (below the 45-degree corner angle: one curve). Polyhedral
// geometry (the curve is the polyline), isotropic size 10.
struct NotchedStrip {
  SurfaceMesh mesh;
  std::unique_ptr<PolyhedralSurface> geometry;
  std::unique_ptr<ControlSpace> control;
  std::unique_ptr<AdaptedMesh> adapted;
  Vertex k, r;
};
std::unique_ptr<NotchedStrip> make_notched_strip() {
  const double c = 0.005 * std::cos(35 * std::numbers::pi / 180), s = 0.005 * std::sin(35 * std::numbers::pi / 180);
  MeshData d;
  // Lower boundary A J K R O E, upper boundary at y = 1.
  d.vertices = {{-2, 0, 0}, {-c, s, 0}, {0, 0, 0}, {1, 0, 0}, {1 + c, s, 0}, {2, 0, 0},
                {-2, 1, 0}, {-1, 1, 0}, {0, 1, 0},  {1, 1, 0}, {2, 1, 0}};
  d.triangles = {{0, 1, 7}, {0, 7, 6}, {1, 2, 8}, {1, 8, 7}, {2, 3, 9}, {2, 9, 8}, {3, 4, 9}, {4, 5, 10}, {4, 10, 9}};
  auto t = std::make_unique<NotchedStrip>();
  build_mesh(d, t->mesh);
  detect_features(t->mesh);
  t->geometry = std::make_unique<PolyhedralSurface>(t->mesh);
  MetricField metric(static_cast<std::size_t>(t->mesh.vertex_capacity()), isotropic_metric(10));
  t->control = std::make_unique<ControlSpace>(t->mesh, metric, true);
  t->adapted = std::make_unique<AdaptedMesh>(t->mesh, *t->geometry, *t->control);
  t->k = Vertex(2);
  t->r = Vertex(3);
  return t;
}

}  // namespace

TEST_CASE("remesh: the curve turn limit applies where the curve bends, not to a short notched segment of a straight curve") {
  auto t = make_notched_strip();
  AdaptedMesh& a = *t->adapted;
  REQUIRE(a.kind(t->k) == VertexKind::Curve);
  REQUIRE(a.kind(t->r) == VertexKind::Curve);
  const Corner c = find_edge_corner(a.mesh(), t->k, t->r);
  REQUIRE(c.is_valid());
  // Collapsing K-R either way turns a 0.005-long notch segment (J-K or
  // R-O) by 35 degrees, beyond max_curve_turn_deg, while the new segment
  // stays within 0.003 of the curve: straight at its scale.
  OperatorOptions strict;
  strict.straight_curve_sag = 0;
  CHECK(can_collapse(a, c, strict).why == Rejection::Tangent);
  const CollapsePlan plan = can_collapse(a, c, OperatorOptions{});
  CHECK(plan.why == Rejection::None);
  // A turn limit of 40 degrees lets it through without the straightness.
  strict.max_curve_turn_deg = 40;
  CHECK(can_collapse(a, c, strict).why == Rejection::None);
  if (plan.why == Rejection::None) {
    collapse(a, plan);
    const ValidationReport v = a.mesh().validate();
    CHECK_MESSAGE(v.ok(), v.summary());
    CHECK(a.count_inverted() == 0);
  }
}

TEST_CASE("remesh: the schedule walks round_plan() round after round, at most max_rounds per stage") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  auto s = make_setup(mesh, sol, 0, true);
  RemeshOptions o;
  o.smoothing_passes = 2;
  o.max_rounds = 2;
  o.converged_share = 0;  // only max_rounds ends the stage (hemi needs more rounds than 2 to settle)
  Remesher r(*s->adapted, o);
  const std::vector<PassKind> plan = r.round_plan();
  REQUIRE(plan == std::vector<PassKind>{PassKind::Split, PassKind::Collapse, PassKind::Swap, PassKind::Smooth,
                                        PassKind::Smooth});
  const std::vector<PassReport> all = r.run();
  REQUIRE(all.size() >= 2 + plan.size());
  CHECK(all.front().kind == PassKind::Swap);  // the initial swaps
  CHECK(all.front().round == 0);
  CHECK(all.back().kind == PassKind::Final);
  const std::size_t round_passes = all.size() - 2;
  REQUIRE(round_passes % plan.size() == 0);
  CHECK(round_passes / plan.size() <= 2);
  for (std::size_t i = 0; i < round_passes; ++i) {
    CAPTURE(i);
    CHECK(all[i + 1].kind == plan[i % plan.size()]);
    CHECK(all[i + 1].round == static_cast<int>(i / plan.size()) + 1);
  }
  // refuse(): the elements an operator never applies to are not refusals.
  for (const PassReport& p : all) {
    CAPTURE(pass_name(p.kind));
    if (p.kind == PassKind::Swap) CHECK(p.rejected[static_cast<std::size_t>(Rejection::Feature)] == 0);
    if (p.kind == PassKind::Smooth || p.kind == PassKind::Final) {
      CHECK(p.rejected[static_cast<std::size_t>(Rejection::Fixed)] == 0);
      CHECK(p.rejected[static_cast<std::size_t>(Rejection::NoGain)] == 0);
    }
  }
  check_state(*s->adapted, "two rounds");
}

namespace {

// The same vertices at the same positions, and the same triangles, slot by
// slot: what a cache must leave as it was.
void check_same_mesh(const SurfaceMesh& a, const SurfaceMesh& b) {
  REQUIRE(a.n_vertices() == b.n_vertices());
  REQUIRE(a.n_triangles() == b.n_triangles());
  int moved = 0;
  for (Vertex v : a.vertices()) moved += a.position(v) == b.position(v) ? 0 : 1;
  CHECK(moved == 0);
  int rewired = 0;
  for (Triangle t : a.triangles())
    for (int k = 0; k < 3; ++k) rewired += a.vertex(t, k) == b.vertex(t, k) ? 0 : 1;
  CHECK(rewired == 0);
}

}  // namespace

TEST_CASE("remesh: the sag memo is a cache: the same adapted mesh without it, where many edges sag off the input") {
  // The fandisk's curvature metric with hausd: the split passes measure the
  // sag of every edge, again after each change around it; the memo keeps the
  // edges found flat per corner slot, which the operators rewrite.
  ANISURF_REQUIRE_SHARED(path, "meshes/fandisk.off");
  const SurfaceMesh in = load_mesh(path);
  auto run = [&](bool memo) {
    remesh::AdaptOptions o;
    o.metric.source = MetricRecipe::Source::Curvature;
    o.metric.hausd = 2e-4 * in.bbox().diagonal();
    o.threads = 1;
    o.remesh.sag_memo = memo;
    return remesh::adapt({in}, o);
  };
  const remesh::AdaptResult with = run(true), without = run(false);
  REQUIRE(with.mesh.validate().ok());
  int splits = 0;
  for (const remesh::CycleReport& c : with.cycles)
    for (const PassReport& p : c.passes) splits += p.splits;
  MESSAGE("fandisk: " << with.mesh.n_triangles() << " triangles, " << splits << " splits");
  CHECK(splits > 0);
  check_same_mesh(with.mesh, without.mesh);
}

TEST_CASE("placed_position: place()'s position, with and without the pull towards the input") {
  // The demo's coarse icosphere: its G1 surface stands off the facets by
  // more than the bound in places (pulled) and not in others.
  auto s = make_setup(test::asset_file("demo.mesh"), "", 0.1, true);
  AdaptedMesh& a = *s->adapted;
  const SurfaceMesh& m = a.mesh();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  int pulled = 0, free_points = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vertex v(std::uniform_int_distribution<int>(0, m.vertex_capacity() - 1)(rng));
    if (m.is_deleted(v) || m.is_isolated(v)) continue;
    const Vec3 x = m.position(v) + Vec3(u(rng), u(rng), u(rng));
    const VertexKind kind = a.kind(v) == VertexKind::Fixed ? VertexKind::Free : a.kind(v);
    const Placement p = a.place(x, kind, {v});
    const Vec3 q = a.placed_position(x, kind, {v});
    CHECK(q.x == p.position.x);
    CHECK(q.y == p.position.y);
    CHECK(q.z == p.position.z);
    (p.pulled ? pulled : free_points) += 1;
  }
  CHECK(pulled > 100);
  CHECK(free_points > 100);
}

TEST_CASE("placed_within: the sag test's shortcut agrees with the placed point, within the input bound") {
  // The demo's coarse icosphere on its G1 surface, points about the vertices
  // and tolerances around their distance to the surface: placed_within
  // settles most of them by the surface's deviation from the facets alone.
  auto s = make_setup(test::asset_file("demo.mesh"), "", 0.1, true);
  AdaptedMesh& a = *s->adapted;
  const SurfaceMesh& m = a.mesh();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 0.1), f(0.2, 2.0);
  int agree_in = 0, agree_out = 0, only_fast = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vertex v(std::uniform_int_distribution<int>(0, m.vertex_capacity() - 1)(rng));
    if (m.is_deleted(v) || m.is_isolated(v) || a.kind(v) != VertexKind::Free) continue;
    const Vec3 x = m.position(v) + Vec3(u(rng), u(rng), u(rng));
    const double placed = norm(a.placed_position(x, VertexKind::Free, {v}) - x);
    const double tol = f(rng) * placed;
    const bool exact = placed <= tol;
    const bool fast = a.placed_within(x, VertexKind::Free, {v}, tol);
    // Never refused where the placed point is within tol; accepted
    // otherwise only for a surface point within tol (on another triangle),
    // so with the input within tol.
    CHECK((!exact || fast));
    if (fast && !exact) {
      ++only_fast;
      CHECK(a.distance_to_input(x, {v}).distance <= tol);
    }
    (exact ? agree_in : agree_out) += exact == fast ? 1 : 0;
  }
  MESSAGE("within tol " << agree_in << ", beyond " << agree_out << ", accepted by another triangle " << only_fast);
  CHECK(agree_in > 500);
  CHECK(agree_out > 500);
}

namespace {

// The fandisk's ungraded curvature metric at hausd 1e-3 of its diagonal, on
// one thread: a coarsening of many rounds.
remesh::AdaptOptions fandisk_coarsening(const SurfaceMesh& in) {
  remesh::AdaptOptions o;
  o.metric.source = MetricRecipe::Source::Curvature;
  o.metric.hausd = 1e-3 * in.bbox().diagonal();
  o.metric.hgrad = 0;
  o.threads = 1;
  return o;
}

}  // namespace

TEST_CASE("remesh: the refusal memo is a cache: the same adapted mesh without it, in a coarsening of many rounds") {
  // The fandisk's curvature metric with hausd coarsens the scan over many
  // rounds whose split and collapse passes refuse the same edges again; the
  // memo answers them while nothing changed around their ends.
  ANISURF_REQUIRE_SHARED(path, "meshes/fandisk.off");
  const SurfaceMesh in = load_mesh(path);
  auto run = [&](bool memo) {
    remesh::AdaptOptions o = fandisk_coarsening(in);
    o.remesh.refusal_memo = memo;
    return remesh::adapt({in}, o);
  };
  const remesh::AdaptResult with = run(true), without = run(false);
  REQUIRE(with.mesh.validate().ok());
  int remembered = 0, remembered_without = 0;
  for (const remesh::CycleReport& c : with.cycles)
    for (const PassReport& p : c.passes) remembered += p.remembered_refusals;
  for (const remesh::CycleReport& c : without.cycles)
    for (const PassReport& p : c.passes) remembered_without += p.remembered_refusals;
  MESSAGE("fandisk: " << in.n_triangles() << " -> " << with.mesh.n_triangles() << " triangles, " << remembered
                      << " refusals remembered");
  CHECK(remembered > 0);
  CHECK(remembered_without == 0);
  check_same_mesh(with.mesh, without.mesh);
}

TEST_CASE("remesh: the rounds end once a round's splits and collapses balance (after balance_after_rounds)") {
  // The fandisk's ungraded curvature metric with hausd: after the first
  // collapses, each round splits and collapses a few dozen edges. With a
  // balance_share of 0.2 the stage ends at the first round past the fourth
  // whose splits and collapses differ by less than a fifth of the larger;
  // without the rule it runs on, and the two meshes are alike.
  ANISURF_REQUIRE_SHARED(path, "meshes/fandisk.off");
  const SurfaceMesh in = load_mesh(path);
  auto run = [&](int after) {
    remesh::AdaptOptions o = fandisk_coarsening(in);
    o.remesh.balance_after_rounds = after;
    o.remesh.balance_share = 0.2;
    return remesh::adapt({in}, o);
  };
  // Per round: splits and collapses.
  auto rounds = [](const remesh::AdaptResult& r) {
    std::map<int, std::pair<int, int>> out;
    for (const PassReport& p : r.cycles.at(0).passes) {
      if (p.kind == PassKind::Final || p.round == 0) continue;
      out[p.round].first += p.splits;
      out[p.round].second += p.collapses;
    }
    return out;
  };
  auto balanced = [](const std::pair<int, int>& sc) {
    return std::abs(sc.first - sc.second) < 0.2 * std::max(sc.first, sc.second);
  };
  const int after = 4;
  const remesh::AdaptResult with = run(after), without = run(0);
  REQUIRE(with.mesh.validate().ok());
  REQUIRE(without.mesh.validate().ok());
  const auto rw = rounds(with), ro = rounds(without);
  // The first balanced round past `after` in the run without the rule.
  int first = 0;
  for (const auto& [round, sc] : ro)
    if (round > after && balanced(sc)) {
      first = round;
      break;
    }
  MESSAGE("fandisk: " << ro.size() << " rounds without the rule, " << rw.size() << " with; first balanced round "
                      << first);
  REQUIRE(first > 0);  // the case exercises the rule
  REQUIRE(first < static_cast<int>(ro.size()));
  CHECK(static_cast<int>(rw.size()) == first);
  for (const auto& [round, sc] : rw) CHECK(ro.at(round) == sc);  // the same rounds up to there
  CHECK(balanced(rw.rbegin()->second));
  CHECK(with.cycles.at(0).final.in_band_share > without.cycles.at(0).final.in_band_share - 0.02);
  CHECK(std::abs(with.mesh.n_triangles() - without.mesh.n_triangles()) < 0.05 * without.mesh.n_triangles());
  CHECK(with.cycles.at(0).inverted_after <= with.cycles.at(0).inverted_before);
}

TEST_CASE("remesh: the final pass removes vertices squeezed into poor fans where that raises the worst quality") {
  // An icosphere of 5120 triangles refined about 4 times in length: the
  // splits leave here and there a vertex squeezed between others, its edges
  // near lmin, which the smoothing cannot shape. With repair_quality the
  // final pass removes such vertices into a neighbour when the triangles
  // that replace their fans are better: fewer poor triangles, the worst no
  // worse, a valid mesh in the band.
  struct Outcome {
    int repairs = 0, poor = 0;
    double q_min = 0, band = 0;
  };
  auto adapt_with = [](double repair_quality) {
    const JitteredSphere s(4, 0.005, 5, 0.02, FeatureOptions{});
    RemeshOptions o;
    o.op.lmin = 0.72;
    o.repair_quality = repair_quality;
    Remesher r(*s.adapted, o);
    const std::vector<PassReport> passes = r.run();
    check_state(*s.adapted, repair_quality > 0 ? "with repairs" : "without");
    Outcome out;
    out.repairs = passes.back().collapses;
    for (Triangle t : s.adapted->mesh().triangles()) out.poor += s.adapted->quality(t) < 0.8 ? 1 : 0;
    const PassReport m = r.measure();
    out.q_min = m.q_min;
    out.band = m.in_band_share;
    return out;
  };
  const Outcome off = adapt_with(0), on = adapt_with(0.8);
  MESSAGE("repairs " << on.repairs << ", triangles below 0.8: " << off.poor << " -> " << on.poor << ", q min "
                     << off.q_min << " -> " << on.q_min << ", band " << off.band << " -> " << on.band);
  CHECK(off.repairs == 0);
  CHECK(on.repairs > 0);
  CHECK(on.poor < off.poor);
  CHECK(on.q_min >= off.q_min);
  CHECK(on.band > 0.97);
}

TEST_CASE("remesh: the final pass moves the worst triangles' vertices where their fans' worst triangle is best") {
  // The same refined icosphere: with relocate_quality the final pass moves
  // the free vertices of the triangles below it where the worst quality of
  // their fan is largest. Fewer triangles below the threshold, the worst
  // higher, the mean and the band kept, a valid and uninverted mesh.
  struct Outcome {
    int poor = 0;
    double q_min = 0, q_mean = 0, band = 0;
  };
  auto adapt_with = [](double relocate_quality) {
    const JitteredSphere s(4, 0.005, 5, 0.02, FeatureOptions{});
    RemeshOptions o;
    o.op.lmin = 0.72;
    o.relocate_quality = relocate_quality;
    Remesher r(*s.adapted, o);
    r.run();
    check_state(*s.adapted, relocate_quality > 0 ? "with relocations" : "without");
    Outcome out;
    for (Triangle t : s.adapted->mesh().triangles()) out.poor += s.adapted->quality(t) < 0.9 ? 1 : 0;
    const PassReport m = r.measure();
    out.q_min = m.q_min;
    out.q_mean = m.q_mean;
    out.band = m.in_band_share;
    return out;
  };
  const Outcome off = adapt_with(0), on = adapt_with(0.9);
  MESSAGE("triangles below 0.9: " << off.poor << " -> " << on.poor << ", q min " << off.q_min << " -> " << on.q_min
                                  << ", mean " << off.q_mean << " -> " << on.q_mean << ", band " << off.band << " -> "
                                  << on.band);
  CHECK(on.poor < off.poor);
  CHECK(on.q_min > off.q_min);
  CHECK(on.q_mean > off.q_mean - 1e-4);
  CHECK(on.band >= off.band - 1e-3);
}

TEST_CASE("move: can_move_for_worst raises the worst quality of the fan, keeps its sum and the short edges") {
  // The refined icosphere of the test above, without the relocations: the
  // fans its smoothing left below 0.9.
  const JitteredSphere s(4, 0.005, 5, 0.02, FeatureOptions{});
  AdaptedMesh& a = *s.adapted;
  SurfaceMesh& m = a.mesh();
  RemeshOptions ro;
  ro.op.lmin = 0.72;
  ro.relocate_quality = 0;
  Remesher(a, ro).run();
  const OperatorOptions& o = ro.op;
  auto fan_qualities = [&](Vertex v) {
    std::pair<double, double> q{1.0, 0.0};
    for (Corner c : m.fan(v)) {
      const double qt = a.quality(SurfaceMesh::triangle(c));
      q.first = std::min(q.first, qt);
      q.second += qt;
    }
    return q;
  };
  int moved = 0, tried = 0;
  double summed_before = 0, summed_after = 0;
  for (Vertex v : m.vertices()) {
    if (a.kind(v) != VertexKind::Free || fan_qualities(v).first >= 0.9) continue;
    ++tried;
    std::vector<std::pair<Vertex, double>> lengths;
    for (Vertex w : one_ring(m, v)) lengths.push_back({w, a.length(v, w)});
    const auto before = fan_qualities(v);
    const MovePlan p = can_move_for_worst(a, v, o, 1.01, 0);  // no trade: the fan's sum does not fall
    if (p.why != Rejection::None) continue;
    CHECK(p.quality_after > 1.01 * p.quality_before);
    move(a, v, p);
    ++moved;
    const auto after = fan_qualities(v);
    CHECK(after.first > before.first);
    summed_before += before.second;
    summed_after += after.second;
    for (const auto& [w, l] : lengths) {
      const double now = a.length(v, w);
      if (now < o.lmin) CHECK(now >= l - 1e-12);  // an edge below lmin only gets longer
    }
    const ValidationReport r = m.validate();
    REQUIRE_MESSAGE(r.ok(), r.summary());
  }
  MESSAGE(moved << " of " << tried << " vertices of poor fans moved; their fans' summed quality " << summed_before
                << " -> " << summed_after);
  CHECK(moved > tried / 5);
  CHECK(summed_after > summed_before);
  CHECK(a.count_inverted() == 0);
}

TEST_CASE("move: can_move_for_worst keeps the triangles across a jump of the metric from getting worse") {
  // A fine icosphere coarsened to a size that halves below the equator:
  // the triangles across the jump have a quality that depends on how
  // lengths are read between their vertices; a relocation improves the
  // others and keeps those.
  SurfaceMesh input = test::build(test::jittered_icosphere(5, 0.995, 1.005, 7));
  detect_features(input, FeatureOptions{});
  PolyhedralSurface geometry(input);
  MetricField metric(static_cast<std::size_t>(input.vertex_capacity()), isotropic_metric(0.12));
  for (Vertex v : input.vertices())
    if (input.position(v).z < 0) metric[static_cast<std::size_t>(v.idx)] = isotropic_metric(0.06);
  ControlSpace control(input, metric, true, MetricInterpolation::Linear, "sol0");
  AdaptedMesh a(input, geometry, control, LengthFormula::LinearMetric, false);
  RemeshOptions ro;
  ro.op.lmin = 0.72;
  ro.relocate_quality = 0;
  Remesher(a, ro).run();
  SurfaceMesh& m = a.mesh();
  auto varies = [&](Triangle t) {
    const SymTensor3& M0 = a.metric(m.vertex(t, 0));
    for (int k = 1; k < 3; ++k)
      if (!(frobenius_norm(a.metric(m.vertex(t, k)) - M0) <= 0.05 * frobenius_norm(M0))) return true;
    return false;
  };
  int moved = 0, across = 0;
  for (Vertex v : m.vertices()) {
    if (a.kind(v) != VertexKind::Free) continue;
    std::vector<std::tuple<Triangle, double, bool>> before;  // quality and metric varying, before the move
    double worst = 1;
    bool near_jump = false, poor = false;
    for (Corner c : m.fan(v)) {
      const Triangle t = SurfaceMesh::triangle(c);
      before.push_back({t, a.quality(t), varies(t)});
      worst = std::min(worst, a.quality(t));
      near_jump = near_jump || varies(t);
      poor = poor || a.quality(t) < 0.9;
    }
    if (!poor) continue;
    const MovePlan p = can_move_for_worst(a, v, ro.op, 1.01, 0.8);
    if (p.why != Rejection::None) continue;
    move(a, v, p);
    ++moved;
    double worst_after = 1;
    for (const auto& [t, q, varied] : before) {
      worst_after = std::min(worst_after, a.quality(t));
      if (varied) {
        ++across;
        CHECK(a.quality(t) >= q);
      }
    }
    CHECK(worst_after >= worst - 1e-9);
    if (near_jump) CHECK(p.quality_after >= p.quality_before);
  }
  MESSAGE(moved << " vertices moved, " << across << " triangles across the jump in their fans");
  CHECK(moved > 0);
  CHECK(across > 0);
  CHECK(m.validate().ok());
  CHECK(a.count_inverted() == 0);
}
