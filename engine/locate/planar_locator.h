// Point location in a planar mesh (dimension 2, or a surface lying in z = 0)
// by the walk on oriented areas of report section 4.1, with the report's fix
// for non-convex domains, and the bounding-box tree as a safety net.
//
// The walk: in triangle K, the three triangles formed by x and the oriented
// edges of K give the signs; all non-negative: x is in K; otherwise cross the
// edge of the most negative one. If that edge is a boundary edge, x is
// projected onto K (distance d0 > 0) and the non-convex fix applies: the
// boundary edges at most d0 from x are found once (with a tree over the
// boundary edges instead of a loop over all of them; same set), and the walk
// restarts from the triangle of the closest edge not tried yet, whose
// projection becomes the best so far if closer, until x is found inside or no
// untried boundary edge is as close as the best projection. Ties restart too:
// behind a reflex boundary vertex the point may lie inside the domain with the
// edge on the other side of the vertex exactly as far.
//
// The safety net: a walk that cycles (possible on non-Delaunay meshes) or
// exceeds the step limit ends with the tree search; with verify_exterior, a
// point declared outside the domain is confirmed by a tree search bounded by
// the distance found (cheap: the ball holds nothing closer when the walk was
// right).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "locate/aabb_tree.h"
#include "locate/location.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

struct PlanarLocateOptions {
  int max_steps = 1 << 20;     // walk moves (all restarts together) before the tree takes over
  bool verify_exterior = true;  // confirm "outside the domain" results with the tree
};

class PlanarLocator {
 public:
  // Throws Error if a live vertex of the mesh has z != 0. The mesh must
  // outlive the locator and stay unchanged. Copies share the search
  // structures and have their own scratch marks (one copy a thread).
  explicit PlanarLocator(const SurfaceMesh& mesh, const PlanarLocateOptions& options = {});
  PlanarLocator(const PlanarLocator& other);
  PlanarLocator& operator=(const PlanarLocator& other);
  PlanarLocator(PlanarLocator&&) noexcept;
  PlanarLocator& operator=(PlanarLocator&&) noexcept;
  ~PlanarLocator();

  // True when every live vertex of the mesh has z == 0.
  static bool is_planar(const SurfaceMesh& mesh);

  // The triangle containing (x.x, x.y), or the closest point of the domain
  // when outside; distance in the plane (x.z is ignored). Walks from the hint;
  // without a valid hint the tree answers directly.
  Location locate(const Vec3& x, Hint hint = {});

  const SurfaceMesh& mesh() const;
  int n_boundary_edges() const;

 private:
  struct Data;
  enum class WalkEnd { Inside, Stopped, Failed };
  WalkEnd walk(const Vec3& x, int& K, int& steps, std::array<double, 3>& areas);
  Location tree_result(const Vec3& x, int start, double bound2, int steps);

  std::shared_ptr<const Data> d_;
  std::vector<std::uint32_t> wmark_;  // per triangle: stamp of the walk that entered it (cycles)
  std::vector<std::uint32_t> smark_;  // per triangle: stamp of the query that stopped or restarted there
  std::uint32_t wstamp_ = 0, sstamp_ = 0;
};

}  // namespace anisurf
