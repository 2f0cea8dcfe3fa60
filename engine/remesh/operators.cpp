#include "remesh/operators.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/features.h"
#include "locate/closest_point.h"
#include "mesh/operators.h"

namespace anisurf::remesh {

namespace {

using M = SurfaceMesh;

// The few angle thresholds of the options come back at every check: their
// cosines are kept (a small per-thread cache keyed by the angle).
double cos_deg(double deg) {
  constexpr int kSlots = 4;
  thread_local double key[kSlots] = {NAN, NAN, NAN, NAN}, value[kSlots] = {};
  thread_local int next_slot = 0;
  for (int i = 0; i < kSlots; ++i)
    if (key[i] == deg) return value[i];
  const double v = std::cos(deg * std::numbers::pi / 180.0);
  key[next_slot] = deg;
  value[next_slot] = v;
  next_slot = (next_slot + 1) % kSlots;
  return v;
}

Vec3 raw_normal(const Vec3& a, const Vec3& b, const Vec3& c) { return cross(b - a, c - a); }

// The angle thresholds of the options as cosines (computed once per check).
struct Limits {
  double cos_turn, cos_surface;
  explicit Limits(const OperatorOptions& o)
      : cos_turn(cos_deg(o.max_normal_turn_deg)), cos_surface(cos_deg(o.max_surface_angle_deg)) {}
  Limits(double turn_deg, double surface_deg) : cos_turn(cos_deg(turn_deg)), cos_surface(cos_deg(surface_deg)) {}
};

// A triangle whose height is below this fraction of its longest edge is
// degenerate: its normal is rounding noise or says nothing of the surface
// (an input's slivers). No operator makes one out of a better triangle
// (degenerate_limit). 1e-4, an angle of 0.006 degrees: at 1e-6, a vertex a
// hair off a straight ridge and two of the ridge's points passed for a
// triangle (q = 0, its ridge edge then too flat to split).
constexpr double kDegenerateHeight = 1e-4;
constexpr double kDegenerateFloor = 1e-12;

// Height over longest edge of triangle (a, b, c).
double height_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double len2 = std::max({norm2(b - a), norm2(c - b), norm2(a - c)});
  return len2 > 0 ? norm(raw_normal(a, b, c)) / len2 : 0.0;
}
double height_ratio(const SurfaceMesh& mesh, Triangle t) {
  const int* v = mesh.triangle_vertices(t);
  return height_ratio(mesh.position(Vertex(v[0])), mesh.position(Vertex(v[1])), mesh.position(Vertex(v[2])));
}

// The least height ratio a triangle replacing one of ratio `old_ratio` may
// have: kDegenerateHeight, or where the old one already was degenerate (a
// sliver of the input, the halves of one) a quarter of it.
double degenerate_limit(double old_ratio) {
  return old_ratio >= kDegenerateHeight ? kDegenerateHeight : std::max(kDegenerateFloor, 0.25 * old_ratio);
}

// A new triangle (a, b, c) replacing one of unit normal `old_n` (zero: none
// known): refused when degenerate, inverted or turned too far from old_n or
// from the surface normals `sn` at its corners (unit, or zero where unknown:
// curves, corners). With `no_worse` (a split's halves), a corner's limit is
// relaxed to what the replaced triangle already had. `degenerate`: the least
// height over longest edge (degenerate_limit of the replaced triangle).
Rejection check_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& old_n,
                         const std::array<Vec3, 3>& sn, const Limits& o, bool no_worse = false,
                         double degenerate = kDegenerateHeight) {
  const Vec3 n = raw_normal(a, b, c);
  const double len2 = std::max({norm2(b - a), norm2(c - b), norm2(a - c)});
  const double area2 = norm(n);
  if (!(area2 > degenerate * len2)) return Rejection::Inversion;  // height / longest edge
  const Vec3 u = n / area2;
  if (norm2(old_n) > 0) {
    const double d = dot(u, old_n);
    if (d <= 0) return Rejection::Inversion;
    if (d < o.cos_turn) return Rejection::Normal;
  }
  // Against the surface normals: never facing away, and with `no_worse`
  // turned beyond the limit only if no more than the replaced triangle
  // (where a coarse input turns by more than the limit within one triangle,
  // a corner whose normal is 67 degrees off its own triangles, the halves of
  // its edges stay admissible).
  const bool known = no_worse && norm2(old_n) > 0;
  for (const Vec3& s : sn) {
    if (!(norm2(s) > 0)) continue;
    const double ds = dot(u, s), before = known ? dot(old_n, s) - 1e-9 : 1.0;
    if (ds <= 0) return Rejection::Inversion;
    if (ds < o.cos_surface && ds < before) return Rejection::Normal;
  }
  return Rejection::None;
}

// Sections 5.1, 5.3-5.5 ("the oriented normal vectors ... have significantly
// changed", "element overlapping"): check_triangle compares a new triangle
// with the triangle it replaces and with the surface normal at its free
// corners (sn nonzero). The inversion measure (count_inverted) votes with
// the surface normal inside the triangle instead (1/10 of the way from each
// free corner to the centroid), which agrees with the corners' normals
// where the surface is smooth, but not always:
//  - with no free corner (every corner on a feature curve: the dense
//    curves of a noisy scan) there is no normal to compare with, and a swap
//    or collapse could turn the triangle against the surface while staying
//    close to the old normals;
//  - near a feature curve the G1 surface is only C0 and turns fast, and a
//    point inside the triangle may be located on the other side of the
//    curve (Avocado's rim), where one vote (one free corner) or two decide
//    against the corners' normals; likewise near a fold of a defective
//    input that no feature marks (thinker.mesh's flipped triangles).
// Those triangles (at most one free corner, or a corner located in a
// triangle of T_G touching a feature curve or a fold) are judged as count_inverted()
// judges them; the others (smooth regions) keep the corner test alone.
// Called last (a projection per free corner).
Rejection check_surface_side(AdaptedMesh& m, const std::array<Vec3, 3>& x, const std::array<Vec3, 3>& sn,
                             const std::array<Hint, 3>& hints) {
  const std::array<bool, 3> free = {norm2(sn[0]) > 0, norm2(sn[1]) > 0, norm2(sn[2]) > 0};
  if (free[0] + free[1] + free[2] >= 2 && !m.near_feature(hints[0]) && !m.near_feature(hints[1]) &&
      !m.near_feature(hints[2]))
    return Rejection::None;
  return m.faces_surface(x, free, hints) ? Rejection::None : Rejection::Inversion;
}

// The normal a new triangle replacing t is compared with: t's unit normal,
// or where t is degenerate (kDegenerateHeight) the mean of its corners' surface normals,
// else of its neighbours' normals (area-weighted), else zero (no reference).
Vec3 reference_normal(const AdaptedMesh& m, Triangle t) {
  const SurfaceMesh& mesh = m.mesh();
  // Area above half the height fraction times the longest edge squared.
  if (has_reliable_normal(mesh, t, 0.5 * kDegenerateHeight)) return normalized(mesh.triangle_normal(t));
  const int* v = mesh.triangle_vertices(t);
  Vec3 sum;
  for (int k = 0; k < 3; ++k) sum += m.surface_normal(Vertex(v[k]));
  if (norm2(sum) > 0) return normalized(sum);
  for (int k = 0; k < 3; ++k) {
    const Corner o = mesh.opposite(M::corner(t, k));
    if (o.is_valid()) sum += mesh.triangle_normal(M::triangle(o));
  }
  return norm2(sum) > 0 ? normalized(sum) : Vec3();
}

