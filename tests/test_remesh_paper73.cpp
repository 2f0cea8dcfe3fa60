// The report's section 7.3 (hemi-sphere and half-circle intersection) through
// the engine, as `anisurf adapt` runs it: T_i (tests/data/paper73_Ti.mesh,
// made by scripts/paper/hemisphere_halfdisc.py: a dome of radius 6.4 on a
// flat half-disc of radius 9.05, glued along a half-circle crease) refined to
// T_r with the isotropic size 0.8, then T_r adapted to the section's
// discontinuous anisotropic metric and to its element suppression metric
// (size 4 where z <= 0: the flat part, the crease and the dome's open base;
// 1.118 above). Checked: validity and orientation after every pass, the
// share of edges in [1/sqrt2, sqrt2], the feature curves (every output
// feature edge on an input feature curve within the sag the operators
// allow, every input feature vertex near an output feature edge, every
// corner kept), and that the suppression removes triangles.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <set>

#include "geometry/features.h"
#include "io/mesh_io.h"
#include "locate/closest_point.h"
#include "mesh/build.h"
#include "metric/metric_field.h"
#include "remesh/remesher.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::remesh;

namespace {

using MetricAt = std::function<SymTensor3(const Vec3&)>;

// The three metrics of section 7.3.
SymTensor3 refinement_metric(const Vec3&) { return SymTensor3::identity(1.5625); }
SymTensor3 anisotropic_metric(const Vec3& x) {
  return x.z <= 0.2 ? SymTensor3(1.5625, 0, 1.5625, 0, 0, 64) : SymTensor3::identity(1.5625);
}
SymTensor3 suppression_metric(const Vec3& x) { return SymTensor3::identity(x.z <= 0 ? 6.25e-2 : 0.8); }

// A fresh mesh with the live elements of `m` and its feature tags (what
// writing a mesh and reading it back gives).
SurfaceMesh copy_of(const SurfaceMesh& m) {
  SurfaceMesh out;
  build_mesh(to_mesh_data(m), out);
  return out;
}

// Adapts `input` (T_G = T_0) to the metric given pointwise at its vertices,
// with the options of `anisurf adapt` (lmin 0.72, sizes interpolated
// linearly, the G1 surface), checking validity and orientation after every
// pass. Returns the adapted mesh (the remesher's measure in `state`).
SurfaceMesh adapt_checked(const SurfaceMesh& input, const MetricAt& metric_at, PassReport& state,
                          const OperatorOptions& op = {}) {
  MetricField metric(static_cast<std::size_t>(input.vertex_capacity()), SymTensor3::identity(1));
  for (int i = 0; i < input.vertex_capacity(); ++i)
    if (!input.is_deleted(Vertex(i))) metric[i] = metric_at(input.position(Vertex(i)));
  BezierGeometry geometry(input);
  ControlSpace control(input, metric, true, MetricInterpolation::LinearSize);
  AdaptedMesh adapted(input, geometry, control);
  RemeshOptions o;
  o.op = op;
  o.op.lmin = 0.72;
  Remesher r(adapted, o);
  REQUIRE(adapted.count_inverted() == 0);
  r.run([&](const PassReport& p) {
    INFO("pass " << pass_name(p.kind) << ", round " << p.round);
    const ValidationReport v = adapted.mesh().validate();
    REQUIRE_MESSAGE(v.ok(), v.summary());
    CHECK(adapted.count_inverted() == 0);
  });
  state = r.measure();
  return copy_of(adapted.mesh());
}

struct Segment {
  Vec3 a, b;
};
std::vector<Segment> feature_segments(const SurfaceMesh& m) {
  std::vector<Segment> out;
  for (int i = 0; i < m.triangle_capacity(); ++i) {
    if (m.is_deleted(Triangle(i))) continue;
    for (int k = 0; k < 3; ++k) {
      const Corner c = SurfaceMesh::corner(Triangle(i), k);
      if (is_feature_edge(m, c)) out.push_back({m.position(m.edge_from(c)), m.position(m.edge_to(c))});
    }
  }
  return out;
}
double distance_to(const std::vector<Segment>& curves, const Vec3& x) {
  double d = INFINITY;
  for (const Segment& s : curves) d = std::min(d, std::sqrt(point_segment_distance2(x, s.a, s.b)));
  return d;
}

// The feature curves of `input` survive in `out`: the ends of every output
// feature edge lie on the input's curves (within the G1 curve's bulge over
// an input edge, `bulge`), its midpoint within `sag` of them; every input
// feature vertex lies within `sag` of an output feature edge (no curve
// lost); every input corner is an output vertex. Returns the number of
// output feature edges.
// (`bulge`: about L^2 / (8 r) over input chords of length L on arcs of
// radius r; 0.014 over T_r's 0.84-long edges on the crease.)
int check_curves_kept(const SurfaceMesh& input, const SurfaceMesh& out, double bulge, double sag) {
  const std::vector<Segment> in_curves = feature_segments(input), out_curves = feature_segments(out);
  REQUIRE(!in_curves.empty());
  double worst_end = 0, worst_mid = 0, worst_cover = 0;
  for (const Segment& s : out_curves) {
    worst_end = std::max({worst_end, distance_to(in_curves, s.a), distance_to(in_curves, s.b)});
    worst_mid = std::max(worst_mid, distance_to(in_curves, 0.5 * (s.a + s.b)));
  }
  for (const Segment& s : in_curves) worst_cover = std::max(worst_cover, distance_to(out_curves, s.a));
  CHECK(worst_end <= bulge);
  CHECK(worst_mid <= bulge + sag);
  CHECK(worst_cover <= bulge + sag);
  std::set<std::array<double, 3>> positions;
  for (int i = 0; i < out.vertex_capacity(); ++i)
    if (!out.is_deleted(Vertex(i))) positions.insert({out.position(Vertex(i)).x, out.position(Vertex(i)).y, out.position(Vertex(i)).z});
  int corners = 0, lost = 0;
  for (int i = 0; i < input.vertex_capacity(); ++i) {
    const Vertex v(i);
    if (input.is_deleted(v) || !input.has_tag(v, kCorner)) continue;
    ++corners;
    const Vec3 x = input.position(v);
    if (!positions.count({x.x, x.y, x.z})) ++lost;
  }
  CHECK(corners >= 4);
  CHECK(lost == 0);
  MESSAGE("feature edges " << in_curves.size() << " sides in, " << out_curves.size() << " out; worst distance to the input curves: end "
                           << worst_end << ", midpoint " << worst_mid << "; input curve points from the output curves " << worst_cover
                           << "; corners " << corners << ", lost " << lost);
  return static_cast<int>(out_curves.size());
}

// T_i, and T_r: T_i refined to the isotropic size 0.8.
struct Paper73 {
  SurfaceMesh ti, tr;
  PassReport refined;
};
const Paper73& paper73() {
  static const std::unique_ptr<Paper73> p = [] {
    auto q = std::make_unique<Paper73>();
    q->ti = load_mesh(test::data_file("paper73_Ti.mesh"));
    detect_features(q->ti);
    q->tr = adapt_checked(q->ti, refinement_metric, q->refined);
    detect_features(q->tr);  // as `anisurf adapt` reading T_r
    return q;
  }();
  return *p;
}

// The suppression metric asks for the size 4 along the curves at z = 0 (the
// crease, a half circle of radius 6.4, the dome's open base, the outer
// half circle of radius 9.05): segments whose chords sag by about h / 10
// (h^2 / (8 r)). With the default curve_sag (0.1) the metric wins; with
// 0.02 the curves stop short of it.
void check_suppression(double curve_sag, bool in_band) {
  const Paper73& p = paper73();
  OperatorOptions op;
  op.curve_sag = curve_sag;
  PassReport s;
  const SurfaceMesh out = adapt_checked(p.tr, suppression_metric, s, op);
  MESSAGE("suppression, curve_sag " << curve_sag << ": " << s.triangles << " triangles (from " << p.refined.triangles
                                    << ", the report: 1116 -> 480), " << 100 * s.in_band_share << "% of edges in band, c_K min "
                                    << s.q_min << " mean " << s.q_mean);
  if (in_band) CHECK(s.in_band_share >= 0.95);
  CHECK(s.triangles < p.refined.triangles);
  // The curves at z = 0 (size 4) sag by at most curve_sag * 4 * lmax.
  const int feature_edges = check_curves_kept(p.tr, out, 0.02, curve_sag * 4 * 1.4);
  CHECK(feature_edges < static_cast<int>(feature_segments(p.tr).size()));
}

}  // namespace

