// T_1, the mesh being adapted (report section 6), tied to T_G and T_0.
//
// Each vertex of T_1 carries, in property arrays: its metric (interpolated in
// T_0 at its location there; stored as PackedMetric, or one double where every
// metric is isotropic), one hint per reference mesh (the triangle of its
// last location in T_G and in T_0: "three pointers to triangles", section 6)
// and the solution values of T_0's fields. place() computes all of it for a
// candidate position (projection onto the geometry, location in T_0), and
// commit() is the one hook that writes it to a vertex after an operator
// created or moved it.
#pragma once
#include <array>
#include <atomic>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/packed_normal.h"
#include "metric/packed_metric.h"
#include "remesh/reference.h"

namespace anisurf::remesh {

// Everything a vertex of T_1 takes from T_G and T_0 at one position.
struct Placement {
  Vec3 position;
  Vec3 normal;  // unit surface normal at the position; zero for curve and fixed vertices (ambiguous)
  Hint hint_g, hint_0;
  ControlValues values;
  double distance = 0;  // from the requested point to the surface
  bool on_surface = true;  // false: kept off the surface (section 5.3's unprojected midpoint)
  bool pulled = false;     // the surface point was farther from T_G than the bound: pulled back (InputBound)
  Vec3 on_input;           // the closest point of the polyhedral T_G (the location's point)
};

// How far from the input T_G the smooth surface may put a vertex. The G1
// surface of section 3 follows T_G's own curvature: across a triangle whose
// edges turn by theta (dihedral angle, or the turn of a feature curve at a
// regular vertex), a smooth surface through its vertices lies about
// |e| theta / 8 off it at the edge's midpoint (the sagitta of a circle), 4/3
// of that at the triangle's centre. (theta, the angle between the facets'
// normals, is about 1/sqrt 3 of the angle an edge subtends on an evenly
// tessellated sphere: the G1 surface of a coarse sphere is pulled about
// halfway back towards its facets; `enabled` false keeps it whole, as the
// report's section 7.2 reconstruction wants.) Where the surface goes
// farther (tangents estimated from features narrower than the triangles,
// slivers, blends of strips), the point is pulled back towards T_G to
//   tolerance = max(size_fraction h, natural_factor x that sagitta),
// h the metric's size at the point (sqrt(3 / trace M): the size of an
// isotropic metric, between the smallest and sqrt 3 times it), and at most
// hausd_fraction x hausd when a chordal deviation is asked for.
struct InputBound {
  bool enabled = true;
  double size_fraction = 0.05;
  double natural_factor = 1.0;
  double hausd = 0;  // 0: none
  double hausd_fraction = 0.2;
};

// How a vertex of T_1 may move (report sections 5.1 and 5.5).
enum class VertexKind {
  Free,   // interior of a smooth region: anywhere on the surface
  Curve,  // on exactly two feature edges: along its curve only
  Fixed,  // corner, required, or on one or more than two feature edges
};

// The vertex property of T_1 (mesh()) that records how each vertex was
// placed: 0 left off the surface (a split at the straight midpoint, or the
// final pass's hausd split part of the way to T_G), 1 on the surface, 2 pulled
// back towards T_G (InputBound). Copies of mesh() carry it.
inline constexpr const char* kPlacementProperty = "remesh:on_surface";
// The vertex properties of T_1's metric: full tensors, or the lambda of
// lambda I where every metric is isotropic (AdaptedMesh::metric).
inline constexpr const char* kMetricProperty = "remesh:metric";
inline constexpr const char* kIsotropicMetricProperty = "remesh:metric_iso";
// True when the mesh's metric is stored as kIsotropicMetricProperty.
bool stores_isotropic_metric(const SurfaceMesh& mesh);
// Turns a mesh's kIsotropicMetricProperty into kMetricProperty (full
// tensors); nothing without it.
void widen_metric_property(SurfaceMesh& mesh);

class AdaptedMesh {
 public:
  // T_1 starts as `initial` (usually a copy of T_0). Every vertex is located
  // in T_G and T_0 (section 4.3, by propagation) and takes its metric and
  // solution values there. Positions are kept, or with `project_initial`
  // (T_G is another mesh than T_0) moved onto the geometry, fixed vertices
  // excepted. Pre: `initial` carries its feature tags (those of T_G when it
  // is a copy).
  AdaptedMesh(SurfaceMesh initial, GeometrySurface& geometry, ControlSpace& control,
              LengthFormula length = LengthFormula::LinearMetric, bool project_initial = false,
              const InputBound& bound = {});

  // A region of `whole` cut out for another thread (remesh/partition.h):
  // `part` carries the remesh:* vertex properties and the fields of the
  // vertices it was cut from, so nothing is located again; `geometry` and
  // `control` are that thread's copies (copy_for_thread) of whole's. The
  // per-triangle data of T_G is shared with `whole`, which must outlive it.
  AdaptedMesh(SurfaceMesh part, const AdaptedMesh& whole, GeometrySurface& geometry, ControlSpace& control);

  SurfaceMesh& mesh() { return mesh_; }
  const SurfaceMesh& mesh() const { return mesh_; }
  GeometrySurface& geometry() { return geometry_; }
  ControlSpace& control() { return control_; }