// The positions and metrics of triangle t with vertex `moved` (and optionally
// `also`) replaced by the placement p.
struct TriangleView {
  std::array<Vec3, 3> x;
  std::array<SymTensor3, 3> M;
  std::array<Vec3, 3> n;  // surface normals at the corners
  std::array<Hint, 3> h;  // hints on T_G
};
TriangleView view(const AdaptedMesh& m, Triangle t, Vertex moved, Vertex also, const Placement& p) {
  TriangleView v;
  for (int k = 0; k < 3; ++k) {
    const Vertex w = m.mesh().vertex(t, k);
    if (w == moved || w == also) {
      v.x[k] = p.position;
      v.M[k] = p.values.metric;
      v.n[k] = p.normal;
      v.h[k] = p.hint_g;
    } else {
      v.x[k] = m.mesh().position(w);
      v.M[k] = m.metric(w);
      v.n[k] = m.surface_normal(w);
      v.h[k] = m.hint_g(w);
    }
  }
  return v;
}

// Distance from the midpoint of a new curve segment p-w (w a curve vertex)
// to the feature curve: to the G1 curve and to T_G's own edges, the larger.
double midpoint_off_curve(AdaptedMesh& m, const Vec3& p, Vertex w) {
  const Vec3 mid = 0.5 * (p + m.mesh().position(w));
  const Placement at = m.place(mid, VertexKind::Curve, {w});
  return std::max(at.distance, norm(mid - at.on_input));
}

// Section 5.1's tolerance for the sag of a new curve segment p-w:
// OperatorOptions::curve_sag times the size the metric asks for along the
// segment (its length over its metric length; infinite for a zero metric
// length), at most curve_max_sag.
double curve_sag_tolerance(const AdaptedMesh& m, const Placement& p, Vertex w, const OperatorOptions& o) {
  const Vec3 pw = m.mesh().position(w);
  const double metric_length = m.length(p.position, p.values.metric, pw, m.metric(w));
  const double relative = metric_length > 0 ? o.curve_sag * norm(pw - p.position) / metric_length : INFINITY;
  return o.curve_max_sag > 0 ? std::min(relative, o.curve_max_sag) : relative;
}

// A move: the new segment p-w stays within the sag tolerance.
bool curve_sag_ok(AdaptedMesh& m, const Placement& p, Vertex w, const OperatorOptions& o) {
  return midpoint_off_curve(m, p.position, w) <= curve_sag_tolerance(m, p, w, o);
}

// Unit direction, or zero.
Vec3 dir(const Vec3& a, const Vec3& b) { return normalized(b - a); }

}  // namespace

std::string_view rejection_name(Rejection r) {
  switch (r) {
    case Rejection::None: return "none";
    case Rejection::Topology: return "topology";
    case Rejection::Fixed: return "fixed";
    case Rejection::Feature: return "feature";
    case Rejection::Tangent: return "tangent";
    case Rejection::Inversion: return "inversion";
    case Rejection::Normal: return "normal";
    case Rejection::Quality: return "quality";
    case Rejection::Length: return "length";
    case Rejection::Cache: return "cache";
    case Rejection::NoGain: return "no_gain";
    case Rejection::Deviation: return "deviation";
    case Rejection::kCount: break;
  }
  return "?";
}

Corner find_edge_corner(const SurfaceMesh& mesh, Vertex a, Vertex b) {
  if (!a.is_valid() || !b.is_valid() || mesh.is_deleted(a) || mesh.is_deleted(b) || mesh.is_isolated(a)) return {};
  // The fan of a, counter-clockwise from corner(a) as SurfaceMesh::fan, without its vector.
  const Corner start = mesh.corner(a);
  Corner c = start;
  int guard = 3 * mesh.triangle_capacity() + 1;
  do {
    // In c's triangle, the edges at a are a->next and prev->a.
    const Corner n = M::next(c), p = M::prev(c);
    if (mesh.vertex(n) == b) return p;  // edge a -> b is opposite prev(c)
    if (mesh.vertex(p) == b) return n;  // edge b -> a is opposite next(c)
    c = mesh.swing_ccw(c);
  } while (c.is_valid() && c != start && --guard > 0);
  return {};
}

// --- split --------------------------------------------------------------------

namespace {

// The point of edge b-d where a split puts its vertex (before projection):
// the midpoint, or with split_in_unit_pieces the point at k / n of the
// edge's metric length L, n = round(L) (at least 2), k = n / 2 rounded down.
Vec3 split_point(const AdaptedMesh& m, Vertex b, Vertex d, const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  const Vec3 pb = mesh.position(b), pd = mesh.position(d);
  double t = 0.5;
  if (o.split_in_unit_pieces) {
    const Vec3 e = pd - pb;
    const double l0 = metric_length(m.metric(b), e), l1 = metric_length(m.metric(d), e);
    const int n = std::max(2, static_cast<int>(std::lround(std::min(m.length(b, d), 1e6))));
    t = length_fraction_parameter(l0, l1, static_cast<double>(n / 2) / n, m.length_formula());
  }
  return (1 - t) * pb + t * pd;
}

// The one or two triangles of edge c, halved at x (surface normal
// `surface_n` there, zero on a curve): check_triangle against the triangle
// each replaces.
Rejection check_halves(const AdaptedMesh& m, Corner c, const Vec3& x, const Vec3& surface_n, const Limits& lim,
                       bool drawn_nowhere = false) {
  const SurfaceMesh& mesh = m.mesh();
  // The point halves the edge: within a tenth of its length of an end, or
  // of a vertex opposite the edge, it would only add a needle or a cap (a
  // projection or T_G's closest point drawn to a point already taken: a
  // fold of the input, or the closest points of a bulge all on one input
  // edge). A point `drawn_nowhere` (the midpoint moved along the edge's
  // normal only, or a feature curve's own point between the edge's ends)
  // keeps only half the opposite vertex's distance to the edge from it,
  // which a thin triangle's vertex beside the midpoint would fail at a
  // tenth of the edge.
  const Vec3 &pb = mesh.position(mesh.edge_from(c)), &pd = mesh.position(mesh.edge_to(c));
  const double end2 = 0.01 * norm2(pd - pb);
  if (!(norm2(x - pb) > end2) || !(norm2(x - pd) > end2)) return Rejection::Inversion;
  for (Corner k : {c, mesh.opposite(c)}) {
    if (!k.is_valid()) continue;
    const Vec3& pa = mesh.position(mesh.vertex(k));
    const double near2 = drawn_nowhere ? std::min(end2, 0.25 * norm2(raw_normal(pb, pd, pa)) / norm2(pd - pb)) : end2;
    if (!(norm2(x - pa) > near2)) return Rejection::Inversion;
  }
  for (Corner k : {c, mesh.opposite(c)}) {
    if (!k.is_valid()) continue;
    const Triangle t = M::triangle(k);
    const Vec3 old_n = reference_normal(m, t);
    const Vertex va = mesh.vertex(k), vb = mesh.edge_from(k), vd = mesh.edge_to(k);
    const Vec3 pa = mesh.position(va), pb = mesh.position(vb), pd = mesh.position(vd);
    const Vec3 &na = m.surface_normal(va), &nb = m.surface_normal(vb), &nd = m.surface_normal(vd);
    // The halves of a degenerate triangle (an input's sliver) are degenerate:
    // no thinner than a quarter of it.
    const double degenerate = degenerate_limit(height_ratio(pa, pb, pd));
    Rejection r = check_triangle(pa, pb, x, old_n, {na, nb, surface_n}, lim, true, degenerate);
    if (r == Rejection::None) r = check_triangle(pa, x, pd, old_n, {na, surface_n, nd}, lim, true, degenerate);
    if (r != Rejection::None) return r;
  }
  return Rejection::None;
}

// The halves of edge c at x on the surface's side (check_surface_side: at
// most one free corner, or near a feature).
Rejection check_halves_side(AdaptedMesh& m, Corner c, const Vec3& x, const Vec3& surface_n, const Hint& hint) {
  const SurfaceMesh& mesh = m.mesh();
  for (Corner k : {c, mesh.opposite(c)}) {
    if (!k.is_valid()) continue;
    const Vertex va = mesh.vertex(k), vb = mesh.edge_from(k), vd = mesh.edge_to(k);
    const Vec3 pa = mesh.position(va), pb = mesh.position(vb), pd = mesh.position(vd);
    const Vec3 &na = m.surface_normal(va), &nb = m.surface_normal(vb), &nd = m.surface_normal(vd);
    const Hint &ha = m.hint_g(va), &hb = m.hint_g(vb), &hd = m.hint_g(vd);
    Rejection r = check_surface_side(m, {pa, pb, x}, {na, nb, surface_n}, {ha, hb, hint});
    if (r == Rejection::None) r = check_surface_side(m, {pa, x, pd}, {na, surface_n, nd}, {ha, hint, hd});
    if (r != Rejection::None) return r;
  }
  return Rejection::None;
}

// Both checks of a split of c at x.
Rejection check_split_at(AdaptedMesh& m, Corner c, const Vec3& x, const Vec3& surface_n, const Hint& hint,
                         const Limits& lim, bool drawn_nowhere = false) {
  const Rejection r = check_halves(m, c, x, surface_n, lim, drawn_nowhere);
  return r == Rejection::None ? check_halves_side(m, c, x, surface_n, hint) : r;
}

}  // namespace

