// Meshes made in the tests of the geometry module: icospheres, grids, cubes,
// and the measures the tests share (distance to the unit sphere, the angle of
// two normals).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "geometry/bezier_surface.h"
#include "mesh/build.h"
#include "mesh/surface_mesh.h"

namespace anisurf::test {

// Icosahedron subdivided `levels` times (each triangle into 4), vertices
// projected onto the unit sphere: 20 * 4^levels triangles.
inline MeshData icosphere(int levels) {
  MeshData d;
  const double p = (1 + std::sqrt(5.0)) / 2;
  const double v[12][3] = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                           {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  for (auto& q : v) d.vertices.push_back(normalized(Vec3(q[0], q[1], q[2])));
  d.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      d.vertices.push_back(normalized(d.vertices[a] + d.vertices[b]));
      return mid[key] = static_cast<int>(d.vertices.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : d.triangles) {
      const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    d.triangles.swap(next);
  }
  return d;
}

// icosphere(levels) with each vertex moved along its radius by a factor
// drawn uniformly from [lo, hi] (std::mt19937 seeded with `seed`).
inline MeshData jittered_icosphere(int levels, double lo, double hi, unsigned seed) {
  MeshData d = icosphere(levels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> factor(lo, hi);
  for (Vec3& p : d.vertices) p = factor(rng) * p;
  return d;
}

// n x n grid of the unit square in the plane z = 0, counter-clockwise from +z.
inline MeshData square_grid(int n) {
  MeshData d;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) d.vertices.push_back({double(i) / n, double(j) / n, 0});
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      d.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      d.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return d;
}

// Unit cube [0,1]^3, two triangles per face, outward orientation.
inline MeshData cube() {
  MeshData d;
  for (int k = 0; k < 8; ++k) d.vertices.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) {
    d.triangles.push_back({q[0], q[1], q[2]});
    d.triangles.push_back({q[0], q[2], q[3]});
  }
  return d;
}

inline SurfaceMesh build(const MeshData& d) {
  SurfaceMesh m;
  build_mesh(d, m);
  return m;
}

// Angle in radians between two vectors.
inline double angle(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// Largest | |p| - 1 | over the points of a k-grid on every triangle.
inline double max_sphere_distance(const SurfaceMesh& mesh, const BezierSurface& s, int k) {
  double mx = 0;
  for (int t = 0; t < mesh.triangle_capacity(); ++t) {
    if (mesh.is_deleted(Triangle(t))) continue;
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i + j <= k; ++i)
        mx = std::fmax(mx, std::fabs(norm(s.position(Triangle(t), {double(k - i - j) / k, double(i) / k, double(j) / k})) - 1));
  }
  return mx;
}

// The mesh rebuilt from its positions and triangles by build_mesh, which
// links every pair of twin edges (triangles added one by one in any order
// can leave fans in pieces, their edges open: the curvature metric treats
// open edges as boundaries, feature curves its fits do not cross).
inline SurfaceMesh rebuilt(const SurfaceMesh& m) {
  MeshData d;
  for (int i = 0; i < m.vertex_capacity(); ++i) d.vertices.push_back(m.position(Vertex(i)));
  for (Triangle t : m.triangles()) {
    const int* v = m.triangle_vertices(t);
    d.triangles.push_back({v[0], v[1], v[2]});
  }
  SurfaceMesh out;
  build_mesh(d, out);
  return out;
}

}  // namespace anisurf::test
