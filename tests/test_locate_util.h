// Helpers of the point-location tests: random points near a mesh and the
// brute-force references (every triangle / every feature edge / every corner).
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "locate/closest_point.h"
#include "locate/location.h"
#include "mesh/surface_mesh.h"

namespace anisurf::test {

// Live triangles of a mesh.
inline std::vector<int> live_triangles(const SurfaceMesh& m) {
  std::vector<int> out;
  for (int t = 0; t < m.triangle_capacity(); ++t)
    if (!m.is_deleted(Triangle(t))) out.push_back(t);
  return out;
}

inline std::array<Vec3, 3> triangle_points(const SurfaceMesh& m, int t) {
  return {m.position(m.vertex(Triangle(t), 0)), m.position(m.vertex(Triangle(t), 1)),
          m.position(m.vertex(Triangle(t), 2))};
}

// A point near the mesh: uniform on a random triangle `source`, moved in a
// random direction by a length log-uniform in [lo, hi] times the bounding box
// diagonal (lo = hi = 0: on the surface).
struct NearPoint {
  Vec3 x;
  int source = -1;
};
inline NearPoint random_point_near(const SurfaceMesh& m, const std::vector<int>& tris, std::mt19937_64& rng,
                                   double lo, double hi) {
  std::uniform_int_distribution<std::size_t> pick(0, tris.size() - 1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss;
  NearPoint np;
  np.source = tris[pick(rng)];
  const auto p = triangle_points(m, np.source);
  double r1 = std::sqrt(u01(rng)), r2 = u01(rng);
  np.x = (1 - r1) * p[0] + r1 * (1 - r2) * p[1] + r1 * r2 * p[2];
  if (hi > 0) {
    const double diag = m.bbox().diagonal();
    const double len = diag * lo * std::pow(hi / lo, u01(rng));
    np.x += normalized(Vec3(gauss(rng), gauss(rng), gauss(rng))) * len;
  }
  return np;
}

// Smallest squared distance from x to a triangle of the mesh (O(N)).
inline double brute_force_d2(const SurfaceMesh& m, const std::vector<int>& tris, const Vec3& x) {
  double best = INFINITY;
  for (int t : tris) {
    const auto p = triangle_points(m, t);
    best = std::min(best, point_triangle_distance2(x, p[0], p[1], p[2]));
  }
  return best;
}

// Smallest squared distance from x to an edge carrying one of `tags`.
inline double brute_force_feature_d2(const SurfaceMesh& m, const Vec3& x, std::uint8_t tags) {
  double best = INFINITY;
  for (int c = 0; c < 3 * m.triangle_capacity(); ++c) {
    const Corner ch(c);
    if (m.is_deleted(SurfaceMesh::triangle(ch)) || !(m.edge_tags(ch) & tags)) continue;
    best = std::min(best, point_segment_distance2(x, m.position(m.edge_from(ch)), m.position(m.edge_to(ch))));
  }
  return best;
}

// Distances agree within `rel` relative (plus an absolute floor for points on
// the surface).
inline bool same_distance(double d, double ref, double diag, double rel = 1e-12) {
  return std::fabs(d - ref) <= rel * ref + 1e-14 * diag;
}

// The location is consistent: its point is the barycentric combination of its
// triangle's vertices and lies at `distance` from x.
inline bool consistent(const SurfaceMesh& m, const Location& loc, const Vec3& x) {
  if (!loc.is_valid() || m.is_deleted(loc.triangle)) return false;
  const auto p = triangle_points(m, loc.triangle.idx);
  const Vec3 q = loc.bary[0] * p[0] + loc.bary[1] * p[1] + loc.bary[2] * p[2];
  const double scale = std::max({norm(p[0]), norm(p[1]), norm(p[2]), 1e-300});
  double sum = 0;
  for (double b : loc.bary) {
    if (b < -1e-14 || b > 1 + 1e-14) return false;
    sum += b;
  }
  return std::fabs(sum - 1) < 1e-12 && norm(q - loc.point) <= 1e-12 * scale &&
         std::fabs(norm(x - loc.point) - loc.distance) <= 1e-12 * (loc.distance + scale);
}

}  // namespace anisurf::test