SplitPlan can_split(AdaptedMesh& m, Corner c, const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  SplitPlan plan;
  if (mesh.has_tag(c, kRequired)) {
    plan.why = Rejection::Fixed;
    return plan;
  }
  const Vertex b = mesh.edge_from(c), d = mesh.edge_to(c);
  plan.kind = is_feature_edge(mesh, c) ? VertexKind::Curve : VertexKind::Free;
  const Vec3 mid = split_point(m, b, d, o);

  const Limits lim(o);
  plan.at = m.place(mid, plan.kind, {b, d});
  // Figure 14: a swap instead when the new vertex would be too close to both
  // opposite vertices.
  const Corner oc = mesh.opposite(c);
  if (oc.is_valid()) {
    const Vertex a = mesh.vertex(c), e = mesh.vertex(oc);
    const double la = m.length(plan.at.position, plan.at.values.metric, mesh.position(a), m.metric(a));
    const double le = m.length(plan.at.position, plan.at.values.metric, mesh.position(e), m.metric(e));
    if (la < o.lmin && le < o.lmin && can_swap(m, c, o).why == Rejection::None) {
      plan.swap_instead = true;
      return plan;
    }
  }
  const Vec3 sn = plan.kind == VertexKind::Free ? plan.at.normal : Vec3();
  // A point of a feature curve is the curve's own between the edge's ends,
  // not drawn to a point already taken: a free vertex beside it (a strip of
  // the surface narrower than the size between two curves) only has to be
  // half its distance to the edge away; the short edge it makes to the new
  // vertex is for the collapses.
  plan.why = check_split_at(m, c, plan.at.position, sn, plan.at.hint_g, lim, plan.kind == VertexKind::Curve);
  if (plan.why != Rejection::None) {
    // Section 5.3: the projection is not admissible, the midpoint is used,
    // if it is close enough to the surface for the triangles around it
    // (a vertex far off a thin triangle would tilt everything refined
    // around it later).
    const Rejection first = plan.why;
    // The input's own closest point (on T_G's triangles or feature edge):
    // where the smooth surface strays from the input (pulled back), or
    // bulges across needles of T_G that its point would tilt (the patches
    // of slivers).
    if (norm(plan.at.on_input - plan.at.position) > 0) {
      plan.why = check_split_at(m, c, plan.at.on_input, sn, plan.at.hint_g, lim);
      if (plan.why == Rejection::None) {
        plan.at.position = plan.at.on_input;
        plan.at.pulled = true;
        return plan;
      }
    }
    double min_height = INFINITY;
    const double len = norm(mesh.position(d) - mesh.position(b));
    for (Corner k : {c, mesh.opposite(c)})
      if (k.is_valid()) min_height = std::min(min_height, norm(mesh.triangle_normal(M::triangle(k))) / len);
    const double off = norm(plan.at.position - mid);
    plan.why = off <= o.split_fallback_offset * min_height ? check_halves(m, c, mid, Vec3(), lim) : first;
    if (plan.why == Rejection::None) plan.why = check_halves_side(m, c, mid, sn, plan.at.hint_g);
    if (plan.why == Rejection::None) {
      plan.projected = false;
      plan.at.position = mid;
      plan.at.on_surface = false;
    } else {
      plan.why = first;
    }
  }
  return plan;
}

SplitPlan can_split_for_sag(AdaptedMesh& m, Corner c, const OperatorOptions& o) {
  SplitPlan plan = can_split(m, c, o);
  if (plan.why != Rejection::None || plan.swap_instead) return plan;
  const SurfaceMesh& mesh = m.mesh();
  const Vertex b = mesh.edge_from(c), d = mesh.edge_to(c);
  const Vec3 &pb = mesh.position(b), &pd = mesh.position(d);
  const double tol = sag_tolerance(m, pb, m.metric(b), pd, m.metric(d), o);
  if (!(point_segment_distance2(plan.at.position, pb, pd) > tol * tol)) plan.why = Rejection::NoGain;
  return plan;
}

SplitPlan can_split_onto_input(AdaptedMesh& m, Corner c, double max_turn_deg, double bound, bool input_first) {
  const SurfaceMesh& mesh = m.mesh();
  SplitPlan plan;
  if (mesh.has_tag(c, kRequired)) {
    plan.why = Rejection::Fixed;
    return plan;
  }
  const Vertex b = mesh.edge_from(c), d = mesh.edge_to(c);
  plan.kind = is_feature_edge(mesh, c) ? VertexKind::Curve : VertexKind::Free;
  const Vec3 mid = 0.5 * (mesh.position(b) + mesh.position(d));
  plan.at = m.place(mid, plan.kind, {b, d});
  const Limits lim(max_turn_deg, max_turn_deg);
  const Vec3 sn = plan.kind == VertexKind::Free ? plan.at.normal : Vec3();
  // The surface point, T_G's closest point, then points part of the way
  // from the midpoint to T_G within `bound` of it (the triangles tilt less;
  // the next sweep goes on).
  const Vec3 input = plan.at.on_input;
  std::array<Vec3, 4> candidates = {plan.at.position, input, mid + 0.5 * (input - mid), mid + 0.25 * (input - mid)};
  if (input_first) std::swap(candidates[0], candidates[1]);
  const std::size_t surface_slot = input_first ? 1 : 0, input_slot = input_first ? 0 : 1;
  Rejection first = Rejection::None;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (i > 0 && !(norm(candidates[i] - candidates[0]) > 0)) continue;
    if (i > 1 && norm(candidates[i] - input) > bound) continue;
    const Rejection why = check_split_at(m, c, candidates[i], sn, plan.at.hint_g, lim);
    if (why == Rejection::None) {
      plan.why = Rejection::None;
      if (i != surface_slot) {
        plan.at.position = candidates[i];
        plan.at.pulled = true;
        plan.at.on_surface = i == input_slot;
      }
      return plan;
    }
    if (i == 0) first = why;
  }
  // T_G's closest point may lie off to one side of the edge (the input bulges
  // across a long edge between thin triangles), near a vertex opposite the
  // edge: the midpoint moved along the edge's normal instead, all or half of
  // the way to T_G, when that point is within `bound` of T_G.
  if (plan.kind == VertexKind::Free) {
    Vec3 n;
    for (Corner k : {c, mesh.opposite(c)})
      if (k.is_valid()) n += normalized(mesh.triangle_normal(M::triangle(k)));
    n = normalized(n);
    const double offset = dot(input - mid, n);
    for (double share : {1.0, 0.5}) {
      const Vec3 x = mid + (share * offset) * n;
      if (!(norm(x - mid) > 0) || !(m.distance_to_input(x, {b, d}).distance <= bound)) continue;
      if (check_split_at(m, c, x, sn, plan.at.hint_g, lim, true) != Rejection::None) continue;
      plan.why = Rejection::None;
      plan.at.position = x;
      plan.at.pulled = true;
      plan.at.on_surface = false;
      return plan;
    }
  }
  plan.why = first;
  return plan;
}