  // The projection of x onto the surface under `kind`'s constraint, searched
  // from the hints of the vertices `near` (in T_G and T_0), with the metric
  // and solution of T_0 there. Fixed vertices are not projected.
  Placement place(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near);
  Placement place(const Vec3& x, VertexKind kind, std::span<const Vertex> near);
  // place(x, kind, near).position alone: T_0's values at the point are
  // looked up only when the pull towards the input (InputBound) may act
  // there (the point farther from the input than the least tolerance the
  // input triangle allows), which most points of a smooth surface are not.
  Vec3 placed_position(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near);
  // norm(placed_position(x, kind, near) - x) <= tol; on a polyhedral
  // surface a free point's place is the input's closest point, and the search
  // stops at the first triangle clearly within tol (Locator::within). On the
  // G1 surface a free point is also within tol where a surface point at the
  // location of the first triangle found within tol is (the surface's
  // deviation bound from that triangle tells, else the surface evaluated
  // there); true wherever the placed point is within tol, never beyond tol
  // of the input.
  bool placed_within(const Vec3& x, VertexKind kind, std::initializer_list<Vertex> near, double tol);
  // The placement of v as it is now (no search).
  Placement current(Vertex v) const;
  // The placement of vertex v at x when T_G's vertex of the same id lies
  // exactly at x (T_1 starts as a copy of T_G): located there, no search.
  // Empty otherwise.
  std::optional<Placement> place_at_input_vertex(Vertex v, const Vec3& x, VertexKind kind);
  // The data-transfer hook: v takes the placement (position, hints, metric,
  // solution values). Called after every split (new vertex), collapse (kept
  // vertex, when it moves) and move.
  void commit(Vertex v, const Placement& p);

  // Every vertex takes again the values of T_0 at its position (after the
  // control space changed its metric: Remark 6). Positions are kept.
  void refresh_values();

  // The metric of v (T_0's, interpolated where v lies: section 6). Where T_0's
  // metric is isotropic (eq. 3) at every vertex (ControlSpace::
  // is_isotropic), T_1 stores the lambda of lambda I (8 bytes a vertex
  // instead of 24) and turns to full tensors at the first metric that is
  // not (a relaxation stage, Remark 6).
  SymTensor3 metric(Vertex v) const { return iso_ ? SymTensor3::identity(metric_iso_[v]) : metric_[v].unpack(); }
  bool stores_isotropic_metric() const { return iso_; }
  // From now on full tensors (kMetricProperty) hold the metric.
  void store_full_metric();
  // Unit surface normal at v's location (zero on feature curves and corners).
  Vec3 surface_normal(Vertex v) const {
    return unpack_normal(normal_[v]);
  }
  // The hint of v's location on T_G.
  const Hint& hint_g(Vertex v) const { return hint_g_[v]; }
  // True if the triangle of T_G of hint h has a vertex on a feature curve,
  // or shares a vertex with a triangle turned more than 60 degrees from it
  // (a fold of a defective input), or has a vertex with another sheet of the
  // surface within a quarter of its edges' length, or if h has no triangle:
  // where the surface turns fast or comes back nearby.
  bool near_feature(const Hint& h) const;
  // False for a vertex left off the surface (a split at the straight
  // midpoint); the next move of the vertex projects it.
  bool on_surface(Vertex v) const { return on_surface_[v] != 0; }
  // True where the last placement of v pulled the surface point back
  // towards T_G (InputBound): where the smooth surface and the input differ.
  bool pulled_to_input(Vertex v) const { return on_surface_[v] == 2; }
  // Distance from x to the polyhedral T_G (its closest point, searched from
  // the hints of the vertices `near`): what the output's distance to the
  // input is measured with; and the natural deviation of the smooth surface
  // from T_G there (InputBound: natural_factor x the sagitta of the closest
  // point's triangle; 0 when the bound is off or unknown).
  struct InputDistance {
    double distance = 0;
    double natural = 0;
  };
  InputDistance distance_to_input(const Vec3& x, std::initializer_list<Vertex> near);
  // An upper bound of x's distance to T_G without a search: the distance to
  // the nearest of the triangles hinting the vertices `near` (INFINITY
  // without a hint).
  double distance_to_hinted_input(const Vec3& x, std::initializer_list<Vertex> near) const;
  // The largest distance the bound allows from T_G at a point of T_G's
  // triangle `t` where the metric is M (InputBound).
  double input_tolerance(Triangle t, const SymTensor3& M) const;
  const InputBound& input_bound() const { return bound_; }
  VertexKind kind(Vertex v) const;
  Constraint constraint(VertexKind k) const;