TEST_CASE("remesh paper 7.3: T_i refined to the size 0.8 (T_r), about the report's 1116 triangles, creases kept") {
  const Paper73& p = paper73();
  MESSAGE("T_r: " << p.refined.triangles << " triangles, " << 100 * p.refined.in_band_share << "% of edges in band");
  CHECK(p.refined.in_band_share >= 0.95);
  CHECK(p.refined.triangles >= 1000);
  CHECK(p.refined.triangles <= 1250);
  // T_i's chords over the dome's base are 2.5 long: its G1 curve bulges by
  // about 0.12 from them (2.5^2 / (8 R)).
  check_curves_kept(p.ti, p.tr, 0.15, 0.0);
}

TEST_CASE("remesh paper 7.3: discontinuous anisotropic metric (h_z = 0.125 where z <= 0.2)") {
  const Paper73& p = paper73();
  PassReport s;
  const SurfaceMesh out = adapt_checked(p.tr, anisotropic_metric, s);
  MESSAGE("anisotropic: " << s.triangles << " triangles (from " << p.refined.triangles << "), " << 100 * s.in_band_share
                          << "% of edges in band, c_K min " << s.q_min << " mean " << s.q_mean);
  CHECK(s.in_band_share >= 0.95);
  check_curves_kept(p.tr, out, 0.02, OperatorOptions{}.curve_sag * 0.8);
}

TEST_CASE("remesh paper 7.3: element suppression (size 4 where z <= 0, 1.118 above), default curve limits: the creases coarsened to the metric, 95% in band") {
  check_suppression(OperatorOptions{}.curve_sag, true);
}

TEST_CASE("remesh paper 7.3: element suppression with curve_sag 0.02: coarser than T_r, the curves kept closer") {
  check_suppression(0.02, false);
}