Vertex split(AdaptedMesh& m, Corner c, const SplitPlan& plan) {
  SurfaceMesh& mesh = m.mesh();
  if (plan.swap_instead) {
    swap(m, c);
    return Vertex();
  }
  const std::uint8_t etags = mesh.edge_tags(c);
  const bool boundary = mesh.is_boundary_edge(c);
  const Vertex v = anisurf::split(mesh, c, plan.at.position);
  if (etags & kRidge) mesh.add_vertex_tag(v, kRidge);
  if (boundary || (etags & kBoundary)) mesh.add_vertex_tag(v, kBoundary);
  m.commit(v, plan.at);
  return v;
}

// --- collapse -----------------------------------------------------------------

namespace {

int rank(VertexKind k) { return k == VertexKind::Free ? 0 : (k == VertexKind::Curve ? 1 : 2); }

// Section 5.1's curve filter for a collapse removing r into k (k taking the
// placement p when `moves`): each new curve segment, from p to the other
// curve neighbour o of r (and of k when it moves), replaces the curve
// through the changed vertex w. Its sag is the larger of its midpoint's
// distance to the curve of T_G and w's distance to it (w lies on the curve
// between p and o). Refused when the sag exceeds the tolerance
// (curve_sag_tolerance), or when the segment turns from the old one (w-o)
// by more than max_curve_turn_deg where the curve bends (the sag above
// straight_curve_sag of the segment's length). The cheap tests first.
Rejection check_curve_collapse(AdaptedMesh& m, Vertex r, Vertex k, const Placement& p, bool moves,
                               const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  const double cos_turn = cos_deg(o.max_curve_turn_deg);
  for (Vertex w : {r, k}) {
    if (w == k && !moves) continue;
    const Vec3 pw = mesh.position(w);
    for (const FeatureEdgeAt& f : feature_edges_at(mesh, w)) {
      if (f.other == r || f.other == k) continue;
      const Vec3 po = mesh.position(f.other);
      const double straight = o.straight_curve_sag * norm(po - p.position);
      const bool turns = dot(dir(pw, po), dir(p.position, po)) < cos_turn;
      const double off = std::sqrt(point_segment_distance2(pw, p.position, po));
      if (turns && off > straight) return Rejection::Tangent;
      const double sag = std::max(off, midpoint_off_curve(m, p.position, f.other));
      if (!(sag <= curve_sag_tolerance(m, p, f.other, o))) return Rejection::Tangent;
      if (turns && sag > straight) return Rejection::Tangent;
    }
  }
  return Rejection::None;
}

// Checks removing r into k, k taking the placement p. `c` names the edge.
// True if removing r into k joins k to another vertex of a region's border
// (kFrozen) that it is not joined to yet: that edge may exist outside the
// region.
bool joins_frozen(const SurfaceMesh& mesh, Vertex r, Vertex k) {
  if (!mesh.has_tag(k, kFrozen)) return false;
  for (Vertex y : mesh.ring_vertices(r))
    if (y != k && mesh.has_tag(y, kFrozen) && !mesh.find_edge(k, y).is_valid() && !mesh.find_edge(y, k).is_valid())
      return true;
  return false;
}

// The worst eq. 17 quality of the triangles around r or k.
double worst_fan_quality(const AdaptedMesh& m, Vertex r, Vertex k) {
  const SurfaceMesh& mesh = m.mesh();
  double q = 1;
  for (Corner x : mesh.fan_corners(r)) q = std::min(q, m.quality(M::triangle(x)));
  for (Corner x : mesh.fan_corners(k)) {
    const Triangle t = M::triangle(x);
    if (!mesh.corner_of(t, r).is_valid()) q = std::min(q, m.quality(t));
  }
  return q;
}

// True if v lies on a feature curve (ridge, boundary, corner).
bool on_feature(const SurfaceMesh& mesh, Vertex v) {
  return (mesh.vertex_tags(v) & (kRidge | kBoundary | kCorner)) != 0 || mesh.is_boundary(v);
}

// True if triangle t, seen as `tv` (r replaced by k), is a needle that no
// operator can avoid (OperatorOptions::strip_width): it spans a strip
// between feature curves narrower than the size (its three vertices on
// feature curves, one of its edges along one, its height in the metric,
// twice its metric area over its longest metric edge, below strip_width),
// or it stands on an edge shorter than lmin between two corners, which no
// collapse removes (an isolated sharp edge shorter than the size).
bool is_forced_needle(const AdaptedMesh& m, Triangle t, const TriangleView& tv, Vertex r, Vertex k,
                      const OperatorOptions& o) {
  if (!(o.strip_width > 0)) return false;
  const SurfaceMesh& mesh = m.mesh();
  std::array<Vertex, 3> w;
  for (int i = 0; i < 3; ++i) {
    w[i] = mesh.vertex(t, i);
    if (w[i] == r) w[i] = k;
  }
  std::array<double, 3> l;
  for (int i = 0; i < 3; ++i) l[i] = m.length(tv.x[i], tv.M[i], tv.x[(i + 1) % 3], tv.M[(i + 1) % 3]);
  for (int i = 0; i < 3; ++i)
    if (l[i] < o.lmin && mesh.has_tag(w[i], kCorner) && mesh.has_tag(w[(i + 1) % 3], kCorner)) return true;
  for (int i = 0; i < 3; ++i)
    if (!on_feature(mesh, w[i])) return false;
  int along_curves = 0;  // t's edges keep their tags through a collapse of r into k
  for (int i = 0; i < 3; ++i) along_curves += is_feature_edge(mesh, M::corner(t, i)) ? 1 : 0;
  if (along_curves != 1) return false;
  const double s = 0.5 * (l[0] + l[1] + l[2]);
  const double area2 = s * (s - l[0]) * (s - l[1]) * (s - l[2]);  // Heron, squared
  const double longest = std::max({l[0], l[1], l[2]});
  return longest > 0 && 2 * std::sqrt(std::max(0.0, area2)) / longest < o.strip_width;
}

// The eq. 17 quality q of triangle t seen as `tv` (r replaced by k) as the
// collapse and move tests count it: 1 (no bound) for a forced needle
// (is_forced_needle), tested only below collapse_quality.
template <class View>
double counted_quality(double q, const AdaptedMesh& m, Triangle t, View&& tv, Vertex r, Vertex k,
                       const OperatorOptions& o) {
  return q < o.collapse_quality && is_forced_needle(m, t, tv(), r, k, o) ? 1.0 : q;
}

// The worst quality of the two fans of an edge before a collapse, measured
// at most once for the options of one edge (worst_fan_quality is symmetric).
struct FanQuality {
  double value = -1;  // < 0: not measured yet
  double get(const AdaptedMesh& m, Vertex r, Vertex k) {
    if (value < 0) value = worst_fan_quality(m, r, k);
    return value;
  }
};

Rejection check_collapse(AdaptedMesh& m, Corner c, Vertex r, Vertex k, const Placement& p, bool moves,
                         VertexKind kind_r, VertexKind kind_k, const OperatorOptions& o, FanQuality& fan_quality,
                         bool topology_checked = false, double* quality_after = nullptr) {
  const SurfaceMesh& mesh = m.mesh();
  if (!topology_checked && !anisurf::can_collapse(mesh, c)) return Rejection::Topology;
  if (joins_frozen(mesh, r, k)) return Rejection::Topology;
  if (kind_r == VertexKind::Curve || (moves && kind_k == VertexKind::Curve)) {
    const Rejection why = check_curve_collapse(m, r, k, p, moves, o);
    if (why != Rejection::None) return why;
  }
  // New triangles: the fans of r and k without the triangles of the edge.
  const Limits lim(o);
  double q_new = 1;
  bool any = false;
  // The new triangles, for check_surface_side after the cheaper filters
  // (storage kept from call to call on each thread).
  thread_local std::vector<TriangleView> new_triangles;
  new_triangles.clear();
  for (Vertex w : {r, k}) {
    for (Corner x : mesh.fan_corners(w)) {
      const Triangle t = M::triangle(x);
      const bool has_r = mesh.corner_of(t, r).is_valid(), has_k = mesh.corner_of(t, k).is_valid();
      if (w == k && has_r) continue;  // counted once from r's fan
      if (has_r && has_k) continue;  // removed
      if (w == k && !moves) continue;  // unchanged
      const TriangleView tv = view(m, t, r, k, p);
      const Rejection why = check_triangle(tv.x[0], tv.x[1], tv.x[2], reference_normal(m, t), tv.n, lim, false,
                                           degenerate_limit(height_ratio(mesh, t)));
      if (why != Rejection::None) return why;
      q_new = std::min(q_new, counted_quality(m.quality(tv.x, tv.M), m, t, [&] { return tv; }, r, k, o));
      any = true;
      new_triangles.push_back(tv);
      // Worse than collapse_quality and than the worst triangle of the two
      // fans before (measured only then: most collapses clear the
      // threshold). q_new only falls with the triangles still to come: the
      // test is made as it goes.
      if (q_new < o.collapse_quality && q_new < fan_quality.get(m, r, k)) return Rejection::Quality;
    }
  }
  if (!any) return Rejection::Topology;
  if (quality_after) *quality_after = q_new;
  // New or changed edges no longer than lmax.
  for (Vertex w : {r, k}) {
    if (w == k && !moves) continue;
    for (Vertex n : mesh.ring_vertices(w)) {
      if (n == r || n == k) continue;
      if (m.length(p.position, p.values.metric, mesh.position(n), m.metric(n)) > o.lmax) return Rejection::Length;
    }
  }
  // New edges across the surface stay on it (feature edges: the curve test).
  bool deviates = false;
  for_ring_edges(mesh, r, [&](Vertex n, Corner e) {
    if (deviates || n == k || is_feature_edge(mesh, e)) return;
    deviates = sags_off_input(m, p.position, p.values.metric, p.normal, k, mesh.position(n), m.metric(n),
                              m.surface_normal(n), n, false, o);
  });
  if (deviates) return Rejection::Deviation;
  for (const TriangleView& tv : new_triangles) {
    const Rejection why = check_surface_side(m, tv.x, tv.n, tv.h);
    if (why != Rejection::None) return why;
  }
  return Rejection::None;
}

// The neighbours a vertex of kind kv may be removed into, the nearest in
// the metric first: along its curve for a curve vertex, else its ring.
std::vector<Vertex> removal_targets(const AdaptedMesh& m, Vertex v, VertexKind kv) {
  const SurfaceMesh& mesh = m.mesh();
  std::vector<std::pair<double, Vertex>> by_length;
  if (kv == VertexKind::Curve) {
    for (const FeatureEdgeAt& f : feature_edges_at(mesh, v)) by_length.push_back({m.length(v, f.other), f.other});
  } else {
    for (Vertex w : mesh.ring_vertices(v)) by_length.push_back({m.length(v, w), w});
  }
  std::sort(by_length.begin(), by_length.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Vertex> out;
  out.reserve(by_length.size());
  for (const auto& [length, w] : by_length) out.push_back(w);
  return out;
}

// The plan of a collapse that passed its checks.
CollapsePlan accepted_collapse(Corner edge, Vertex removed, Vertex kept, const Placement& at, bool moves) {
  CollapsePlan p;
  p.why = Rejection::None;
  p.edge = edge;
  p.removed = removed;
  p.kept = kept;
  p.at = at;
  p.moves = moves;
  return p;
}

}  // namespace

CollapsePlan can_collapse(AdaptedMesh& m, Corner c, const OperatorOptions& o, double length) {
  const SurfaceMesh& mesh = m.mesh();
  const Vertex p = mesh.edge_from(c), q = mesh.edge_to(c);
  const VertexKind kp = m.kind(p), kq = m.kind(q);
  const bool feature_edge = is_feature_edge(mesh, c);
  CollapsePlan out;
  out.edge = c;
  out.why = Rejection::Fixed;
  if ((kp == VertexKind::Fixed && kq == VertexKind::Fixed) || mesh.has_tag(c, kRequired)) return out;

  // May r be removed into the other end?
  auto removable = [&](VertexKind kr) {
    if (kr == VertexKind::Fixed) return Rejection::Fixed;
    if (kr == VertexKind::Curve && !feature_edge) return Rejection::Feature;
    return Rejection::None;
  };
  struct Option {
    Vertex removed, kept;
    VertexKind kr, kk;
    bool moves;
  };
  std::array<Option, 3> options;
  int n_options = 0;
  const bool midpoint = kp == kq && removable(kp) == Rejection::None;
  const bool in_place_first = length >= 0 && length < o.collapse_in_place_length;
  if (midpoint && !in_place_first) options[n_options++] = {p, q, kp, kq, true};
  // The less constrained end first.
  if (rank(kp) <= rank(kq)) {
    options[n_options++] = {p, q, kp, kq, false};
    options[n_options++] = {q, p, kq, kp, false};
  } else {
    options[n_options++] = {q, p, kq, kp, false};
    options[n_options++] = {p, q, kp, kq, false};
  }
  if (midpoint && in_place_first) options[n_options++] = {p, q, kp, kq, true};
  Rejection last = Rejection::Fixed;
  bool topology_checked = false;
  FanQuality fan_quality;
  for (int i = 0; i < n_options; ++i) {
    const Option& op = options[i];
    const Rejection why = removable(op.kr);
    if (why != Rejection::None) {
      if (last == Rejection::Fixed) last = why;
      continue;
    }
    // The topological check depends on the edge only: once for all options
    // (a refusal refuses them all, before any projection).
    if (!topology_checked) {
      if (!anisurf::can_collapse(mesh, c)) {
        out.why = Rejection::Topology;
        return out;
      }
      topology_checked = true;
    }
    Placement at;
    if (op.moves) {
      const Vec3 mid = 0.5 * (mesh.position(p) + mesh.position(q));
      at = m.place(mid, op.kk, {p, q});
    } else {
      at = m.current(op.kept);
    }
    last = check_collapse(m, c, op.removed, op.kept, at, op.moves, op.kr, op.kk, o, fan_quality, true);
    if (last == Rejection::None) return accepted_collapse(c, op.removed, op.kept, at, op.moves);
  }
  out.why = last;
  return out;
}

CollapsePlan can_remove_vertex(AdaptedMesh& m, Vertex v, const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  CollapsePlan out;
  const VertexKind kv = m.kind(v);
  out.why = Rejection::Fixed;
  if (kv == VertexKind::Fixed) return out;
  const std::vector<Vertex> into = removal_targets(m, v, kv);
  for (Vertex w : into) {
    // The corner of the edge with v as edge_from, or (boundary edge w -> v)
    // the one with w as edge_from: collapse() then moves v's data to the slot.
    Corner c = find_edge_corner(mesh, v, w);
    if (!c.is_valid()) continue;
    const Placement at = m.current(w);
    FanQuality fan_quality;
    out.why = check_collapse(m, c, v, w, at, false, kv, m.kind(w), o, fan_quality);
    if (out.why == Rejection::None) return accepted_collapse(c, v, w, at, false);
  }
  return out;
}

CollapsePlan can_collapse_for_quality(AdaptedMesh& m, Vertex v, const OperatorOptions& o, double gain) {
  const SurfaceMesh& mesh = m.mesh();
  CollapsePlan out;
  const VertexKind kv = m.kind(v);
  out.why = Rejection::Fixed;
  if (kv == VertexKind::Fixed) return out;
  double fan_v = 1;
  for (Corner x : mesh.fan_corners(v)) fan_v = std::min(fan_v, m.quality(M::triangle(x)));
  const std::vector<Vertex> into = removal_targets(m, v, kv);
  OperatorOptions judged_here = o;  // its quality threshold: the triangles replaced
  for (Vertex w : into) {
    const Corner c = find_edge_corner(mesh, v, w);
    if (!c.is_valid()) continue;
    if (!anisurf::can_collapse(mesh, c)) {
      out.why = Rejection::Topology;
      continue;
    }
    const VertexKind kw = m.kind(w);
    for (const bool moves : {false, true}) {
      if (moves && kw != kv) continue;  // the midpoint for ends alike, as can_collapse
      const Placement at = moves ? m.place(0.5 * (mesh.position(v) + mesh.position(w)), kw, {v, w}) : m.current(w);
      double before = fan_v;
      if (moves)
        for (Corner x : mesh.fan_corners(w)) before = std::min(before, m.quality(M::triangle(x)));
      // check_collapse refuses a new triangle below gain x before as it
      // meets it, before its costlier tests (lengths, the sag's projections).
      judged_here.collapse_quality = gain * before;
      FanQuality threshold;
      threshold.value = gain * before;
      double after = 0;
      Rejection why = check_collapse(m, c, v, w, at, moves, kv, kw, judged_here, threshold, true, &after);
      if (why == Rejection::None && !(after > gain * before)) why = Rejection::Quality;
      out.why = why;
      if (why == Rejection::None) return accepted_collapse(c, v, w, at, moves);
    }
  }
  return out;
}

Vertex collapse(AdaptedMesh& m, const CollapsePlan& plan) {
  SurfaceMesh& mesh = m.mesh();
  // The topological collapse removes edge_from(edge); the surviving slot takes
  // the kept vertex's tags, reference, properties and placement.
  const std::uint8_t tags = mesh.vertex_tags(plan.kept);
  const int ref = mesh.vertex_ref(plan.kept);
  const Vertex survivor = mesh.edge_to(plan.edge);
  if (survivor != plan.kept) {
    PropertyContainer& props = mesh.vertex_properties();
    PropertyContainer::copy_entry(props.pairs_with(props), static_cast<std::size_t>(plan.kept.idx),
                                  static_cast<std::size_t>(survivor.idx));
  }
  const Vertex v = anisurf::collapse(mesh, plan.edge);
  mesh.set_vertex_tags(v, tags);
  mesh.set_vertex_ref(v, ref);
  m.commit(v, plan.at);
  return v;
}

// --- swap ---------------------------------------------------------------------

SwapPlan can_swap(AdaptedMesh& m, Corner c, const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  SwapPlan plan;
  if (mesh.is_boundary_edge(c) || is_feature_edge(mesh, c)) {
    plan.why = Rejection::Feature;
    return plan;
  }
  if (mesh.has_tag(c, kRequired)) {
    plan.why = Rejection::Fixed;
    return plan;
  }
  // can_flip (mesh/operators.h) without its one-ring vector: the opposite
  // triangle differs here, and the new diagonal a-e is not an edge already
  // (a walk around a: checked once the cheap tests below pass).
  const Corner oc = mesh.opposite(c);
  if (M::triangle(oc) == M::triangle(c) || mesh.vertex(c) == mesh.vertex(oc)) {
    plan.why = Rejection::Topology;
    return plan;
  }
  const Vertex a = mesh.vertex(c), b = mesh.edge_from(c), d = mesh.edge_to(c), e = mesh.vertex(oc);
  if (mesh.has_tag(a, kFrozen) && mesh.has_tag(e, kFrozen)) {  // the diagonal may exist outside the region
    plan.why = Rejection::Topology;
    return plan;
  }
  const Vec3 &pa = mesh.position(a), &pb = mesh.position(b), &pd = mesh.position(d), &pe = mesh.position(e);
  // The quality first: most swaps tried bring no gain, and this test reads
  // the positions and metrics only.
  const SymTensor3 &Ma = m.metric(a), &Mb = m.metric(b), &Md = m.metric(d), &Me = m.metric(e);
  // Eq. 17 in one metric per triangle (AdaptedMesh::quality_in_one_metric):
  // with per-edge metrics, the coarse triangles of a strongly varying metric
  // read c_K = 0 and any swap "improved" them, into pairs of needles along
  // long chords of the curved surface, which no split could refine later.
  plan.quality_before =
      std::min(m.quality_in_one_metric({pa, pb, pd}, {Ma, Mb, Md}), m.quality_in_one_metric({pe, pd, pb}, {Me, Md, Mb}));
  // The second new triangle is measured only when the first one gains.
  const double needed = o.swap_gain * plan.quality_before;
  plan.quality_after = m.quality_in_one_metric({pa, pb, pe}, {Ma, Mb, Me});
  if (plan.quality_after > needed)
    plan.quality_after = std::min(plan.quality_after, m.quality_in_one_metric({pe, pd, pa}, {Me, Md, Ma}));
  if (!(plan.quality_after > needed)) {
    plan.why = Rejection::Quality;
    return plan;
  }
  const Vec3 n1 = reference_normal(m, M::triangle(c)), n2 = reference_normal(m, M::triangle(oc));
  const Vec3 navg = normalized(n1 + n2);
  const Limits lim(o);
  const Vec3 &na = m.surface_normal(a), &nb = m.surface_normal(b), &nd = m.surface_normal(d), &ne = m.surface_normal(e);
  for (const auto& [t, sn] : {std::pair{std::array<Vec3, 3>{pa, pb, pe}, std::array<Vec3, 3>{na, nb, ne}},
                              std::pair{std::array<Vec3, 3>{pe, pd, pa}, std::array<Vec3, 3>{ne, nd, na}}}) {
    const Rejection r = check_triangle(
        t[0], t[1], t[2], navg, sn, lim, false,
        degenerate_limit(std::min(height_ratio(mesh, M::triangle(c)), height_ratio(mesh, M::triangle(oc)))));
    if (r != Rejection::None) {
      plan.why = r;
      return plan;
    }
  }
  const Vec3 m1 = normalized(raw_normal(pa, pb, pe)), m2 = normalized(raw_normal(pe, pd, pa));
  if (dot(m1, m2) < std::min(dot(n1, n2), cos_deg(0.5 * o.max_normal_turn_deg))) {
    plan.why = Rejection::Normal;
    return plan;
  }
  if (find_edge_corner(mesh, a, e).is_valid()) {
    plan.why = Rejection::Topology;
    return plan;
  }
  const Hint &ha = m.hint_g(a), &hb = m.hint_g(b), &hd = m.hint_g(d), &he = m.hint_g(e);
  Rejection r = check_surface_side(m, {pa, pb, pe}, {na, nb, ne}, {ha, hb, he});
  if (r == Rejection::None) r = check_surface_side(m, {pe, pd, pa}, {ne, nd, na}, {he, hd, ha});
  // The new diagonal stays on the surface (else the next split undoes it).
  if (r == Rejection::None && sags_off_input(m, pa, Ma, na, a, pe, Me, ne, e, false, o) &&
      !sags_off_input(m, pb, Mb, nb, b, pd, Md, nd, d, false, o))
    r = Rejection::Deviation;
  plan.why = r;
  return plan;
}

Corner swap(AdaptedMesh& m, Corner c) { return flip(m.mesh(), c); }

// --- move ---------------------------------------------------------------------

namespace {

// Section 5's fidelity test for smoothing: an edge across the surface from
// v's new place `at` to a ring neighbour sags off the input while the edge
// as it is does not (smoothing must not undo what the splits and the
// collapses' own test kept; an edge already off is left to the splits).
bool moved_edge_sags_off_input(AdaptedMesh& m, Vertex v, const Placement& at, const std::vector<Vertex>& ring,
                               const OperatorOptions& o) {
  if (!(o.surface_sag > 0)) return false;
  const SurfaceMesh& mesh = m.mesh();
  for (Vertex w : ring) {
    const Corner e = find_edge_corner(mesh, v, w);
    if (e.is_valid() && is_feature_edge(mesh, e)) continue;  // curve segments: curve_sag_ok
    if (sags_off_input(m, at.position, at.values.metric, at.normal, v, mesh.position(w), m.metric(w),
                       m.surface_normal(w), w, false, o) &&
        !edge_sags_off_input(m, v, w, false, o))
      return true;
  }
  return false;
}

}  // namespace

namespace {

// What a move of v is checked against (section 5.5): its ring, its fan's
// reference normals and degenerate limits, the lengths of its edges and the
// worst quality of its fan as they are.
struct MoveCheck {
  AdaptedMesh& m;
  Vertex v;
  VertexKind kind;
  const OperatorOptions& o;
  Limits lim;
  std::vector<Vertex> ring, curve_nbrs;
  std::vector<Corner> fan;
  std::vector<Vec3> old_n;
  std::vector<double> old_limit, old_len;
  double quality_before = 1;
  double shortest = INFINITY;
  // No incident edge shorter than lmin gets shorter (the relocation of
  // worst elements: it must not trade the lengths of good triangles).
  bool keeps_short_edges = false;

