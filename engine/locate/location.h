// The result of locating a point on a reference mesh (report section 4: the
// element containing the projection and its barycentric coordinates), the hint
// that starts the next search there (section 4.3), and the constraint a query
// carries (section 4.2: boundary and feature points project onto boundary and
// feature curves only).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "core/vec3.h"
#include "mesh/surface_mesh.h"

namespace anisurf {

// Where a query point may land.
enum class Constraint : std::uint8_t {
  Free,       // anywhere on the surface
  OnFeature,  // on a feature curve: edges tagged with LocateOptions::feature_tags
  Fixed,      // on a corner vertex: vertices tagged with LocateOptions::corner_tags
};

// A starting element for a local search: the triangle of a previous result
// (e.g. kept per vertex of the mesh being adapted, one per reference mesh).
struct Hint {
  Triangle triangle;
  bool is_valid() const { return triangle.is_valid(); }
};

struct Location {
  Triangle triangle;                // triangle holding the closest point (invalid: empty mesh)
  std::array<double, 3> bary{};     // barycentric coordinates w.r.t. vertex(triangle, 0..2)
  Vec3 point;                       // closest point on the polyhedral mesh
  double distance = INFINITY;       // |query - point|
  int steps = 0;                    // moves of the local walk / descent
  bool used_fallback = false;       // the global tree search was consulted
  Constraint constraint = Constraint::Free;  // the constraint applied (weaker than asked
                                             // when the mesh has no feature or corner)
  Corner edge;                      // OnFeature: corner of `triangle` opposite the feature edge
  Vertex vertex;                    // Fixed: the corner vertex

  bool is_valid() const { return triangle.is_valid(); }
  Hint hint() const { return Hint{triangle}; }
};

}  // namespace anisurf
