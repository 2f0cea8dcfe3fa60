// Helpers of the point-location tests: random points near a mesh and the
// brute-force references (every triangle / every feature edge / every corner).
#pragma once
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "locate/closest_point.h"
#include "locate/location.h"
#include "mesh/build.h"
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

// Points near a mesh: uniform on a random triangle (the `source`), moved in a
// random direction by a length log-uniform in [lo, hi] times the bounding box
// diagonal (lo = hi = 0: on the surface).
struct NearPoint {
  Vec3 x;
  int source = -1;
};
class PointSampler {
 public:
  explicit PointSampler(const SurfaceMesh& m) : m_(m), tris_(live_triangles(m)), diag_(m.bbox().diagonal()) {}
  NearPoint operator()(std::mt19937_64& rng, double lo, double hi) const {
    std::uniform_int_distribution<std::size_t> pick(0, tris_.size() - 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> gauss;
    NearPoint np;
    np.source = tris_[pick(rng)];
    const auto p = triangle_points(m_, np.source);
    const double r1 = std::sqrt(u01(rng)), r2 = u01(rng);
    np.x = (1 - r1) * p[0] + r1 * (1 - r2) * p[1] + r1 * r2 * p[2];
    if (hi > 0) {
      const double len = diag_ * lo * std::pow(hi / lo, u01(rng));
      np.x += normalized(Vec3(gauss(rng), gauss(rng), gauss(rng))) * len;
    }
    return np;
  }
  const std::vector<int>& triangles() const { return tris_; }
  double diagonal() const { return diag_; }

 private:
  const SurfaceMesh& m_;
  std::vector<int> tris_;
  double diag_;
};

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

namespace anisurf::test {

// Closed surface of the box [0, sx] x [0, sy] x [0, sz], each face a grid of
// n? cells along each axis split into triangles (orientation left to build_mesh).
inline SurfaceMesh box_surface(Vec3 size, int nx, int ny, int nz) {
  MeshData d;
  std::map<std::array<int, 3>, int> id;
  const int n[3] = {nx, ny, nz};
  auto vertex = [&](std::array<int, 3> ijk) {
    auto it = id.find(ijk);
    if (it != id.end()) return it->second;
    const int v = static_cast<int>(d.vertices.size());
    d.vertices.push_back({size.x * ijk[0] / nx, size.y * ijk[1] / ny, size.z * ijk[2] / nz});
    id.emplace(ijk, v);
    return v;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n[u]; ++i)
        for (int j = 0; j < n[w]; ++j) {
          auto at = [&](int a, int b) {
            std::array<int, 3> ijk{};
            ijk[axis] = side * n[axis];
            ijk[u] = a;
            ijk[w] = b;
            return vertex(ijk);
          };
          const int p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          d.triangles.push_back({p00, p10, p11});
          d.triangles.push_back({p00, p11, p01});
        }
  }
  SurfaceMesh m;
  build_mesh(d, m);
  return m;
}

// Connected component (through shared edges) of each triangle slot (-1 deleted).
inline std::vector<int> triangle_components(const SurfaceMesh& m, int* count = nullptr) {
  std::vector<int> comp(static_cast<std::size_t>(m.triangle_capacity()), -1);
  int nc = 0;
  for (int s = 0; s < m.triangle_capacity(); ++s) {
    if (m.is_deleted(Triangle(s)) || comp[s] >= 0) continue;
    std::vector<int> stack{s};
    comp[s] = nc;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Corner o = m.opposite(SurfaceMesh::corner(Triangle(t), k));
        if (!o.is_valid()) continue;
        const int u = SurfaceMesh::triangle(o).idx;
        if (comp[u] < 0) {
          comp[u] = nc;
          stack.push_back(u);
        }
      }
    }
    ++nc;
  }
  if (count) *count = nc;
  return comp;
}

}  // namespace anisurf::test