  MoveCheck(AdaptedMesh& mesh_, Vertex v_, const OperatorOptions& o_)
      : m(mesh_), v(v_), kind(mesh_.kind(v_)), o(o_), lim(o_) {
    const SurfaceMesh& mesh = m.mesh();
    ring = one_ring(mesh, v);
    if (kind == VertexKind::Curve)
      for (const FeatureEdgeAt& f : feature_edges_at(mesh, v)) curve_nbrs.push_back(f.other);
    const Vec3& s = mesh.position(v);
    for (Vertex w : ring) shortest = std::min(shortest, norm(mesh.position(w) - s));
    fan = mesh.fan(v);
    old_n.reserve(fan.size());
    old_limit.reserve(fan.size());
    for (Corner x : fan) {
      const Triangle t = M::triangle(x);
      old_n.push_back(reference_normal(m, t));
      old_limit.push_back(degenerate_limit(height_ratio(m.mesh(), t)));
      const auto current = [&] { return view(m, t, Vertex(), Vertex(), {}); };
      quality_before = std::min(quality_before, counted_quality(m.quality(t), m, t, current, {}, {}, o));
    }
    old_len.reserve(ring.size());
    for (Vertex w : ring) old_len.push_back(m.length(v, w));
  }
  // The neighbours eq. 19 averages: the ring, or the curve's two.
  const std::vector<Vertex>& neighbours() const { return kind == VertexKind::Curve ? curve_nbrs : ring; }

