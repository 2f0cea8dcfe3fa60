// The smooth surface of report section 3 ("C.A.D. reconstruction"): Farin's
// G1 Bezier surface over the mesh, generalized to feature curves.
//
// Per triangle:
//  1. a cubic patch from the vertex tangent planes: the edge control points
//     lie in the tangent plane of their vertex (proposition 1: G1 at the
//     vertices); along a feature curve they come from the curve tangents and
//     are shared by both sides (so positions agree exactly);
//  2. the centre control point by the report's formula (quadratic precision);
//  3. the Clough-Tocher split at the barycentre into three cubic subpatches
//     and their degree elevation to quartics: 31 control points;
//  4. G1 corrections across every interior non-feature edge: the two rows of
//     control points next to the edge are set so that both cross-boundary
//     derivatives lie in span{W(t), Gamma'(t)}, W linear in the common
//     tangent planes of the end vertices (the conditions of proposition 2,
//     eq. 11-13, with a linear combination instead of a constant alpha, since
//     eq. 14 does not hold for arbitrary tangent planes), then the inner
//     control points of the split are recomputed from the Clough-Tocher C1
//     conditions so that each macro patch stays C1 inside.
// Across feature edges the surface is C0, each side with its own tangent
// plane.
#pragma once
#include <array>
#include <vector>

#include "geometry/normals.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

// Barycentric coordinates with respect to the triangle's vertices 0, 1, 2.
using Bary = std::array<double, 3>;

struct BezierOptions {
  // Length of the edge control points' offset from their vertex, along the
  // projection of the edge onto the vertex's tangent plane (or along the
  // curve tangent on features):
  //  Projection: the projection of the 1/3 point (|e| cos(phi) / 3);
  //  Circular: |e| / (3 cos^2(phi/2)), exact for circular arcs (phi: angle of
  //  the edge with the tangent plane or the curve tangent).
  enum class Handle { Projection, Circular };
  Handle handle = Handle::Circular;
  // false: no G1 corrections (the plain cubic patch, only G1 at vertices).
  bool g1_corrections = true;
  // The free inner control point of each subpatch (28 + k) moves by this
  // weight times the sum of the corrections of its two points next to the
  // macro edge (0: only the C1 conditions move the inner points). Measured on
  // hemi.mesh: 3.1e-4 (0), 2.2e-4 (0.5), 1.7e-4 (1); 1 also lowers the
  // coarsest icosphere's error 20x, but the closest-point test of locate/
  // (first-order optimality to 1e-8 on sphere20k) then misses 2 of 500
  // points: 0.5 until that is understood.
  double inner_correction_weight = 0.5;
};

// Position, first derivatives and unit normal at a point of a triangle.
struct SurfacePoint {
  Vec3 position;
  // Derivatives along the parameter directions v1 - v0 (d1) and v2 - v0 (d2),
  // i.e. with respect to barycentric coordinates 1 and 2 (coordinate 0 being
  // 1 - b1 - b2).
  Vec3 d1, d2;
  Vec3 normal;  // unit, d1 x d2 normalized (oriented like the triangle)
};

class BezierSurface {
 public:
  static constexpr int kControlPoints = 31;
  using Patch = std::array<Vec3, kControlPoints>;

  BezierSurface() = default;
  // Builds the surface over `mesh` (features tagged, frames computed on the
  // same mesh). The surface keeps no reference to the mesh.
  BezierSurface(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options = {});

  // Point of triangle t at barycentric coordinates b (pre: b sums to 1; values
  // outside [0,1] extrapolate the subpatch that contains them).
  Vec3 position(Triangle t, const Bary& b) const;
  SurfacePoint evaluate(Triangle t, const Bary& b) const;
  // The same on the control points of a patch (patch(t)).
  static SurfacePoint evaluate(const Patch& P, const Bary& b);

  // The 31 control points of triangle t (section 3, steps 3-4; zero for a
  // deleted triangle). Layout: 0-2 the vertices, 3 the centre, 4 + 3k + m the
  // quartic points of the edge opposite vertex k (from vertex k+1), 13 + 3j + m
  // the points of the inner edge from vertex j to the centre, 22 + 2k + {0,1}
  // and 28 + k the inner points of subtriangle k (vertices k+1, k+2, centre).
  // Assembled from the stored data (see below), bitwise as built.
  Patch patch(Triangle t) const;
  // A bound of |S(b) - F(b)| over triangle t, F the flat triangle with
  // corners `corners` (t's vertices, in t's order): the largest distance of a
  // control point from its domain point on F (each subpatch and its flat part
  // are Bezier triangles of the same degree over the same parameters, and a
  // Bezier point is a convex combination of its control points), plus the
  // rounding of an evaluation.
  double flat_deviation(Triangle t, const std::array<Vec3, 3>& corners) const;
  // Number of triangle slots covered (the mesh's triangle capacity).
  int size() const { return static_cast<int>(macro_.size()); }

  // Storage: what the 31 points are made of, each stored once.
  //  - the vertices, per vertex slot;
  //  - the two cubic control points of every edge (step 1), shared by both
  //    sides: the macro edge's quartic points follow by degree elevation;
  //  - the first point of each inner edge (13 + 3j) follows from the cubic
  //    (the G1 corrections leave it);
  //  - per triangle the 9 points the G1 corrections set (step 4: the two
  //    points next to each macro edge and the free inner points, 22-30);
  //  - the centre and the other 6 inner-edge points (3, 13 + 3j + {1, 2})
  //    follow from the Clough-Tocher C1 conditions on a corrected triangle,
  //    and are stored (`derived_`) only on the others.
  static constexpr int kStoredPoints = 9;
  static constexpr int kDerivedPoints = 7;

 private:
  struct Macro {
    int vertex[3] = {-1, -1, -1};  // -1: deleted triangle
    int edge[3] = {0, 0, 0};       // edge of the side opposite vertex k; ~id when seen against its direction
    int derived = -1;              // index into derived_, -1: the C1 conditions give them
  };
  void index_mesh(const SurfaceMesh& mesh);
  void build_edges(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options);
  void edge_cubic(const Macro& m, int k, Vec3& p1, Vec3& p2) const;
  void fill_shared(const Macro& m, Patch& P) const;
  void cubic_net(const Macro& m, const Patch& P, Vec3 b[10]) const;
  Patch elevated_patch(int t) const;
  std::vector<char> correct_g1(const SurfaceMesh& mesh, const SurfaceFrames& frames, const BezierOptions& options);

  std::vector<Vec3> vertex_;
  std::vector<std::array<Vec3, 2>> edge_;  // next to the edge's from / to vertex (its canonical corner)
  std::vector<Macro> macro_;
  std::vector<std::array<Vec3, kStoredPoints>> stored_;
  std::vector<std::array<Vec3, kDerivedPoints>> derived_;
};

}  // namespace anisurf
