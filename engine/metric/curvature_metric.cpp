// The geometric metric of a chordal deviation (Frey & Alauzet 2005, section
// 3.2; Mmg's -hausd): sizes sqrt(8 hausd / |kappa|) from the principal
// curvatures, computed per smooth sector so that a feature curve does not
// mix the curvatures of its two sides, and along each feature curve from the
// curve's own curvature.
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "geometry/parallel_chunks.h"
#include "metric/hessian.h"
#include "metric/surface_metric.h"

namespace anisurf {

namespace {

// Curvature of the circle through a, v, b (0 for aligned or coincident
// points): 2 sin(angle at v) / |a - b|.
double circle_curvature(const Vec3& a, const Vec3& v, const Vec3& b) {
  const Vec3 e1 = a - v, e2 = b - v;
  const double l1 = norm(e1), l2 = norm(e2), l3 = norm(a - b);
  if (!(l1 > 0) || !(l2 > 0) || !(l3 > 0)) return 0;
  return 2.0 * norm(cross(e1, e2)) / (l1 * l2 * l3);
}

// A vertex inside a feature curve: two feature edges and not a corner (the
// curve is smooth there, compute_frames gives it one tangent).
bool is_regular_curve_vertex(const SurfaceMesh& mesh, Vertex v, const std::vector<FeatureEdgeAt>& fe) {
  return fe.size() == 2 && !mesh.has_tag(v, kCorner);
}

// A direction of a feature curve at a vertex and the curve's curvature there.
struct CurveDirection {
  Vec3 tangent;
  double curvature;
};

// The feature curves through v: at a regular curve vertex its tangent and
// curvature from the circle through v and its two curve neighbours; at a
// corner (or a curve end) each curve leaving it along its first edge, with
// the curvature of the circle through the corner and the next two curve
// points when the curve goes on smoothly at the next vertex, zero (a
// straight segment between corners) when it does not. The turn at the corner
// itself is a kink of the input, not a curvature.
std::vector<CurveDirection> curve_directions(const SurfaceMesh& mesh, Vertex v) {
  const std::vector<FeatureEdgeAt> fe = feature_edges_at(mesh, v);
  const Vec3& p = mesh.position(v);
  if (is_regular_curve_vertex(mesh, v, fe)) {
    const Vec3 &a = mesh.position(fe[0].other), &b = mesh.position(fe[1].other);
    return {{circle_tangent(a, p, b), circle_curvature(a, p, b)}};
  }
  std::vector<CurveDirection> out;
  for (const FeatureEdgeAt& e : fe) {
    const Vec3& q = mesh.position(e.other);
    const Vec3 chord = normalized(q - p);
    if (norm(chord) == 0) continue;
    double kappa = 0;
    const std::vector<FeatureEdgeAt> next = feature_edges_at(mesh, e.other);
    if (is_regular_curve_vertex(mesh, e.other, next)) {
      const Vertex beyond = next[0].other == v ? next[1].other : next[0].other;
      kappa = circle_curvature(p, q, mesh.position(beyond));
    }
    out.push_back({chord, kappa});
  }
  return out;
}

// The metric asking for size sqrt(8 hausd / kappa) along t (kappa floored
// at `floor`) and the floor's size (hmax) across.
SymTensor3 curve_metric(const CurveDirection& d, double floor, double scale) {
  const SymTensor3 tt = SymTensor3::outer(d.tangent);
  const SymTensor3 across = SymTensor3::identity() - tt;
  return (scale * max_of(d.curvature, floor)) * tt + (scale * floor) * across;
}

// Unit normal of t, or zero when t is too thin for it to mean anything (area
// below 1e-12 times its longest edge squared, as detect_features).
Vec3 reliable_normal(const SurfaceMesh& mesh, Triangle t) {
  const Vec3 n = mesh.triangle_normal(t);
  double longest2 = 0;
  for (int k = 0; k < 3; ++k)
    longest2 = max_of(longest2, norm2(mesh.position(mesh.vertex(t, (k + 1) % 3)) - mesh.position(mesh.vertex(t, k))));
  return 0.5 * norm(n) > 1e-12 * longest2 ? normalized(n) : Vec3();
}

// The creases of the input: at both ends of every edge that is not a
// feature curve, whose triangles turn by theta, the size 2 hausd / sin(theta
// / 2) across it (a chord whose ends lie on the two planes, h / 2 from the
// edge, passes h sin(theta / 2) / 2 from it) and nothing along it. Where the
// input is fine for hausd (theta below about 2 sqrt(2 hausd kappa)) the
// curvature asks for more; on a coarse tessellation (facets sagging by more
// than about hausd / 4 from the smooth surface) the output follows its folds.
// A crease asks at most 1 / h^2 in any direction: a vertex whose metric's
// smallest eigenvalue is already that large keeps its metric (the
// eigenvalues only grow by intersections, so the first ones bound them).
void intersect_crease_metrics(const SurfaceMesh& mesh, double hausd, double floor, double scale, MetricField& M) {
  const double floor_value = scale * floor;  // 1 / hmax^2
  const int nv = static_cast<int>(M.size());
  std::vector<double> smallest(M.size(), 0.0);
  run_chunks(nv, chunk_count(nv, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i)  // less its round-off: a bound from below
      smallest[i] = smallest_eigenvalue(M[i]) - 1e-12 * frobenius_norm(M[i]);
  });
  // The creases that ask more than a first metric at an end, found in
  // parallel chunks of the corners, applied in the order of the edges.
  struct Crease {
    Corner edge;
    double demand;
    Vec3 across;
  };
  const int nc = 3 * mesh.triangle_capacity();
  const int chunks = chunk_count(nc, 3 * 8192);
  std::vector<std::vector<Crease>> found(static_cast<std::size_t>(chunks));
  run_chunks(nc, chunks, [&](int chunk, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Corner c(i);
      if (!mesh.is_edge_corner(c) || is_feature_edge(mesh, c)) continue;
      const Corner o = mesh.opposite(c);
      if (!o.is_valid()) continue;
      const Vec3 n1 = reliable_normal(mesh, SurfaceMesh::triangle(c));
      const Vec3 n2 = reliable_normal(mesh, SurfaceMesh::triangle(o));
      if (norm2(n1) == 0 || norm2(n2) == 0) continue;
      const double half_sin = 0.5 * norm(n1 - n2);  // sin(theta / 2)
      const double h = 2.0 * hausd / half_sin;
      const double demand = 1.0 / (h * h);
      if (!(demand > floor_value)) continue;
      const Vertex a = mesh.edge_from(c), b = mesh.edge_to(c);
      if (demand <= smallest[a.idx] && demand <= smallest[b.idx]) continue;
      const Vec3 across = normalized(cross(normalized(n1 + n2), mesh.position(b) - mesh.position(a)));
      if (norm2(across) == 0) continue;
      found[static_cast<std::size_t>(chunk)].push_back({c, demand, across});
    }
  });
  for (const std::vector<Crease>& part : found)
    for (const Crease& k : part) {
      const SymTensor3 uu = SymTensor3::outer(k.across);
      const SymTensor3 crease = k.demand * uu + floor_value * (SymTensor3::identity() - uu);
      for (Vertex v : {mesh.edge_from(k.edge), mesh.edge_to(k.edge)})
        if (k.demand > smallest[v.idx]) M[v.idx] = intersect(M[v.idx], crease);
    }
}

}  // namespace

