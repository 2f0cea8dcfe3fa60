// Projection of points onto a reference surface mesh (T_G or T_0): the local
// projection by neighbourhood descent with element marking (report section
// 4.2), its initialization by topological propagation (section 4.3), and a
// global bounding-box tree the report lacks, so that a projection never fails
// and never stops on the wrong sheet of a thin part.
//
// Exactness. The descent stops at a triangle K whose neighbourhood E(K) (the
// triangles sharing a vertex with K, all evaluated by then) holds nothing
// closer. Each vertex v carries its clearance rho(v), the distance from v to
// the nearest triangle not incident to v, computed once. Any triangle outside
// K and E(K) misses the vertices of K, so it lies at least rho(v) - |x - v|
// from the query x (triangle inequality): when |x - v| + d <= rho(v) for a
// vertex v of K, where d is the distance found, the local result is the
// global one ("certified"). Otherwise (a thin part, a point far from the
// surface, too many steps) the tree search continues from the local result
// as an upper bound, which keeps it short. Either way the result is the
// closest point of the whole mesh, up to floating-point rounding and ties.
// Feature curves are handled the same way with their edges.
#pragma once
#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "locate/aabb_tree.h"
#include "locate/location.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

struct TriangleClosest;  // locate/closest_point.h

struct LocateOptions {
  // Descent moves before the tree search takes over (a hint far away).
  int max_steps = 64;
  // Edge tags that make the feature curves (OnFeature queries).
  std::uint8_t feature_tags = kRidge | kBoundary | kRequired;
  // Vertex tags that make the fixed corners (Fixed queries).
  std::uint8_t corner_tags = kCorner;
};

// Locator over one reference mesh. The mesh must outlive the locator and stay
// unchanged (build a new locator after modifying it). Queries use scratch
// marks, so one locator serves one thread at a time; copies share the
// immutable search structures and have their own marks (one copy a thread).
class Locator {
 public:
  explicit Locator(const SurfaceMesh& mesh, const LocateOptions& options = {});
  Locator(const Locator& other);
  Locator& operator=(const Locator& other);
  Locator(Locator&&) noexcept;
  Locator& operator=(Locator&&) noexcept;
  ~Locator();

  // Closest point of the mesh to x under a constraint, by local descent from
  // the best of the hints (section 4.2; 4.3: "one of the elements pointed by
  // its vertices"; a free point is first walked towards across the edges),
  // certified or completed by the tree. Invalid or stale hints
  // are ignored; with none the tree answers directly. An OnFeature / Fixed
  // query on a mesh without feature edges / corners is answered as the next
  // weaker constraint (see Location::constraint).
  Location project(const Vec3& x, std::span<const Hint> hints = {}, Constraint constraint = Constraint::Free);
  // One hint (a template so that project(x, {}, c) picks the span overload).
  template <std::same_as<Hint> H>
  Location project(const Vec3& x, H hint, Constraint constraint = Constraint::Free) {
    return project(x, std::span<const Hint>(&hint, 1), constraint);
  }

  // Whether the mesh comes within tol of x: the answer of
  // norm(project(x, hints).point - x) <= tol, cut short by the first
  // triangle the descent finds clearly within tol.
  bool within(const Vec3& x, double tol, std::span<const Hint> hints = {});
  // The first triangle the descent finds within tol of x (a free location
  // closer than tol, not always the closest), or else the closest location,
  // as project() gives it.
  Location first_within(const Vec3& x, double tol, std::span<const Hint> hints = {});

  const SurfaceMesh& mesh() const;
  const LocateOptions& options() const;
  // Feature edges and fixed corners found in the mesh from the option tags.
  int n_feature_edges() const;
  int n_corners() const;
  // Clearance rho(v) of a vertex (see above, less a rounding margin; 0 where
  // a triangle not incident to v touches it, e.g. at a pinch point).
  double clearance(Vertex v) const;
  // The triangle tree (for callers that want their own searches).
  const AabbTree& tree() const;

 private:
  struct Data;
  // The free projection; returns the first triangle found at a squared
  // distance below accept2 (< 0: none is, the closest point).
  Location project_free(const Vec3& x, std::span<const Hint> hints, double accept2);
  Location project_feature(const Vec3& x, std::span<const Hint> hints);
  Location project_corner(const Vec3& x);
  Location free_result(const Vec3& x, int t, int steps, bool fallback) const;
  // The same from t's closest point to x, already found.
  Location free_result(const TriangleClosest& c, int t, int steps, bool fallback) const;
  Location feature_result(const Vec3& x, int e, int steps, bool fallback) const;
  void next_stamp();

  std::shared_ptr<const Data> d_;
  std::vector<std::uint32_t> tmark_;  // per triangle slot: stamp of the query that evaluated it
  std::vector<std::uint32_t> fmark_;  // per feature edge
  std::uint32_t stamp_ = 0;
};

// The constraint of a vertex of a mesh being adapted (T_1), from its tags:
// Fixed if it has one of corner_tags, OnFeature if an incident edge has one of
// feature_tags, else Free.
Constraint vertex_constraint(const SurfaceMesh& mesh, Vertex v, std::uint8_t feature_tags = kRidge | kBoundary | kRequired,
                             std::uint8_t corner_tags = kCorner);

struct PropagationStats {
  int projected = 0;       // vertices projected
  int seeds = 0;           // searches started without a neighbour's result (one per component of T_1)
  long long steps = 0;     // total descent moves
  int fallbacks = 0;       // results that needed the tree
  double mean_steps() const { return projected ? static_cast<double>(steps) / projected : 0.0; }
};

// Initialization by topological propagation (section 4.3): projects every live
// vertex of `mesh` (T_1) onto the locator's mesh, breadth-first from a seed per
// component, each vertex starting from its own hint and from the result of the
// neighbour that reached it. `hints` (one per vertex slot of `mesh`; resized
// if shorter) is read and overwritten with the results. With
// `use_constraints`, each vertex carries vertex_constraint() computed with the
// locator's option tags. Returns one Location per vertex slot (invalid for
// deleted slots).
std::vector<Location> project_vertices(const SurfaceMesh& mesh, Locator& locator, std::vector<Hint>& hints,
                                       bool use_constraints = true, PropagationStats* stats = nullptr);

}  // namespace anisurf