  // Edge length in the metric between two positions with their metrics
  // (eq. 6, or eq. 7 with LengthFormula::LinearSize).
  double length(const Vec3& a, const SymTensor3& Ma, const Vec3& b, const SymTensor3& Mb) const {
    return edge_length(Ma, Mb, b - a, length_);
  }
  double length(Vertex a, Vertex b) const {
    if (iso_) return isotropic_length(a, b);
    return length(mesh_.position(a), metric_[a].unpack(), mesh_.position(b), metric_[b].unpack());
  }
  // Quality c_K (eq. 17) with edge lengths from the vertex metrics.
  double quality(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M) const;
  double quality(Triangle t) const;
  // c_K (eq. 17) with the three edges measured in one metric, the vertex
  // metrics interpolated at the centroid: the lengths of a real triangle, so
  // a shape measure even where the metric varies a lot between the vertices
  // (a coarse triangle across a thin anisotropic band). There, lengths taken
  // from different metrics per edge can break the triangle inequality (c_K 0
  // for a well-shaped triangle) or satisfy it comfortably for three nearly
  // collinear points (a good c_K for a needle); where the metric varies
  // little both measures agree. The criterion of the swaps.
  double quality_in_one_metric(const std::array<Vec3, 3>& p, const std::array<SymTensor3, 3>& M) const;
  double quality_in_one_metric(Triangle t) const;
  LengthFormula length_formula() const { return length_; }

  // Triangles of T_1 whose normal points against the surface normal near
  // most of their free corners (points 1/10 of the way to the centroid,
  // located on T_G from the vertex hints), or at the centroid for a triangle
  // without a free corner (by the sheet it faces when the centroid lies
  // between two sheets of a thin part, the tip of a wing: either orientation
  // faces one of them). O(n); for tests and reports.
  int count_inverted();
  // The test of count_inverted() for one triangle.
  bool is_inverted(Triangle t);
  // The same test for a triangle (p0, p1, p2) not in the mesh (yet): its
  // corners free where `free` (VertexKind::Free), with their hints on T_G
  // (the corner 0's for the centroid); true when it faces the surface (not
  // inverted). The operators check some new triangles with it.
  bool faces_surface(const std::array<Vec3, 3>& p, const std::array<bool, 3>& free, const std::array<Hint, 3>& hints);
  // The same two searching the surface g (a copy for another thread).
  bool is_inverted(Triangle t, GeometrySurface& g);
  bool faces_surface(const std::array<Vec3, 3>& p, const std::array<bool, 3>& free, const std::array<Hint, 3>& hints,
                     GeometrySurface& g);

 private:
  SurfaceMesh mesh_;
  GeometrySurface& geometry_;
  ControlSpace& control_;
  LengthFormula length_;
  Property<PackedMetric> metric_;  // full tensors (iso_ false), 24 bytes a vertex
  Property<double> metric_iso_;   // lambda of lambda I (iso_ true)
  bool iso_ = false;
  // The constructor's parallel commits: a metric that is not isotropic is
  // not stored but noted, and the commits run again with full tensors.
  bool committing_in_parallel_ = false;
  std::atomic<bool> lost_isotropy_{false};
  void set_metric(Vertex v, const SymTensor3& M);
  // edge_length for isotropic metrics: sqrt(lambda) |e| at each end.
  double isotropic_length(Vertex a, Vertex b) const;
  Property<PackedNormal> normal_;  // an angle reference: 4 bytes a vertex (within 1e-4 radian)
  Property<std::uint8_t> on_surface_;  // 0 off the surface, 1 on it, 2 pulled towards T_G
  Property<Hint> hint_g_;
  Property<Hint> hint_0_;  // none when T_0 is T_G (the hint on T_G is the one)
  Hint hint_0(Vertex v) const { return hint_0_ ? hint_0_[v] : hint_g_[v]; }
  std::vector<Property<FieldValue>> solution_;
  // Per triangle slot of T_G (shared with the regions cut for threads):
  std::shared_ptr<const std::vector<std::uint8_t>> rough_;  // near_feature()
  void mark_rough_triangles();
  InputBound bound_;
  std::shared_ptr<const std::vector<float>> sagitta_;  // the natural deviation of InputBound
  void measure_sagitta();
  // Handles of the remesh:* properties and of the solution fields of mesh_.
  void bind_properties();
  void pull_towards_input(Placement& p, const Location& on_geometry) const;
  // The projection of place(): the hints of `near` in T_G (hg, n of them)
  // and T_0 (h0).
  Projection project_from(const Vec3& x, VertexKind kind, std::span<const Vertex> near, std::array<Hint, 8>& h0,
                          std::size_t& n);
  // The hints of `near` that have one in T_G (into hg) and their hints in
  // T_0 (into h0, when given); returns how many.
  std::size_t hints_of(std::span<const Vertex> near, std::array<Hint, 8>& hg, std::array<Hint, 8>* h0) const;
  // The values of place() at the projection pr of x (hints h0, n of them).
  Placement placement_at(const Vec3& x, VertexKind kind, const Projection& pr, const std::array<Hint, 8>& h0,
                         std::size_t n);
  // placement_at(...).position, T_0 looked up only when the pull may act
  // (placed_position once projected).
  Vec3 position_placed_at(const Vec3& x, VertexKind kind, const Projection& pr, const std::array<Hint, 8>& h0,
                          std::size_t n);
  // A lower bound of input_tolerance(t, M) over every M.
  double least_input_tolerance(Triangle t) const;
};

}  // namespace anisurf::remesh