// At a vertex off the features: the metric of its principal curvatures (the
// normal direction takes the largest tangent size). At a vertex on feature
// curves: the intersection of the metrics of its sectors (each in its own
// tangent plane, asking nothing along its normal) and of its curves'
// directions. Intersection, not the finer size per direction of one frame:
// every edge leaving the vertex lies in one of its sectors and must meet that
// sector's metric; the intersection is the largest single tensor that does,
// and where the sectors' planes are far apart (a sharp edge) each sector's
// normal carries no demand, so a flat face keeps hmax beside a curved one.
MetricField curvature_metric(const SurfaceMesh& mesh, double hausd, const MetricBounds& bounds_in,
                             const HessianRecoveryOptions& options) {
  if (!(hausd > 0)) throw MetricError("curvature metric: hausd must be > 0");
  MetricBounds bounds = bounds_in;
  if (!std::isfinite(bounds.hmax)) bounds.hmax = mesh.bbox().diagonal();
  const SectorCurvatures sc = recover_sector_curvature(mesh, options);
  const double floor = 8.0 * hausd / (bounds.hmax * bounds.hmax);  // |kappa| giving hmax
  const double scale = 1.0 / (8.0 * hausd);
  MetricField M(mesh.vertex_capacity(), SymTensor3::identity());
  // Vertex by vertex, each on its own (parallel chunks of the slots).
  const int nv = mesh.vertex_capacity();
  run_chunks(nv, chunk_count(nv, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Vertex v(i);
      if (mesh.is_deleted(v)) continue;
      const int first = sc.first[i], last = sc.first[i + 1];
      if (first == last) continue;
      SymTensor3 m = absolute_tangent_metric(sc.form[first], sc.normal[first], floor, scale);
      if (sc.on_feature[i]) {
        for (int s = first + 1; s < last; ++s)
          m = intersect(m, absolute_tangent_metric(sc.form[s], sc.normal[s], floor, scale));
        for (const CurveDirection& d : curve_directions(mesh, v)) m = intersect(m, curve_metric(d, floor, scale));
      }
      M[i] = m;
    }
  });
  intersect_crease_metrics(mesh, hausd, floor, scale, M);
  run_chunks(nv, chunk_count(nv, 8192), [&](int, int begin, int end) {
    for (int i = begin; i < end; ++i)
      if (!mesh.is_deleted(Vertex(i)) && !mesh.is_isolated(Vertex(i))) M[i] = clamp_metric(M[i], bounds);
  });
  return M;
}

}  // namespace anisurf
