// Tangent planes of the surface at the mesh vertices, one per smooth sector
// (the triangles around a vertex between two feature edges; a vertex off the
// features has one sector, a ridge vertex one per side), and the tangents of
// the feature curves. These are the data of the report's section 3 ("surface
// tangent planes at the vertices are supposed to be known"): they decide most
// of the reconstruction error on coarse meshes.
#pragma once
#include <array>
#include <vector>

#include "mesh/surface_mesh.h"

namespace anisurf {

struct NormalOptions {
  enum class Method {
    AngleWeighted,  // sum of the sector's unit triangle normals weighted by their angle at the vertex
    LocalFit,       // height function fitted over the sector's 2-ring (see below)
  };
  Method method = Method::LocalFit;
  // LocalFit: least-squares height function z(x, y) through the vertex, in the
  // frame of the angle-weighted normal, on the vertices of the triangles
  // within two rings of the vertex reached without crossing a feature edge;
  // refitted `fit_iterations` times in the frame of the fitted normal (which
  // removes the bias of a tilted first frame, e.g. on boundaries). Degree 2
  // (a quadric), or degree 3 when the neighbourhood has at least
  // `cubic_min_points` points (0: never).
  int fit_iterations = 2;
  int cubic_min_points = 0;
  // Fall back to the angle-weighted normal when the fit is ill-posed (fewer
  // than 5 usable points, rank deficient) or turns the normal by more than
  // this angle.
  double max_fit_deviation_deg = 30.0;
  // Consistency after the estimate: the sector normals are turned (about the
  // curve tangent on a feature curve) so that every mesh edge makes equal
  // angles with the tangent planes at both ends, as on planes, spheres and
  // cylinders (a global least-squares problem, `mirror_iterations`
  // Gauss-Newton steps, 0: off); `mirror_anchor` weighs a pull back towards
  // the estimate. This mostly fixes one-sided neighbourhoods (boundaries),
  // where fits are biased.
  int mirror_iterations = 2;
  double mirror_anchor = 1e-3;
  // Each step's linear system is solved (conjugate gradient) to a residual
  // of mirror_tolerance x the first step's right-hand side. The second
  // step's right-hand side is a tenth to a fifth of the first's (the
  // Falcon: 0.17), so the steps leave a few percent of it: solving them
  // further changes nothing the steps keep (1e-6 took 175 iterations on
  // the Falcon, 1e-3 54, for the same deviations and bands).
  double mirror_tolerance = 1e-3;
  // The consistency turns a sector normal at most this far from its
  // estimate (the condition is exact only where the edges are short for the
  // curvature; on coarse scans it would turn normals by 30-60 degrees).
  double max_mirror_turn_deg = 10.0;
  // Use the file's NormalAtVertices (vertex properties "normal"/"has_normal")
  // at vertices with a single sector.
  bool use_file_normals = true;
  // The tangent of a feature curve at a regular vertex is the circle tangent
  // unless turning the edges that far would fold a thin triangle beside the
  // curve: then the turn is shared so that, in each such triangle, the
  // turned edge keeps at least tangent_room of its margin; when nothing fits
  // (a crest bending out of the surface beside slivers) the sector planes
  // turn about the circle tangent instead (unfold_margin_deg below).
  double tangent_room = 0.5;
  // The curve tangent before that check: where the two curve edges at the
  // vertex have comparable lengths (longer / shorter <= tangent_circle_ratio)
  // the circle through the vertex and its neighbours, exact on circles
  // sampled unevenly. Its turn off each edge is proportional to that edge's
  // length, so beside a much shorter edge it lies nearly along the short one
  // and the long edge's curve bulges by about its length x the turn / 4 (a
  // straight run meeting a finely sampled fillet, as CAD tessellations have
  // them). At ratios of tangent_even_ratio and more the turn off each edge
  // is inversely proportional to its length instead (both edges sag alike:
  // the long edge stays nearly straight); in between the two blend.
  double tangent_circle_ratio = 2.0;
  double tangent_even_ratio = 4.0;
  // A sector normal more than this angle away from one of its triangles'
  // normals (noisy fans: the patch would fold) is tilted towards them.
  double max_tilt_deg = 75.0;
  // On a regular curve vertex, a sector normal is turned about the curve
  // tangent when a thin triangle beside the curve would fold in its plane,
  // keeping each such triangle at least this angle away from folding.
  double unfold_margin_deg = 1.0;
  // At a corner, sectors joined by a feature edge along which their planes
  // differ by less than this angle share one plane (e.g. both sides of a
  // reference interface on a smooth surface).
  double corner_merge_angle_deg = 20.0;
  // At a corner, a curve end takes the line where its two sector planes meet
  // unless that line is more than this angle from the curve's own tangent
  // (step 1: the chord, or its regular neighbour's circle): then every curve
  // at the corner keeps its own tangent and the sector planes turn to
  // contain them.
  double corner_tangent_tolerance_deg = 15.0;
};

// Tangent planes per sector and feature-curve tangents, indexed by corner.
class SurfaceFrames {
 public:
  // Unit normal of the tangent plane at vertex(c) on the side of c's triangle.
  const Vec3& normal(Corner c) const {
    const int s = corner_sector_[c.idx];
    return s >= 0 ? sector_normal_[s] : kZero;
  }
  // Sector of c (corners of the same vertex between the same feature edges
  // share it); -1 for a deleted triangle.
  int sector(Corner c) const { return corner_sector_[c.idx]; }
  int n_sectors() const { return static_cast<int>(sector_normal_.size()); }
  const Vec3& sector_normal(int s) const { return sector_normal_[s]; }
  Vertex sector_vertex(int s) const { return sector_vertex_[s]; }
  // For a feature edge (the edge opposite e): unit tangent of its curve at
  // edge_from(e) pointing along the edge, and at edge_to(e) pointing back
  // along it. Zero for an edge that is not a feature.
  const Vec3& tangent_from(Corner e) const {
    const int i = tangent_slot_[e.idx];
    return i >= 0 ? tangent_[i][0] : kZero;
  }
  const Vec3& tangent_to(Corner e) const {
    const int i = tangent_slot_[e.idx];
    return i >= 0 ? tangent_[i][1] : kZero;
  }
  // How each sector normal was obtained (counts over sectors).
  int fitted = 0, angle_weighted = 0, from_file = 0, constrained = 0;
  int mirror_capped = 0;  // sectors whose consistency turn was capped (max_mirror_turn_deg)
  int tilted = 0;    // sectors tilted to see all their triangles
  int unfolded = 0;  // sectors turned about their curve tangent to unfold thin triangles