  // Every filter of a move of v to `at` (placed): validity and normals,
  // the worst quality at least `least` (a vertex off the surface: valid
  // only), the lengths, the curve's sag, the input's sag, the surface's
  // side. `q` gets the worst quality of the fan there.
  Rejection check(const Placement& at, double least, double& q) const {
    const SurfaceMesh& mesh = m.mesh();
    q = 1;
    Rejection last = Rejection::None;
    for (std::size_t i = 0; i < fan.size() && last == Rejection::None; ++i) {
      const TriangleView tv = view(m, M::triangle(fan[i]), v, Vertex(), at);
      last = check_triangle(tv.x[0], tv.x[1], tv.x[2], old_n[i], tv.n, lim, false, old_limit[i]);
      q = std::min(q, counted_quality(m.quality(tv.x, tv.M), m, M::triangle(fan[i]), [&] { return tv; }, {}, {}, o));
      // q only falls with the rest of the fan: the test is made as it goes.
      if (last == Rejection::None && ((m.on_surface(v) && !(q >= least)) || q <= 0)) last = Rejection::Quality;
    }
    if (last != Rejection::None) return last;
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vertex w = ring[i];
      const double l_new = m.length(at.position, at.values.metric, mesh.position(w), m.metric(w));
      if (l_new > o.lmax && l_new > old_len[i]) return Rejection::Length;
      if (o.move_keeps_lmin && quality_before >= o.keep_lmin_quality && l_new < o.lmin && old_len[i] >= o.lmin)
        return Rejection::Length;
      if (keeps_short_edges && l_new < o.lmin && l_new < old_len[i]) return Rejection::Length;
    }
    if (kind == VertexKind::Curve)
      for (Vertex w : curve_nbrs)
        if (!curve_sag_ok(m, at, w, o)) return Rejection::Tangent;
    if (m.on_surface(v) && moved_edge_sags_off_input(m, v, at, ring, o)) return Rejection::Deviation;
    for (std::size_t i = 0; i < fan.size() && last == Rejection::None; ++i) {
      const TriangleView tv = view(m, M::triangle(fan[i]), v, Vertex(), at);
      last = check_surface_side(m, tv.x, tv.n, tv.h);
    }
    return last;
  }

