// Closest point on a smooth surface parameterised over the triangles of the
// reference mesh (the G1 surface of report section 3, evaluated at
// (triangle, barycentric coordinates)). The surface comes as a callback, so
// point location knows nothing of how it is built.
//
// Method: the polyhedral projection (Locator) gives the starting parameters;
// Gauss-Newton steps on |S(t, b) - x|^2 in the two free barycentric
// coordinates then move the parameter point, crossing into the neighbouring
// triangle when a step leaves the current one (the parameter domain is the
// whole mesh, continuous across edges), and stopping on a boundary edge.
// OnFeature queries minimise along the feature curve's edges (crossing at
// vertices where the curve goes on), Fixed ones keep the corner vertex (the
// surface interpolates the mesh vertices).
#pragma once
#include <array>
#include <functional>
#include <span>

#include "locate/locator.h"

namespace anisurf {

// A point of the parametric surface and its derivatives with respect to
// barycentric coordinates 1 and 2 (coordinate 0 being 1 - b1 - b2), i.e.
// along the parameter directions v1 - v0 and v2 - v0.
struct ParametricPoint {
  Vec3 position, d1, d2;
};
using SurfaceEvaluator = std::function<ParametricPoint(Triangle, const std::array<double, 3>&)>;

struct SurfaceProjectionOptions {
  int max_iterations = 50;
  // Converged when a step moves the parameters by less than this (in
  // barycentric units) or the gradient is this small relative to |S - x| |dS|.
  double tolerance = 1e-13;
};

struct SurfaceProjection {
  Location location;       // parameters (triangle, barycentric) of the point on the surface
  Vec3 point;              // S(location.triangle, location.bary)
  double distance = 0;     // |x - point|
  Location polyhedral;     // the starting projection onto the mesh
  int iterations = 0;
  bool converged = false;  // false: stopped by max_iterations (point still the best found)
};

// Closest point to x of the surface `eval` over the locator's mesh, from the
// hints, under a constraint (as Locator::project). A local minimiser near the
// polyhedral projection: the surface must stay close to its mesh (as a G1
// interpolant does).
SurfaceProjection project_onto_surface(Locator& locator, const SurfaceEvaluator& eval, const Vec3& x,
                                       std::span<const Hint> hints, Constraint constraint = Constraint::Free,
                                       const SurfaceProjectionOptions& options = {});

}  // namespace anisurf