 private:
  friend SurfaceFrames compute_frames(const SurfaceMesh&, const NormalOptions&);
  // Tangent `end` (0: from, 1: to) of the feature edge opposite corner c.
  Vec3& tangent(int c, int end) { return tangent_[tangent_slot_[c]][end]; }

  static inline const Vec3 kZero{};
  // Normals per sector only (a corner's is its sector's), tangents only on
  // the feature edges: the frames are alive with the Bezier surface built
  // from them, at the peak memory of `adapt`.
  std::vector<int> corner_sector_;
  std::vector<Vec3> sector_normal_;
  std::vector<Vertex> sector_vertex_;
  std::vector<int> tangent_slot_;  // per corner slot: index into tangent_, -1 off the features
  std::vector<std::array<Vec3, 2>> tangent_;
};

// Computes the frames of `mesh` from its feature tags (run detect_features
// first). Pre: a valid mesh. Sector normals are oriented like the triangles
// (counter-clockwise seen from outside). On a regular curve vertex (two
// feature edges, not a corner) the curve tangent comes first (circle through
// the vertex and its two curve neighbours) and the sector planes contain it;
// at a corner the planes come first and each curve end takes the line where
// the planes of its two sectors meet. Either way every sector plane contains
// the tangents of its bounding curves, so that the control points around
// every vertex of a sector are coplanar (report, proposition 1).
SurfaceFrames compute_frames(const SurfaceMesh& mesh, const NormalOptions& options = {});

// Unit tangent of a feature curve at the middle vertex of three consecutive
// curve points a, v, b: the tangent at v of the circle through them (exact on
// circles for any spacing), oriented from a towards b.
Vec3 circle_tangent(const Vec3& a, const Vec3& v, const Vec3& b);

// Unit tangent of a feature curve at v between its neighbours a and b,
// oriented from a towards b: circle_tangent while the longer of the edges
// v-a, v-b is at most circle_ratio times the shorter; from even_ratio on,
// the turn between the edges shared in inverse proportion to their lengths
// (the deviation of the tangent from each edge times the edge's length is
// the same on both sides: the curve's sag stays bounded by the short edge's
// turn); a blend in between (NormalOptions::tangent_circle_ratio).
Vec3 curve_tangent(const Vec3& a, const Vec3& v, const Vec3& b, double circle_ratio, double even_ratio);

}  // namespace anisurf