  // The displacement dx from v, halved after each refusal (at most
  // o.move_backtracks tries, and not below o.min_move x the shortest edge
  // once v is on the surface), the first placement that passes check()
  // with a worst quality of at least `least`.
  MovePlan first_passing(Vec3 dx, double least) const {
    MovePlan plan;
    plan.quality_before = quality_before;
    const Vec3 s = m.mesh().position(v);
    Rejection last = Rejection::NoGain;
    for (int k = 0; k < o.move_backtracks; ++k, dx *= 0.5) {
      if (k > 0 && m.on_surface(v) && !(norm(dx) > o.min_move * shortest)) break;
      ++plan.tries;
      const Placement at = m.place(s + dx, kind, {v});
      double q = 1;
      last = check(at, least, q);
      if (last != Rejection::None) continue;
      plan.why = Rejection::None;
      plan.at = at;
      plan.quality_after = q;
      return plan;
    }
    plan.why = last;
    return plan;
  }
};

}  // namespace

MovePlan can_move(AdaptedMesh& m, Vertex v, const OperatorOptions& o) {
  const SurfaceMesh& mesh = m.mesh();
  MovePlan plan;
  if (m.kind(v) == VertexKind::Fixed) {
    plan.why = Rejection::Fixed;
    return plan;
  }
  const MoveCheck mc(m, v, o);
  const Vec3 s = mesh.position(v);
  const SymTensor3& Mi = m.metric(v);
  const SymTensor3 Mi_inv = inverse(Mi);
  // Eq. 19 with the edge metrics M_j = ((M_s^-1 + M_j^-1) / 2)^-1 (M_s
  // itself where both ends hold the same metric: a uniform field).
  SymTensor3 A{};
  Vec3 rhs;
  for (Vertex w : mc.neighbours()) {
    const SymTensor3& Mw = m.metric(w);
    const SymTensor3 Mj = Mw == Mi ? Mi : inverse(0.5 * (Mi_inv + inverse(Mw)));
    A += Mj;
    rhs += Mj * mesh.position(w);
  }
  if (!(det(A) > 0)) {
    plan.why = Rejection::NoGain;
    return plan;
  }
  const Vec3 p0 = inverse(A) * rhs;
  Vec3 dx = o.omega * (p0 - s);
  const double dmax = o.max_move * mc.shortest;
  if (norm(dx) > dmax) dx *= dmax / norm(dx);
  if (!(norm(dx) > o.min_move * mc.shortest)) {
    if (m.on_surface(v)) {
      plan.why = Rejection::NoGain;
      return plan;
    }
    dx = Vec3();  // only the projection onto the surface
  }
  // Not worse than before (times move_quality_factor); a vertex off the
  // surface is projected whatever the quality (validity only).
  return mc.first_passing(dx, o.move_quality_factor * mc.quality_before);
}

