// The local operators of the report's section 5 on T_1, each a check `can_X`
// (topology from mesh/operators.h plus the geometric and metric filters; it
// returns the decision and the placements it computed) and an action `X`
// (applies a decision, then calls the data-transfer hook for the vertices it
// created or moved). An edge is named by a corner as in mesh/operators.h.
#pragma once
#include <array>
#include <string_view>
#include <vector>

#include "remesh/adapted_mesh.h"

namespace anisurf::remesh {

// f(w, e) for each neighbour w of v in the order of ring_vertices(v), e a
// corner naming the edge between them (v -> w; w -> v for the neighbour that
// closes the open fan of a boundary vertex).
template <class F>
void for_ring_edges(const SurfaceMesh& mesh, Vertex v, F&& f) {
  Corner last;
  for (Corner c : mesh.fan_corners(v)) {
    f(mesh.vertex(SurfaceMesh::next(c)), SurfaceMesh::prev(c));
    last = c;
  }
  if (last.is_valid() && mesh.is_boundary(v)) f(mesh.vertex(SurfaceMesh::prev(last)), SurfaceMesh::next(last));
}

// Why an operator was refused (the filters, in the order they are tried).
enum class Rejection : int {
  None = 0,
  Topology,     // mesh/operators.h refused (link condition, boundary, existing diagonal ...), or an edge between two region borders (kFrozen)
  Fixed,        // a fixed (corner, required) vertex would be removed or moved, or a required edge changed
  Feature,      // a feature edge would be swapped, or a curve vertex left its curve
  Tangent,      // a curve would turn or sag too much (collapse or move of a curve vertex)
  Inversion,    // a triangle would be inverted or degenerate
  Normal,       // a triangle normal would turn too far (from its old normal or the surface)
  Quality,      // eq. 17 quality: worse than the threshold and than before
  Length,       // a collapse would create an edge longer than lmax, a move one beyond it
  Cache,        // undoes one of the last modifications (Remark 5)
  NoGain,       // move: the vertex is already at its optimum; split for the sag: the new vertex stays on the chord
  Deviation,    // a new edge would leave the input surface by more than the sag tolerance
  kCount
};
std::string_view rejection_name(Rejection r);

// Thresholds of the filters. Defaults: the report's lmin / lmax; the angles
// are this implementation's choices (the report says "significantly changed").
struct OperatorOptions {
  double lmax = 1.4;  // section 6: edges longer are split
  double lmin = 0.6;  // section 6: edges shorter are collapsed
  // Largest angle between a new triangle's normal and the normal of the
  // triangle it replaces (split, collapse, swap, move).
  double max_normal_turn_deg = 45.0;
  // Largest angle between a new triangle's normal and the surface normal at
  // each of its free vertices (stored per vertex when it was placed).
  double max_surface_angle_deg = 60.0;
  // Curve vertices (a collapse or a move along a ridge, boundary or
  // reference-interface curve, section 5.1): each new curve segment is
  // compared with the feature curve of T_G it stands for.
  // Sag: the largest distance of a new segment from that curve (its
  // midpoint's distance to the curve; for a collapse also the removed
  // vertex's distance to the segment), relative to the size h the metric
  // asks for along the segment (its length over its metric length). A
  // straight curve has no sag and is coarsened as far as the metric asks; a
  // curved one until its chords sag by curve_sag * h: on an arc of radius r,
  // segments of the size h when h <= 8 curve_sag r (the polygon turning by
  // up to 8 curve_sag radians per vertex), shorter ones (sqrt(8 curve_sag r
  // h)) where it asks for coarser. 0.1 (46 degrees per vertex at most) lets
  // the metric of the report's section 7.3 coarsen the half-circle crease
  // (radius 6.4, size 4) from 24 to 8 edges (tests/test_remesh_paper73.cpp);
  // curve_max_sag (> 0, absolute: the adaptation's chordal deviation hausd)
  // caps it where the metric is coarse.
  double curve_sag = 0.1;
  double curve_max_sag = 0;
  // The same for the edges across the surface: an edge whose midpoint lies
  // farther from the surface than surface_sag times the size the metric
  // asks for along it (and than surface_max_sag, absolute, when > 0) is
  // split even when it is short enough, and no collapse creates one
  // (0: no such test). Edges shorter than twice the tolerance are left (a
  // split there cannot bring the midpoint closer: a crease).
  double surface_sag = 0.1;
  double surface_max_sag = 0;
  // Turn: the largest angle between a new curve segment and the segment it
  // replaces (section 5.1, "their tangent vectors are quite different"):
  // keeps a bend of the curve (below the corner angle) from being cut where
  // the metric is coarse enough for the sag to allow it.
  double max_curve_turn_deg = 25.0;
  // The turn limit applies where the curve bends over the new segment, not
  // where the segment's sag stays below this share of its length (there the
  // curve is straight: a short old segment may point anywhere without the
  // curve changing).
  double straight_curve_sag = 0.005;
  // Split: the straight midpoint replaces a refused projection (section 5.3)
  // only when the projection is within this share of the smallest height of
  // the split triangles.
  double split_fallback_offset = 0.05;
  // Split: an edge of metric length L is cut where it ends best in
  // n = round(L) unit pieces, at k / n of its length (k = n / 2 rounded
  // down), instead of the report's midpoint: halving a 3-long edge twice
  // would leave 0.75-long pieces (a coarse boundary split into edges of
  // 0.77: hemi's triangles along it stretched, q mean 0.905 against 0.965).
  bool split_in_unit_pieces = true;
  // Collapse: the worst new quality must be at least the worst old quality
  // or this threshold (section 5.1's metric check).
  double collapse_quality = 0.3;
  // Collapse and move: needles no operator can avoid, where the input is
  // narrower than the size, do not count against collapse_quality or the
  // move's quality test (they must still be valid: check_triangle), so the
  // mesh around them is coarsened to the size as elsewhere. They are the
  // triangles whose three vertices lie on feature curves, one edge along
  // one, and whose height in the metric is below strip_width (a strip
  // between two curves: a blunt trailing edge, the side of a thin plate,
  // one layer of needles along it), and those on an edge shorter than lmin
  // between two corners (an isolated sharp edge shorter than the size).
  // 0: every triangle counts.
  double strip_width = 0.5;
  // Collapse: an edge shorter than this in the metric (far below lmin: a
  // coarsening, where the next collapses and the smoothing place the
  // vertices again) first tries keeping an end where it is, which needs no
  // projection onto the surface; the midpoint comes after. 0: the midpoint
  // first for every edge whose ends are alike.
  double collapse_in_place_length = 0.3;
  // Swap: the new worst quality must exceed the old one by this factor (eq. 17, section 5.4).
  double swap_gain = 1.0 + 1e-6;
  // Move (section 5.5): relaxation omega of the displacement toward eq. 19,
  // its bound relative to the shortest incident edge, and the number of
  // placements tried, the displacement halved after each ("about 8-10").
  double omega = 0.6;
  double max_move = 0.5;
  // Displacements shorter than this share of the shortest incident edge are
  // not worth a move (the vertex is at its optimum): none is tried, and the
  // halvings stop there.
  double min_move = 0.03;
  int move_backtracks = 8;
  // Move: accept when the worst new quality is at least this factor times
  // the worst old one (1: the report's "greater than"; below 1: Remark 4's
  // relaxed first passes).
  double move_quality_factor = 1.0;
  // Move: refused when it shortens an edge of lmin or more below lmin and
  // the worst quality of the vertex's fan is keep_lmin_quality or more (set
  // by the final smoothing, after which no collapse removes such an edge; a
  // fan with a worse triangle may still trade a length for its quality).
  bool move_keeps_lmin = false;
  double keep_lmin_quality = 0.5;
};

// --- edge split (section 5.3) -------------------------------------------------
struct SplitPlan {
  Rejection why = Rejection::None;
  Placement at;            // the new vertex
  VertexKind kind = VertexKind::Free;
  bool projected = true;   // false: the projection was refused, the straight midpoint is used
  bool swap_instead = false;  // section 5.3 / figure 14: the edge is swapped, no vertex added
};
// New vertex at the projection of the midpoint, or of the point at k / n of
// the edge (split_in_unit_pieces), onto the surface (onto the feature curve
// for a feature edge). Refused when a new triangle would be inverted or turned
// too far with respect to the triangle it halves, at the projection and
// (when it is close to the surface: split_fallback_offset) at the straight
// midpoint. When both new edges to the opposite vertices would
// be shorter than lmin and the edge can be swapped (can_swap), the plan is
// that swap instead (section 5.3, figure 14).
SplitPlan can_split(AdaptedMesh& m, Corner c, const OperatorOptions& o);
// can_split of an edge no longer than lmax that sags off the surface
// (sags_off_input, section 5's fidelity): refused (NoGain) when the new
// vertex would stay within the sag tolerance of the edge (the projection
// refused and the fallback point on the chord: its halves would sag as
// much, and be split again).
SplitPlan can_split_for_sag(AdaptedMesh& m, Corner c, const OperatorOptions& o);
// The split that keeps T_1 within `bound` of the input (the --hausd bound,
// Remesher's final pass): the new vertex at the projection of the straight
// midpoint (within the input bound of T_G), else at T_G's own closest point,
// else half or a quarter of the way from the midpoint to it when that is
// within `bound` of T_G (left off the surface), with the normal filters of
// can_split widened to `max_turn_deg` (a triangle across a crease of the
// input turns to follow it), else (a free edge) the midpoint moved along the
// edge's normal all or half of the way to T_G when within `bound` of it;
// no swap instead. With `input_first`, T_G's closest point is tried before
// the surface point (where the smooth surface rounds what T_G keeps sharp).
SplitPlan can_split_onto_input(AdaptedMesh& m, Corner c, double max_turn_deg, double bound, bool input_first = false);
// Pre: can_split(...).why == None. Returns the new vertex (tagged kRidge on a
// ridge edge), or an invalid vertex when the plan was a swap.
Vertex split(AdaptedMesh& m, Corner c, const SplitPlan& plan);

// --- edge collapse (section 5.1) ----------------------------------------------
struct CollapsePlan {
  Rejection why = Rejection::None;
  Corner edge;        // the corner naming the edge with the removed vertex as edge_from
  Vertex removed, kept;
  Placement at;       // the kept vertex's new placement
  bool moves = false; // the kept vertex moves (to the projection of the midpoint)
};
// Chooses the removed vertex (section 5.1: never a fixed one, a curve vertex
// only along its curve, an interior one before a curve one; two similar ones:
// the kept one moves to the projection of the midpoint, else stays; an edge
// of metric length `length` below collapse_in_place_length tries the ends
// staying first), then checks the topology, the curve tangents, inversion
// and normals, the new edge lengths (<= lmax) and the quality. Tries the
// alternatives in turn and returns the first that passes, or the last
// refusal. `length` < 0: not known (the midpoint first).
CollapsePlan can_collapse(AdaptedMesh& m, Corner c, const OperatorOptions& o, double length = -1);
// Pre: plan.why == None. Returns the kept vertex.
Vertex collapse(AdaptedMesh& m, const CollapsePlan& plan);
// Vertex suppression (section 5.2): removes v by collapsing one of its edges
// (along its curve for a curve vertex), the shortest in the metric first;
// the other end stays. Same filters as can_collapse.
CollapsePlan can_remove_vertex(AdaptedMesh& m, Vertex v, const OperatorOptions& o);
// The final optimisation's repair of a poor fan (ours): removes v into a
// neighbour (the shortest edge first; along its curve for a curve vertex),
// which stays or, for ends alike, moves to the midpoint, when the worst
// quality of the new triangles exceeds `gain` times the worst of those they
// replace (a needle the features force counting as in can_collapse:
// OperatorOptions::strip_width). The other filters of can_collapse.
CollapsePlan can_collapse_for_quality(AdaptedMesh& m, Vertex v, const OperatorOptions& o, double gain);

// --- edge swap (section 5.4) --------------------------------------------------
struct SwapPlan {
  Rejection why = Rejection::None;
  // min c_K of the two triangles (in one metric each); refused for Quality,
  // quality_after may be the first new triangle's alone (it fails already).
  double quality_before = 0, quality_after = 0;
};
// Interior non-feature edges only; refused when a new triangle turns too far
// from the old pair or the pair folds more than before, or when the worst
// quality (eq. 17, each triangle's edges in the metric at its centroid:
// AdaptedMesh::quality_in_one_metric) does not improve, or when a new
// triangle with at most one free corner is inverted by the measure of
// AdaptedMesh::count_inverted (faces_surface; every operator checks it).
SwapPlan can_swap(AdaptedMesh& m, Corner c, const OperatorOptions& o);
// Pre: plan.why == None. Returns the corner of the new diagonal.
Corner swap(AdaptedMesh& m, Corner c);

// --- vertex move (section 5.5) ------------------------------------------------
struct MovePlan {
  Rejection why = Rejection::None;
  Placement at;
  double quality_before = 0, quality_after = 0;  // min c_K of the fan
  int tries = 0;
};
// Target p0 of eq. 19 (metric-weighted barycentre of the neighbours; of the
// two curve neighbours for a curve vertex), displacement omega (p0 - s)
// bounded by max_move times the shortest incident edge, projected onto the
// surface (the curve), halved until no triangle inverts, the worst quality
// is not lower than before (times move_quality_factor) and no incident edge
// grows beyond lmax (smoothing must not undo the splits).
MovePlan can_move(AdaptedMesh& m, Vertex v, const OperatorOptions& o);
// The final optimisation's worst-element relocation (ours): a free vertex
// on the surface moved where the worst quality of its fan is largest (a
// compass search in its tangent plane, the fan's metrics as they are) while
// the fan's summed quality does not fall (for a fan whose worst is below
// `trade_below`: falls by no more than the worst gains), then placed on the
// surface and checked as by can_move, no edge below lmin made shorter;
// refused (NoGain) unless the worst quality rises above `gain` times what
// it was. A triangle whose vertices' metrics differ by more than 5% (its
// lengths depend on how they are read between the vertices: a jump of the
// field) does not count in the worst and the sum but may not get worse,
// v's metric read where it lands (else Quality). Fixed for a vertex that
// is not free or not on the surface.
MovePlan can_move_for_worst(AdaptedMesh& m, Vertex v, const OperatorOptions& o, double gain, double trade_below);
// Pre: plan.why == None.
void move(AdaptedMesh& m, Vertex v, const MovePlan& plan);

// Corner naming the edge a-b (either direction), or invalid.
Corner find_edge_corner(const SurfaceMesh& mesh, Vertex a, Vertex b);

// Section 5's fidelity test of a segment a-b of T_1 (an edge, or one an
// operator would create): true when its midpoint lies farther from the
// surface (the point a vertex there would take: AdaptedMesh::place, within
// the input bound) than OperatorOptions::surface_sag allows. `na`, `nb`: the surface
// normals at the ends (zero on features), a cheap bound first; `curve`: the
// segment runs along a feature curve (its midpoint is projected onto it).
// The sag a segment a-b of T_1 may have (OperatorOptions::surface_sag times
// the size along it, at most surface_max_sag; infinite without a sag test).
double sag_tolerance(const AdaptedMesh& m, const Vec3& pa, const SymTensor3& Ma, const Vec3& pb, const SymTensor3& Mb,
                     const OperatorOptions& o);
bool sags_off_input(AdaptedMesh& m, const Vec3& pa, const SymTensor3& Ma, const Vec3& na, Vertex a, const Vec3& pb,
                    const SymTensor3& Mb, const Vec3& nb, Vertex b, bool curve, const OperatorOptions& o);
// The same for the edge a-b of T_1 as it is.
bool edge_sags_off_input(AdaptedMesh& m, Vertex a, Vertex b, const OperatorOptions& o);
// ... with `curve` known (the edge lies on a feature curve).
bool edge_sags_off_input(AdaptedMesh& m, Vertex a, Vertex b, bool curve, const OperatorOptions& o);

}  // namespace anisurf::remesh