MovePlan can_move_for_worst(AdaptedMesh& m, Vertex v, const OperatorOptions& o, double gain, double trade_below) {
  const SurfaceMesh& mesh = m.mesh();
  MovePlan plan;
  if (m.kind(v) != VertexKind::Free || !m.on_surface(v)) {
    plan.why = Rejection::Fixed;
    return plan;
  }
  const Vec3& n = m.surface_normal(v);
  if (!(norm2(n) > 0)) {
    plan.why = Rejection::NoGain;
    return plan;
  }
  const Vec3 s = mesh.position(v);
  // The fan's worst quality with v at s + x, its metric and the others' as
  // they are, unprojected: what the search climbs (the placement checks the
  // point it ends at).
  std::vector<std::array<Vertex, 3>> tris;
  double shortest = INFINITY;
  for (Corner c : mesh.fan(v)) {
    const Triangle t = M::triangle(c);
    tris.push_back({mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2)});
  }
  for (Vertex w : one_ring(mesh, v)) shortest = std::min(shortest, norm(mesh.position(w) - s));
  // Triangles whose vertices' metrics differ by more than 5%: there the
  // measured quality depends on how lengths are read between the vertices
  // (eq. 6 or 7, the field's own jumps), so such a triangle is only kept
  // from getting worse, and the others are what the search improves.
  const double kVaries = 0.05;
  std::vector<char> varies(tris.size(), 0);
  int uniform = 0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const SymTensor3& M0 = m.metric(tris[i][0]);
    for (int k = 1; k < 3; ++k)
      if (!(frobenius_norm(m.metric(tris[i][k]) - M0) <= kVaries * frobenius_norm(M0))) varies[i] = 1;
    uniform += varies[i] ? 0 : 1;
  }
  if (uniform == 0) {
    plan.why = Rejection::NoGain;
    return plan;
  }
  std::vector<double> kept(tris.size(), 0.0);  // the varying triangles' qualities as they are
  // The worst and the summed quality of the uniform triangles with v at
  // s + x, its metric and the others' as they are, unprojected (the
  // placement checks the point the search ends at); the worst is -1 where a
  // varying triangle gets worse.
  auto qualities_at = [&](const Vec3& x, bool record = false) {
    std::pair<double, double> q{1.0, 0.0};
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const auto& t = tris[i];
      std::array<Vec3, 3> p;
      std::array<SymTensor3, 3> M3;
      for (int k = 0; k < 3; ++k) {
        p[k] = t[k] == v ? s + x : mesh.position(t[k]);
        M3[k] = m.metric(t[k]);
      }
      const double qt = m.quality(p, M3);
      if (varies[i]) {
        if (record) kept[i] = qt;
        else if (qt < kept[i]) q.first = -1;
        continue;
      }
      q.first = std::min(q.first, qt);
      q.second += qt;
    }
    return q;
  };
  // Compass search in the tangent plane: eight directions, the step halved
  // where none gains; the worst quality climbs and the sum over the fan
  // does not fall, or, for a worst triangle below trade_below in a fan
  // whose metric does not vary, falls by no more than the worst gains.
  const Vec3 un = normalized(n);
  const Vec3 axis = std::abs(un.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(un, axis)), e2 = cross(un, e1);
  const double r = 1.0 / std::sqrt(2.0);
  const std::array<Vec3, 8> dirs = {e1, -1.0 * e1, e2, -1.0 * e2, r * (e1 + e2), r * (e1 - e2), r * (e2 - e1), -r * (e1 + e2)};
  Vec3 x;
  const auto [start, start_sum] = qualities_at(x, true);
  const double trade = uniform == static_cast<int>(tris.size()) ? trade_below : 0.0;
  double best = start;
  double step = 0.25 * shortest;
  const double smallest = o.min_move * shortest;
  for (int evals = 0; step >= smallest && evals < 48;) {
    int chosen = -1;
    double chosen_q = best;
    for (int d = 0; d < 8; ++d, ++evals) {
      const auto [q, sum] = qualities_at(x + step * dirs[static_cast<std::size_t>(d)]);
      if (q > chosen_q && sum >= start_sum - (start < trade ? q - start : 0.0)) {
        chosen_q = q;
        chosen = d;
      }
    }
    if (chosen < 0) {
      step *= 0.5;
      continue;
    }
    x += step * dirs[static_cast<std::size_t>(chosen)];
    best = chosen_q;
  }
  if (!(best > gain * start) || !(norm(x) > smallest)) {
    plan.why = Rejection::NoGain;
    return plan;
  }
  MoveCheck mc(m, v, o);
  mc.keeps_short_edges = true;
  MovePlan placed = mc.first_passing(x, uniform == static_cast<int>(tris.size()) ? gain * mc.quality_before : mc.quality_before);
  if (placed.why != Rejection::None) return placed;
  // The varying triangles with v where it lands (its metric read there);
  // mc.fan is the fan `tris` was taken from, in the same order.
  for (std::size_t i = 0; i < mc.fan.size(); ++i) {
    if (!varies[i]) continue;
    const Triangle t = M::triangle(mc.fan[i]);
    const TriangleView tv = view(m, t, v, Vertex(), placed.at);
    if (m.quality(tv.x, tv.M) < m.quality(t)) {
      placed.why = Rejection::Quality;
      return placed;
    }
  }
  return placed;
}

void move(AdaptedMesh& m, Vertex v, const MovePlan& plan) { m.commit(v, plan.at); }

double sag_tolerance(const AdaptedMesh& m, const Vec3& pa, const SymTensor3& Ma, const Vec3& pb, const SymTensor3& Mb,
                     const OperatorOptions& o) {
  const double metric_length = m.length(pa, Ma, pb, Mb);
  if (!(o.surface_sag > 0) || !(metric_length > 0)) return INFINITY;
  const double tol = o.surface_sag * norm(pb - pa) / metric_length;
  return o.surface_max_sag > 0 ? std::min(tol, o.surface_max_sag) : tol;
}

bool sags_off_input(AdaptedMesh& m, const Vec3& pa, const SymTensor3& Ma, const Vec3& na, Vertex a, const Vec3& pb,
                    const SymTensor3& Mb, const Vec3& nb, Vertex b, bool curve, const OperatorOptions& o) {
  const double tol = sag_tolerance(m, pa, Ma, pb, Mb, o);
  const double len = norm(pb - pa);
  if (!(len > 2 * tol)) return false;
  // A smooth surface turning by theta between the ends sags by about
  // len theta / 8 (a circle): far below the tolerance, no projection.
  if (norm2(na) > 0 && norm2(nb) > 0) {
    // theta = atan2(s, c) <= s / c where c > 0: the quotient settles most
    // (less a margin for the rounding of the arc tangent and the products).
    const double s = norm(cross(na, nb)), c = dot(na, nb);
    if (c > 0 && len * s < 2 * tol * c * (1 - 1e-12)) return false;
    if (len * std::atan2(s, c) < 2 * tol) return false;
  }
  // The midpoint against the point a new vertex there would take (on the
  // smooth surface, within the input bound): the segment's chordal sag.
  const Vec3 mid = 0.5 * (pa + pb);
  return !m.placed_within(mid, curve ? VertexKind::Curve : VertexKind::Free, {a, b}, tol);
}

bool edge_sags_off_input(AdaptedMesh& m, Vertex a, Vertex b, const OperatorOptions& o) {
  if (!(o.surface_sag > 0)) return false;
  const Corner e = find_edge_corner(m.mesh(), a, b);
  return edge_sags_off_input(m, a, b, e.is_valid() && is_feature_edge(m.mesh(), e), o);
}

bool edge_sags_off_input(AdaptedMesh& m, Vertex a, Vertex b, bool curve, const OperatorOptions& o) {
  if (!(o.surface_sag > 0)) return false;
  const SurfaceMesh& mesh = m.mesh();
  return sags_off_input(m, mesh.position(a), m.metric(a), m.surface_normal(a), a, mesh.position(b), m.metric(b),
                        m.surface_normal(b), b, curve, o);
}

}  // namespace anisurf::remesh
